"""The pipeline a GPU runs, run on the CPU (no GPU has been lent to this project, and CI has none).

Off a CPU the engine compiles another substep from the same stages:
- the parallel pair stage visits every particle's whole list (pair_stages.visit_all), not the
  sweep in parts (pair_parts.parts_here() is 0);
- the lists are only ever rebuilt in full (refresh._on_cpu() is False);
- a substep is one kernel that gates the rebuild's loops by the flag on the device, not
  split_substep.py's launches (the flag is not read through its address: IntCell.on_cpu).

Those three switches are flipped here, and the kernels compiled afresh for them. The run must
follow the serial schedule to float32 round-off, repeat bit for bit, and rebuild its lists
without a single partial rebuild. A broken GPU path (a pair lost by visit_all, a rebuild never
gated in) would part from the serial run by whole contacts.
"""
import numpy as np
import pytest

from conftest import ASSETS

PILE = dict(mesh=str(ASSETS / "sphere.obj"), count=8, scale=0.2, position=(0.0, -0.7, 0.0),
            initial_velocity=(1.5, -2.0, 0.5), initial_angular_velocity=(2.0, 1.0, 0.0), sleep=False)
KEYS = ("x", "q", "v", "omega", "P", "L")


@pytest.fixture
def gpu_pipeline(monkeypatch):
    """The engine's kernels compiled as for a GPU (in a kernel cache of this test's own)."""
    from rigid.engine import arrays, kernels, pair_parts, refresh

    monkeypatch.setattr(pair_parts, "parts_here", lambda: 0)
    monkeypatch.setattr(refresh, "_on_cpu", lambda: False)
    monkeypatch.setattr(arrays.IntCell, "on_cpu", property(lambda self: False))
    monkeypatch.setattr(kernels, "_CACHE", {})


def test_the_gpu_pipeline_follows_the_serial_schedule(units, gpu_pipeline):
    from rigid.config import SimConfig
    from rigid.engine.launch import SplitLaunch
    from rigid.engine.refresh_state import refreshes_so_far
    from rigid.engine.simulator import Simulator

    config = SimConfig(fp64=False, **PILE).validate()
    serial = Simulator(config, units, schedule="serial").advance_frames(40)
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
                                             * Simulator(config, units).model.body_mass_np).sum(axis=1)
    assert touching.max() > 1e-3, "no contact: the comparison would be of free flight only"
