"""The pipeline a GPU runs, run on the CPU (no GPU has been lent to this project, and CI has none).

Off a CPU (schedule.on_cpu() is False) the engine compiles another substep from the same stages:
- the parallel pair stage visits every particle's whole list (pair_stages.visit_all), not the
  sweep in parts (pair_parts.parts_here() is 0);
- the lists are only ever rebuilt in full (refresh.settle);
- the motion test runs as parallel loops (motion.note_motion_spread), and a frame's contact
  energy is summed in chunks (stages.sum_energy_chunks);
- a substep is one kernel that gates the rebuild's loops by the flag on the device, not
  split_substep.py's launches (the flag is not read through its address: IntCell.on_cpu).

Those switches are flipped here, and the kernels compiled afresh for them. The run must follow
the CPU's serial schedule to float32 round-off (its energies too), repeat bit for bit, and rebuild
its lists without a single partial rebuild; the motion test spread over threads must take the
one-thread test's decisions. A broken GPU path (a pair lost by visit_all, a rebuild never gated
in) would part from the serial run by whole contacts.
"""
import numpy as np
import pytest

from conftest import ASSETS

PILE = dict(mesh=str(ASSETS / "sphere.obj"), count=8, scale=0.2, position=(0.0, -0.7, 0.0),
            initial_velocity=(1.5, -2.0, 0.5), initial_angular_velocity=(2.0, 1.0, 0.0), sleep=False)
KEYS = ("x", "q", "v", "omega", "P", "L")


@pytest.fixture
def as_on_a_gpu(monkeypatch):
    """as_on_a_gpu(): from then on, the engine's kernels compiled as for a GPU (in a kernel cache of
    this test's own)."""
    from rigid.engine import arrays, kernels, schedule

    def switch():
        monkeypatch.setattr(schedule, "on_cpu", lambda: False)
        monkeypatch.setattr(arrays.IntCell, "on_cpu", property(lambda self: False))
        monkeypatch.setattr(kernels, "_CACHE", {})

    return switch


def test_the_gpu_pipeline_follows_the_serial_schedule(units, as_on_a_gpu):
    from rigid.config import SimConfig
    from rigid.engine.launch import SplitLaunch
    from rigid.engine.broadphase_host import refreshes_so_far
    from rigid.engine.simulator import Simulator

    config = SimConfig(fp64=False, **PILE).validate()
    # The reference: the CPU's serial schedule, as users run it (the kernels of the in-process
    # "engine" group, conftest.GROUPS); then the GPU's pipeline.
    reference = Simulator(config, units, schedule="serial")
    serial = reference.advance_frames(40)
    as_on_a_gpu()
    runs = []
    for _ in range(2):
        sim = Simulator(config, units, schedule="parallel")
        runs.append(sim.advance_frames(40))
        assert not isinstance(sim._prepared_launches()["substep"], SplitLaunch)  # one kernel a substep
        assert sim.neighbour_builds > 3 and refreshes_so_far(sim) == 0, (sim.neighbour_builds, refreshes_so_far(sim))
    gpu, again = runs
    for key in KEYS:
        assert np.array_equal(gpu[key], again[key]), key  # fixed-order sums, whatever the threads
        scale = np.abs(serial[key]).max()
        np.testing.assert_allclose(gpu[key], serial[key], rtol=0, atol=2e-4 * scale + 1e-6, err_msg=key)
    touching = serial["potential_energy"] + (serial["x"] @ np.asarray(config.gravity)
                                             * reference.model.body_mass_np).sum(axis=1)
    assert touching.max() > 1e-3, "no contact: the comparison would be of free flight only"
    for key in ("kinetic_energy", "potential_energy"):  # the frame's energy summed in chunks
        np.testing.assert_allclose(gpu[key], serial[key], rtol=1e-3, atol=1e-3 * np.abs(serial[key]).max(), err_msg=key)


def test_the_spread_motion_test_takes_the_one_thread_tests_decisions(units):
    """motion.note_motion_spread (a GPU's motion test, parallel loops with atomic min, max and
    counts) against motion.note_motion (one thread) on the same states of a falling and
    settling pile: the same flag, and for every body the same bound e_b (broadphase.MOTION) and
    reach ρ'_b (REACH, where the test asks for it) to round-off: LLVM contracts the two kernels'
    arithmetic into FMAs differently, and Δx less the middle of the Δx cancels to a few ulps."""
    import taichi as ti

    from rigid.config import SimConfig
    from rigid.engine import broadphase as bp
    from rigid.engine import motion
    from rigid.engine.arrays import ScratchArgs, StateArgs, download, upload
    from rigid.engine.simulator import Simulator

    S, C = StateArgs(), ScratchArgs()

    @ti.kernel
    def one_thread(state: S, scratch: C):
        ti.loop_config(serialize=True)
        for _ in range(1):
            motion.note_motion(scratch, state)

    @ti.kernel
    def spread(state: S, scratch: C):
        motion.note_motion_spread(scratch, state)

    sim = Simulator(SimConfig(fp64=False, **PILE).validate(), units, schedule="serial")
    arrays = sim._scratch_arrays
    flags_seen = set()
    for _ in range(12):
        sim.advance_frames(5)
        start = {name: download(arrays[name]).copy()
                 for name in ("broadphase_body_floats", "broadphase_ints", "broadphase_floats")}
        results = []
        for kernel in (one_thread, spread):
            for name, value in start.items():
                upload(arrays[name], value)
            kernel(sim.state.args, sim.scratch)
            flags, table = download(arrays["broadphase_ints"]), download(arrays["broadphase_body_floats"])
            results.append((flags[bp.REBUILD], table))
        (flag, pose), (flag_spread, pose_spread) = results
        assert flag == flag_spread, (sim.frame, flag, flag_spread)
        allowed = start["broadphase_floats"][bp.ALLOWED]  # the motion the decisions weigh e against
        np.testing.assert_allclose(pose_spread[:, bp.MOTION], pose[:, bp.MOTION], rtol=0, atol=1e-5 * allowed,
                                   err_msg=str(sim.frame))
        if flag == motion.MAYBE:
            np.testing.assert_allclose(pose_spread[:, bp.REACH], pose[:, bp.REACH], rtol=1e-6, err_msg=str(sim.frame))
        flags_seen.add(int(flag))
        for name, value in start.items():  # the run goes on from its own state
            upload(arrays[name], value)
    assert {0, motion.MAYBE} <= flags_seen, flags_seen  # both decisions were taken and compared
