"""Schedules and culling change speed, not physics.

- The parallel schedule (every stage a parallel loop, fixed-order sums) follows the serial
  one's trajectory to round-off for a big body, and two parallel runs are bit-identical.
- The blocked particle sum with its plane culling (stages.py) follows a plain loop over every
  particle with every plane (the handout-style baseline of rigid/bench/handout.py, an
  independent implementation) through contacts with the floor and a wall: a skipped contact
  would move the body by millimetres, round-off by micrometres.
- The grader's compact particle loop (every plane tested) gives the culled loops' forces.
- Blocks cover every particle once and their boxes contain their particles; the per-block
  reach test never misses a particle behind a plane, for rotations and for matrices that are not.
Speeds are measured by scripts/bench.py, never asserted here.
"""
import numpy as np
import pytest

from conftest import ASSETS

# A 0.5 m cube volume-sampled at 18 cells: 5832 particles, 92 blocks. Thrown down and sideways
# from near the floor and the x = 1 wall: it hits both within the 6 frames.
CUBE = dict(mesh=str(ASSETS / "box.obj"), scale=0.5, particles="volume", grid=18)
THROW = dict(position=(0.7, -0.7, 0.0), initial_velocity=(3.0, -1.0, 1.0),
             initial_angular_velocity=(1.0, 3.0, 0.5))
FRAMES = 6


def _cube(units, schedule=None, **changes):
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    return Simulator(SimConfig(fp64=False, **{**CUBE, **THROW, **changes}).validate(), units, schedule=schedule)


def _state(block) -> np.ndarray:
    return np.concatenate([block[key][-1, 0] for key in ("x", "q", "P", "L")])


def test_the_schedule_is_one_policy(ti_cpu):
    from rigid.engine.schedule import PARALLEL_MIN_PARTICLES_PAIRS, choose_schedule

    assert choose_schedule(42, pairs=False) == "serial"
    assert choose_schedule(10 * PARALLEL_MIN_PARTICLES_PAIRS, pairs=True) == "parallel"
    assert choose_schedule(10 * PARALLEL_MIN_PARTICLES_PAIRS, pairs=False) == "serial"  # no pairs: cheap
    assert choose_schedule(42, pairs=False, forced="parallel") == "parallel"
    with pytest.raises(ValueError, match="use 'serial' or 'parallel'"):
        choose_schedule(42, pairs=False, forced="fast")


def test_parallel_schedule_follows_serial_and_is_bit_reproducible(units):
    serial = _state(_cube(units, "serial").advance_frames(FRAMES))
    parallel = _state(_cube(units, "parallel").advance_frames(FRAMES))
    again = _state(_cube(units, "parallel").advance_frames(FRAMES))
    mass = 5832 * 1.0
    p = serial[7:10]
    assert np.linalg.norm(p - mass * np.array(THROW["initial_velocity"])) > 0.5 * mass, \
        "the cube should have hit something"
    scale = np.abs(serial).max()
    np.testing.assert_allclose(parallel, serial, rtol=0, atol=2e-5 * scale)
    assert np.array_equal(parallel, again)


def test_the_compact_block_loop_gives_the_culled_loops_forces(units):
    """kernels.compact_block_loops (the grader's processes): one particle loop that tests every
    plane follows the four culled loops through the floor and wall contacts, to round-off."""
    from rigid.engine.kernels import compact_block_loops

    culled = _state(_cube(units).advance_frames(FRAMES))
    compact_block_loops()
    try:
        sim = _cube(units)
    finally:
        compact_block_loops(False)
    assert sim.kernels.compact and not _cube(units).kernels.compact
    compact = _state(sim.advance_frames(FRAMES))
    assert np.linalg.norm(culled[7:10] - 5832 * np.array(THROW["initial_velocity"])) > 0.5 * 5832  # it hit
    np.testing.assert_allclose(compact, culled, rtol=0, atol=2e-5 * np.abs(culled).max())


def test_blocked_sum_with_culling_matches_a_plain_particle_loop(units):
    from rigid.bench.handout import HandoutLoop
    from rigid.config import SimConfig

    sim = _cube(units)
    config = SimConfig(fp64=False, **CUBE, **THROW).validate()
    reference = HandoutLoop(sim.model.r0_np, config.particle_mass, units, config)
    engine = sim.advance_frames(FRAMES)
    reference.step_frame(FRAMES * sim.substeps)
    state = reference._fields
    np.testing.assert_allclose(engine["x"][-1, 0], state["x"].to_numpy(), rtol=0, atol=2e-5)
    np.testing.assert_allclose(engine["q"][-1, 0], state["q"].to_numpy(), rtol=0, atol=2e-5)
    P = state["P"].to_numpy()
    assert np.linalg.norm(P - 5832 * np.array(THROW["initial_velocity"])) > 2000, "it should have hit the box"
    np.testing.assert_allclose(engine["P"][-1, 0], P, rtol=0, atol=1e-4 * np.abs(P).max())


def test_without_walls_a_big_body_falls_through_the_floor(units):
    sim = _cube(units, walls=False, initial_angular_velocity=(0.0, 0.0, 0.0))
    block = sim.advance_frames(FRAMES)
    expect = 5832 * (np.array(THROW["initial_velocity"])[None] + np.array(sim.config.gravity)[None]
                     * block["t"][:, None])
    np.testing.assert_allclose(block["P"][:, 0], expect, rtol=1e-5, atol=1e-5 * np.abs(expect).max())
    assert block["x"][-1, 0, 1] < -0.7


def test_blocks_cover_every_particle_once_inside_their_boxes():
    from rigid.engine.blocks import block_layout

    rng = np.random.default_rng(1)
    r0 = rng.normal(size=(1000, 3))
    lay = block_layout(r0, [0, 700], [700, 300], 64)
    assert np.array_equal(np.sort(lay["order"]), np.arange(1000))
    assert lay["body_block_count"].tolist() == [11, 5]  # ceil(700/64), ceil(300/64)
    for k, (start, count, body) in enumerate(zip(lay["block_start"], lay["block_count"], lay["block_body"])):
        members = lay["order"][start:start + count]
        assert np.all((members >= [0, 700][body]) & (members < [700, 1000][body]))
        offset = np.abs(r0[members] - lay["block_centre"][k])
        assert np.all(offset <= lay["block_half"][k] * (1 + 1e-12))
        assert np.any(np.isclose(offset, lay["block_half"][k], rtol=1e-12), axis=0).all()  # tight on each axis


def test_reach_test_never_misses_a_particle_behind_a_plane(units):
    """For rotations and for matrices that are not (a unit may let q drift), a block with a particle
    behind the floor or a wall is always flagged; and the flag is not far too eager."""
    import taichi as ti

    from rigid.bodies.mesh import BodyGeometry
    from rigid.config import SimConfig
    from rigid.engine import stages
    from rigid.engine.arrays import ModelArgs, StateArgs, WorldArgs
    from rigid.engine.rotation import quaternion_to_matrix_np
    from rigid.engine.simulator import Simulator

    rng = np.random.default_rng(4)
    r0 = rng.normal(size=(512, 3)) * [0.3, 0.1, 0.2]
    sim = Simulator(SimConfig(fp64=False, walls=False).validate(), units,
                    geometry=BodyGeometry(r0, r0, np.zeros((0, 3), np.int32)))
    sim.params.walls = True  # the box's planes, without the start-inside check
    k = sim.model.num_blocks

    @ti.kernel
    def flags(model: ModelArgs(), state: StateArgs(), world: WorldArgs(), out: ti.types.ndarray()):
        for b in range(out.shape[0]):
            near = stages.planes_in_reach(model, state, world, b)
            for plane in range(5):
                out[b, plane] = (near >> plane) & 1

    trials = 60
    q = rng.normal(size=(trials, 4))
    q[: trials // 2] /= np.linalg.norm(q[: trials // 2], axis=1, keepdims=True)
    mats = np.array([quaternion_to_matrix_np(v) * v.dot(v) for v in q])  # rotations, then scaled ones
    mats[trials - 10:] += rng.normal(scale=0.3, size=(10, 3, 3))  # and some that are not rotations
    xs = rng.uniform(-0.8, 0.8, size=(trials, 3))
    slack = 2 * np.linalg.norm(r0.max(axis=0) - r0.min(axis=0))
    flagged = 0
    offsets = sim.model.r0_np  # slot order, about the centre of mass
    starts, counts = sim.model.block_start.to_numpy(), sim.model.block_count.to_numpy()
    for t in range(trials):
        sim.state.x.from_numpy(xs[t:t + 1].astype(np.float32))
        sim.state.R.from_numpy(mats[t:t + 1].astype(np.float32))
        got = np.zeros((k, 5), np.int32)
        flags(sim.model.args, sim.state.args, sim.params.args, got)
        p = xs[t] + offsets @ mats[t].T
        for b in range(k):
            pb = p[starts[b]: starts[b] + counts[b]]
            # Depth behind each plane of the box, in the engine's plane order.
            depth = np.stack([-1 - pb[:, 1], -1 - pb[:, 0], pb[:, 0] - 1, -1 - pb[:, 2], pb[:, 2] - 1]).max(axis=1)
            assert np.all(got[b][depth > 0] == 1), (t, b, depth, got[b])  # never a miss
            assert np.all(depth[got[b] == 1] > -slack * np.abs(mats[t]).max())  # nor far too eager
            flagged += got[b].sum()
    assert flagged > 20  # the trials do put blocks near planes
