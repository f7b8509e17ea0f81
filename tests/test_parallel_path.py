"""The fast paths change speed, not physics.

- The parallel path (threads over blocks, fixed-order sum) follows the serial
  path's trajectory to round-off, and two parallel runs are bit-identical.
- The blocked particle sum with its plane culling (wrench.py) follows a plain
  loop over every particle with every plane (the handout-style baseline of
  scripts/bench_handout.py, an independent implementation) through contacts
  with the floor and a wall: a skipped contact would move the body by
  millimetres, round-off by micrometres.
- Blocks cover every particle once and their spheres contain their particles;
  the rotation gain bounds |R r| / |r| for matrices that are not rotations.
Speeds are measured by scripts/bench.py, never asserted here.
"""
import sys

import numpy as np
import pytest

from conftest import ASSETS, ROOT

# A 0.5 m cube volume-sampled at 18 cells: 5832 particles, 92 blocks. Thrown down and sideways
# from near the floor and the x = 1 wall: it hits both within the 6 frames.
CUBE = dict(mesh=str(ASSETS / "box.obj"), scale=0.5, particles="volume", grid=18)
THROW = dict(position=(0.7, -0.7, 0.0), initial_velocity=(3.0, -1.0, 1.0),
             initial_angular_velocity=(1.0, 3.0, 0.5))
FRAMES = 6


def _run(sim, parallel: bool) -> np.ndarray:
    sim.integrator.parallel = parallel
    assert sim.integrator.uses_parallel == parallel
    sim.reset()
    for _ in range(FRAMES):
        sim.step_frame()
    s = sim.state
    return np.concatenate([f.to_numpy()[0].ravel() for f in (s.x, s.q, s.P, s.L)]).astype(np.float64)


@pytest.fixture(scope="module")
def cube(sim_cache):
    sim = sim_cache(**CUBE, **THROW)
    yield sim
    sim.integrator.parallel = None


def test_parallel_path_follows_serial_and_is_bit_reproducible(cube):
    serial = _run(cube, parallel=False)
    parallel = _run(cube, parallel=True)
    again = _run(cube, parallel=True)
    p = serial[7:10]
    assert np.linalg.norm(p - cube.model.mass * np.array(THROW["initial_velocity"])) > 0.5 * cube.model.mass, \
        "the cube should have hit something"
    scale = np.abs(serial).max()
    np.testing.assert_allclose(parallel, serial, rtol=0, atol=2e-5 * scale)
    assert np.array_equal(parallel, again)


def test_blocked_sum_with_culling_matches_a_plain_particle_loop(cube, units):
    sys.path.insert(0, str(ROOT / "scripts"))
    from bench_handout import HandoutLoop

    engine = _run(cube, parallel=False)
    plain = HandoutLoop(cube.model.r0_np, cube.config.particle_mass, units, cube.config)
    for _ in range(FRAMES):
        plain.step_frame(cube.substeps)
    f = plain._fields
    reference = np.concatenate([f[k].to_numpy().ravel() for k in ("x", "q", "P", "L")]).astype(np.float64)
    np.testing.assert_allclose(engine[:3], reference[:3], rtol=0, atol=2e-5)  # x, m
    np.testing.assert_allclose(engine[3:7], reference[3:7], rtol=0, atol=2e-5)  # q
    np.testing.assert_allclose(engine[7:], reference[7:], rtol=0, atol=1e-4 * np.abs(reference[7:]).max())


def test_blocks_cover_every_particle_once_inside_their_spheres():
    from rigid.blocks import block_layout

    rng = np.random.default_rng(3)
    r0 = rng.normal(size=(1000, 3)) * [0.3, 0.1, 0.2]
    lay = block_layout(r0, [0, 700], [700, 300], 64)
    assert np.array_equal(np.sort(lay["order"]), np.arange(1000))
    assert lay["body_block_count"].tolist() == [11, 5]  # ceil(700/64), ceil(300/64)
    for k in range(len(lay["block_start"])):
        start, count, body = lay["block_start"][k], lay["block_count"][k], lay["block_body"][k]
        members = lay["order"][start:start + count]
        assert np.all((members >= [0, 700][body]) & (members < [700, 1000][body]))
        distance = np.linalg.norm(r0[members] - lay["block_centre"][k], axis=1)
        assert distance.max() <= lay["block_radius"][k] * (1 + 1e-12)


def test_rotation_gain_bounds_the_stretch_of_any_matrix(ti_cpu):
    import taichi as ti

    from rigid.wrench import make_wrench

    rng = np.random.default_rng(4)
    q = rng.normal(size=(40, 4))
    q[:20] /= np.linalg.norm(q[:20], axis=1, keepdims=True)  # rotations, then scaled rotations
    from rigid.rotation import quaternion_to_matrix_np

    mats = np.array([quaternion_to_matrix_np(v) * np.dot(v, v) for v in q])
    mats[30:] += rng.normal(scale=0.3, size=(10, 3, 3))  # not rotations at all
    field = ti.Matrix.field(3, 3, ti.f32, shape=40)
    gains = ti.field(ti.f32, shape=40)
    field.from_numpy(mats.astype(np.float32))
    _pf, rotation_gain, _bw, _w = make_wrench(None, None, None, None)

    @ti.kernel
    def measure():
        for i in range(40):
            gains[i] = rotation_gain(field[i])

    measure()
    spectral = np.linalg.norm(mats, ord=2, axis=(1, 2))
    g = gains.to_numpy()
    assert np.all(g >= spectral * (1 - 1e-6))
    np.testing.assert_allclose(g[:20], 1.0, rtol=1e-5)  # tight for rotations: no blocks lost to slack
