"""The fast paths change speed, not physics.

- The parallel path (threads over blocks, fixed-order sum) follows the serial
  path's trajectory to round-off, and two parallel runs are bit-identical.
- The blocked particle sum with its plane culling (wrench.py) follows a plain
  loop over every particle with every plane (the handout-style baseline of
  scripts/bench_handout.py, an independent implementation) through contacts
  with the floor and a wall: a skipped contact would move the body by
  millimetres, round-off by micrometres.
- Blocks cover every particle once and their boxes contain their particles;
  the per-block reach test never misses a particle behind a plane, for
  rotations and for matrices that are not.
Speeds are measured by scripts/bench.py, never asserted here.
"""
import sys
from types import SimpleNamespace

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
    from rigid.bench.handout import HandoutLoop

    engine = _run(cube, parallel=False)
    plain = HandoutLoop(cube.model.r0_np, cube.config.particle_mass, units, cube.config)
    for _ in range(FRAMES):
        plain.step_frame(cube.substeps)
    f = plain._fields
    reference = np.concatenate([f[k].to_numpy().ravel() for k in ("x", "q", "P", "L")]).astype(np.float64)
    np.testing.assert_allclose(engine[:3], reference[:3], rtol=0, atol=2e-5)  # x, m
    np.testing.assert_allclose(engine[3:7], reference[3:7], rtol=0, atol=2e-5)  # q
    np.testing.assert_allclose(engine[7:], reference[7:], rtol=0, atol=1e-4 * np.abs(reference[7:]).max())


def test_without_walls_a_big_body_falls_through_the_floor(cube):
    """walls off: no block runs a contact loop, even one deep below the floor (P = M (v0 + g t))."""
    cube.reconfigure(walls=False, position=(0.0, -1.2, 0.0))
    try:
        for parallel in (False, True):
            state = _run(cube, parallel)
            t = FRAMES * cube.substeps * cube.config.dt
            expect = cube.model.mass * (np.array(THROW["initial_velocity"]) + np.array(cube.config.gravity) * t)
            np.testing.assert_allclose(state[7:10], expect, rtol=1e-5, atol=1e-5 * np.abs(expect).max())
    finally:
        cube.reconfigure(walls=True, position=THROW["position"])


def test_blocks_cover_every_particle_once_inside_their_boxes():
    from rigid.engine.blocks import block_layout

    rng = np.random.default_rng(3)
    r0 = rng.normal(size=(1000, 3)) * [0.3, 0.1, 0.2]
    lay = block_layout(r0, [0, 700], [700, 300], 64)
    assert np.array_equal(np.sort(lay["order"]), np.arange(1000))
    assert lay["body_block_count"].tolist() == [11, 5]  # ceil(700/64), ceil(300/64)
    for k in range(len(lay["block_start"])):
        start, count, body = lay["block_start"][k], lay["block_count"][k], lay["block_body"][k]
        members = lay["order"][start:start + count]
        assert np.all((members >= [0, 700][body]) & (members < [700, 1000][body]))
        offset = np.abs(r0[members] - lay["block_centre"][k])
        assert np.all(offset <= lay["block_half"][k] * (1 + 1e-12))


def test_reach_test_never_misses_a_particle_behind_a_plane(ti_cpu):
    """For rotations and for matrices that are not (a unit may let q drift), a block with a particle
    behind the floor or a wall is always flagged; and the flag is not far too eager."""
    import taichi as ti

    from rigid.engine.blocks import ParticleBlocks
    from rigid.engine.rotation import quaternion_to_matrix_np
    from rigid.engine.wrench import make_wrench

    rng = np.random.default_rng(4)
    r0 = rng.normal(size=(512, 3)) * [0.3, 0.1, 0.2]
    model = SimpleNamespace(r0_np=r0, body_start=_Host([0]), body_count=_Host([512]))
    blocks = ParticleBlocks(model, block_size=64)
    prm = SimpleNamespace(walls=ti.field(ti.i32, shape=()), floor=ti.field(ti.f32, shape=()),
                          wall=ti.field(ti.f32, shape=()))
    prm.walls[None], prm.floor[None], prm.wall[None] = 1, -1.0, 1.0
    _pf, planes_in_reach, _bw, _w = make_wrench(None, prm, blocks, None)
    trials, k = 60, blocks.num_blocks
    R = ti.Matrix.field(3, 3, ti.f32, shape=trials)
    x = ti.Vector.field(3, ti.f32, shape=trials)
    near = ti.field(ti.i32, shape=(trials, k, 5))

    @ti.kernel
    def flags():
        for t, b in ti.ndrange(trials, k):
            flag = planes_in_reach(b, x[t], R[t])
            for plane in ti.static(range(5)):
                near[t, b, plane] = flag[plane]

    q = rng.normal(size=(trials, 4))
    q[: trials // 2] /= np.linalg.norm(q[: trials // 2], axis=1, keepdims=True)
    mats = np.array([quaternion_to_matrix_np(v) * v.dot(v) for v in q])  # rotations, then scaled ones
    mats[trials - 10:] += rng.normal(scale=0.3, size=(10, 3, 3))  # and some that are not rotations
    R.from_numpy(mats.astype(np.float32))
    x.from_numpy(rng.uniform(-0.8, 0.8, size=(trials, 3)).astype(np.float32))
    flags()
    got = near.to_numpy()
    slack = 2 * np.linalg.norm(r0.max(axis=0) - r0.min(axis=0))
    flagged = 0
    for t in range(trials):
        p = x.to_numpy()[t] + r0[blocks.order] @ mats[t].T  # particles in block order, world frame
        for b in range(k):
            pb = p[64 * b: 64 * (b + 1)]
            # Depth behind each plane of the box, as contact.box_force orders them.
            depth = np.stack([-1 - pb[:, 1], -1 - pb[:, 0], pb[:, 0] - 1, -1 - pb[:, 2], pb[:, 2] - 1]).max(axis=1)
            assert np.all(got[t, b][depth > 0] == 1), (t, b, depth, got[t, b])  # never a miss
            assert np.all(depth[got[t, b] == 1] > -slack * np.abs(mats[t]).max())  # nor far too eager
            flagged += got[t, b].sum()
    assert flagged > 20  # the trials do put blocks near planes


class _Host:
    """A stand-in for a Taichi field read with to_numpy()."""

    def __init__(self, values):
        self.values = np.asarray(values)

    def to_numpy(self):
        return self.values
