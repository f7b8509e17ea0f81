"""Frames in chunks (rigid.engine.rows, rigid.run.runner): one launch for many frames, the
rows read back at once, and numbers bit-identical to a frame-by-frame run; the parallel
schedule against the serial one.

References here come from outside the rows: the state fields read after each ``step_frame``,
energies recomputed in numpy (½ P·v + ½ L·ω; −M g·x + Σ ½ k depth² over the box's planes),
and a blow-up found by a frame-by-frame loop with its own checks.
"""
import contextlib

import numpy as np
import pytest

from rigid.run.runner import energy_bound, run_frames

THROWN = dict(position=(0.0, 0.2, 0.0), initial_velocity=(6.0, -3.0, 2.0), initial_angular_velocity=(3.0, -2.0, 5.0))
KEYS = ("x", "q", "v", "omega", "P", "L")


def fields_after_each_frame(sim, frames: int) -> dict:
    """The state fields (float64 copies of the float32 values) and particle positions after
    each of ``frames`` frame-by-frame calls."""
    s, out = sim.state, {key: [] for key in KEYS + ("particles",)}
    for _ in range(frames):
        sim.step_frame()
        for key in KEYS:
            out[key].append(getattr(s, key).to_numpy().astype(np.float64))
        out["particles"].append(s.particle_x.to_numpy().astype(np.float64))
    return {key: np.asarray(value) for key, value in out.items()}


def box_spring_energy(p: np.ndarray, k: float, floor: float, wall: float) -> float:
    """Σ ½ k depth² over particles behind the floor y = floor and the walls x, z = ±wall."""
    depths = np.concatenate([floor - p[:, 1], p[:, 0] - wall, -wall - p[:, 0], p[:, 2] - wall, -wall - p[:, 2]])
    depths = depths[depths > 0]
    return float(0.5 * k * (depths ** 2).sum())


def chunked(sim, sizes) -> dict:
    blocks = [sim.advance_frames(size) for size in sizes]
    return {key: np.concatenate([block[key] for block in blocks]) for key in blocks[0]}


def test_chunked_rows_are_the_frame_by_frame_state_and_energies(sim_cache):
    sim = sim_cache(**THROWN)
    reference = fields_after_each_frame(sim, 40)
    sim.reset()
    rows = chunked(sim, (1, 3, 7, 13, 16))  # 40 frames; 7 and 13 run as several graphs
    for key in KEYS:
        assert np.array_equal(rows[key], reference[key]), key  # bit for bit
    dt, n = sim.params.dt, sim.substeps  # t counts in float64 (the kernels step with its float32 rounding)
    assert np.allclose(rows["t"], dt * n * np.arange(1, 41), rtol=1e-12, atol=0)
    P, v, L, w, x = (reference[key][:, 0] for key in ("P", "v", "L", "omega", "x"))
    kinetic = 0.5 * np.einsum("ij,ij->i", P, v) + 0.5 * np.einsum("ij,ij->i", L, w)
    assert np.allclose(rows["kinetic_energy"], kinetic, rtol=1e-12, atol=0)
    cfg = sim.config
    springs = np.array([box_spring_energy(p, cfg.collision_stiffness, cfg.floor, cfg.wall)
                        for p in reference["particles"]])
    assert (springs > 1e-3).sum() >= 3, "the body should touch the box in a few rows"
    gravity = -sim.model.mass * x @ np.asarray(cfg.gravity, np.float64)
    assert np.allclose(rows["potential_energy"] - gravity, springs, rtol=1e-4, atol=1e-5)


def test_many_body_chunks_equal_frame_by_frame(sim_cache):
    sim = sim_cache(count=3, scale=0.25, initial_velocity=(4.0, -2.0, 1.0), initial_angular_velocity=(2.0, 1.0, 0.0))
    assert sim.many and sim.model.num_bodies == 3
    reference = fields_after_each_frame(sim, 24)
    sim.reset()
    rows = chunked(sim, (5, 19))
    for key in KEYS:
        assert rows[key].shape == (24, 3, reference[key].shape[-1])
        assert np.array_equal(rows[key], reference[key]), key
    P, v, L, w = (reference[key] for key in ("P", "v", "L", "omega"))
    kinetic = 0.5 * (P * v).sum(axis=(1, 2)) + 0.5 * (L * w).sum(axis=(1, 2))
    assert np.allclose(rows["kinetic_energy"], kinetic, rtol=1e-12, atol=0)
    sim.reset()
    for _ in range(24):
        sim.step_frame()
    snapshots_energy = sim.snapshot()["potential_energy"]
    assert rows["potential_energy"][-1] == snapshots_energy


@pytest.mark.parametrize("many", [False, True])
def test_the_parallel_schedule_follows_the_serial_one(units, many):
    """The same stages as parallel loops (the GPU's schedule, and large scenes' on a CPU): the
    same numbers up to float32 round-off where the compiler vectorises differently, and a
    second parallel run gives the same bits (every sum has a fixed order, whatever the threads)."""
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    config = SimConfig(fp64=False, **(dict(count=3, scale=0.25, initial_velocity=(4.0, -2.0, 1.0),
                                           initial_angular_velocity=(2.0, 1.0, 0.0)) if many else THROWN)).validate()
    runs = [Simulator(config, units, schedule=schedule).advance_frames(30)
            for schedule in ("serial", "parallel", "parallel")]
    serial, parallel, again = runs
    for key in KEYS:
        assert np.array_equal(parallel[key], again[key]), key
        scale = np.abs(serial[key]).max()
        np.testing.assert_allclose(parallel[key], serial[key], rtol=0, atol=2e-4 * scale + 1e-6, err_msg=key)
    touching = serial["potential_energy"] + (serial["x"] @ np.asarray(config.gravity)
                                             * Simulator(config, units).model.body_mass_np).sum(axis=1)
    assert touching.max() > 1e-3, "no contact: the comparison would be of free flight only"
    np.testing.assert_allclose(parallel["potential_energy"], serial["potential_energy"], rtol=1e-3, atol=1e-3)


def test_the_schedule_can_change_between_frames(units):
    """Setting Simulator.schedule between frames runs the other schedule's kernels from there
    (scripts/bench.py compares them on one Simulator): the run goes on as a serial one does."""
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    config = SimConfig(fp64=False, **THROWN).validate()
    switched, serial = Simulator(config, units, schedule="serial"), Simulator(config, units, schedule="serial")
    first = switched.advance_frames(10)
    switched.schedule = "parallel"
    rows = switched.advance_frames(10)
    expected = serial.advance_frames(20)
    assert np.array_equal(first["x"], expected["x"][:10])
    scale = np.abs(expected["x"]).max()
    np.testing.assert_allclose(rows["x"], expected["x"][10:], rtol=0, atol=2e-4 * scale)
    assert not np.array_equal(rows["x"][0], first["x"][-1])  # it moved on
    with pytest.raises(ValueError, match="serial"):
        switched.schedule = "threads"


@pytest.mark.parametrize("schedule", ["serial", "parallel"])
def test_prepared_launches_are_the_plain_kernel_calls(units, schedule):
    """The Simulator launches its kernels with their arguments set once (rigid.engine.launch):
    the same bits as Taichi's own calls of the same kernels, frame after frame."""
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    config = SimConfig(fp64=False, count=3, scale=0.25, initial_velocity=(4.0, -2.0, 1.0)).validate()
    prepared, plain = Simulator(config, units, schedule=schedule), Simulator(config, units, schedule=schedule)
    rows = prepared.advance_frames(12)
    assert all(launch.prepared for launch in prepared._launches.values())
    k, m, s, w, c, r = plain.kernels, plain.model.args, plain.state.args, plain.params.args, plain.scratch, plain.rows.args
    for frame in range(12):
        if schedule == "serial":
            k.run_frames(m, s, w, c, r, 1, plain.substeps)
        else:
            for _ in range(plain.substeps):
                k.substep(m, s, w, c)
            k.finish_frame(m, s, w, c, r, 0)
        got = plain.current_block()
        for key in KEYS:
            assert np.array_equal(got[key][0], rows[key][frame]), (frame, key)


def test_advance_frames_runs_past_the_row_buffer_in_chunks(sim_cache):
    """No silent cap: more frames than one chunk's rows are several launches, one row each."""
    sim = sim_cache(**THROWN)
    frames = sim.rows.capacity + 5
    block = sim.advance_frames(frames)
    assert block["x"].shape == (frames, 1, 3) and len(block["t"]) == frames
    tail = block["x"][-1]
    sim.reset()
    for _ in range(frames):
        sim.step_frame()
    assert np.array_equal(sim.snapshot()["x"], tail)


@contextlib.contextmanager
def counting_launches(sim):
    """Yields the list of frame counts ``sim.advance_frames`` is called with while inside."""
    calls = []
    original = sim.advance_frames
    sim.advance_frames = lambda frames: calls.append(frames) or original(frames)
    try:
        yield calls
    finally:
        del sim.advance_frames


def first_bad_frame(sim, frames: int) -> int:
    """Frame-by-frame: the first frame whose state is non-finite or whose energy rose past the bound."""
    def energy(s):
        return s["kinetic_energy"] + s["potential_energy"]

    start = sim.snapshot()
    e0 = energy(start)
    bound = energy_bound(sim.model.mass, sim.config.gravity, start["kinetic_energy"])
    for i in range(1, frames + 1):
        sim.step_frame()
        s = sim.snapshot()
        finite = all(np.isfinite(s[key]).all() for key in ("x", "q", "P", "L")) and np.isfinite(energy(s))
        if not finite or energy(s) - e0 > bound:
            return i
    raise AssertionError("no blow-up: the test needs one")


def test_a_blow_up_inside_a_chunk_keeps_exactly_the_good_frames(sim_cache, tmp_path):
    stiff = dict(collision_stiffness=3e6)  # explicit Euler's bound is dt < c/k = 3.3e-4 s here
    sim = sim_cache(**stiff)
    bad = first_bad_frame(sim, 300)
    assert bad > 8, "the blow-up should fall inside a chunk, not in the first frames"
    sim = sim_cache(**stiff)
    out = tmp_path / "t.npz"
    with counting_launches(sim) as calls:
        result = run_frames(sim, 300, export_path=out)
    assert result.status == "blew-up" and result.frames == bad - 1, (result, bad)
    assert f"(frame {bad})" in result.message
    assert max(calls) > 1, "the run should have been chunked"
    d = np.load(out)
    assert len(d["t"]) == bad  # row 0 and the bad - 1 good frames
    assert np.isfinite(d["x"]).all() and np.isfinite(d["kinetic_energy"]).all()
    assert result.last_row["t"] == pytest.approx(float(d["t"][-1]), rel=1e-6)


def test_a_long_headless_run_takes_few_launches(sim_cache):
    sim = sim_cache(**THROWN)
    with counting_launches(sim) as calls:
        result = run_frames(sim, 600)
    assert result.status == "done" and result.frames == 600 and sum(calls) == 600
    assert calls[0] == 1 and len(calls) < 40, calls  # frame by frame would be 600 launches


def test_reconfigure_moves_and_launches_many_bodies(units):
    """Simulator.reconfigure with a new position or velocity places many bodies again (it once
    kept the bodies of the build's config): every centre moves by the offset, every body moves
    with the new velocity, the model is the same."""
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    sim = Simulator(SimConfig(count=3, scale=0.25).validate(), units)
    x0 = sim.snapshot()["x"]
    assert np.allclose(sim.snapshot()["v"], 0.0)
    sim.reconfigure(position=(0.1, 0.0, -0.05), initial_velocity=(0.5, 1.0, -0.25))
    snap = sim.snapshot()
    assert np.allclose(snap["x"] - x0, [0.1, 0.0, -0.05], atol=1e-6)
    assert np.allclose(snap["v"], [0.5, 1.0, -0.25], atol=1e-6)


def test_byte_copies_to_and_from_the_arrays_are_taichis_own(ti_cpu):
    """rigid.engine.arrays copies bytes on the CPU instead of Taichi's per-array kernels: the same
    values as Taichi's from_numpy / to_numpy / fill, for every element kind the engine uses."""
    from rigid.engine.arrays import clear, download, upload, zeros

    rng = np.random.default_rng(3)
    for kind, shape in (("f", (7,)), ("i", (7,)), ("v3", (7, 3)), ("v4", (7, 4)), ("v13", (7, 13)),
                        ("m3", (7, 3, 3)), ("v3i", (7, 3))):
        values = rng.normal(size=shape) * 100
        ours, theirs = zeros(7, kind), zeros(7, kind)
        upload(ours, values)
        theirs.from_numpy(values.astype(theirs.to_numpy().dtype))
        assert np.array_equal(ours.to_numpy(), theirs.to_numpy()), kind
        assert np.array_equal(download(theirs), theirs.to_numpy()), kind
        clear(ours)
        assert not np.any(ours.to_numpy()), kind
