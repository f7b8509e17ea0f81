"""The adaptive skin (rigid.engine.skin): a skin made to shrink after every frame (thresholds
patched) changes which pairs the lists hold and how often they are rebuilt, never the sums:
the 27-sphere pile keeps the bits of the run with the skin at half a diameter, on both
schedules, with its bodies falling asleep as well."""
import numpy as np
import pytest

from conftest import ASSETS

PILE = dict(mesh=str(ASSETS / "sphere.obj"), count=27, scale=0.15, position=(0.0, -0.8, 0.0),
            particle_mass=0.01, velocity_damping_stiffness=12.0, friction_stiffness=0.4,
            integrator="symplectic", sleep=False)


def _run(sim_cache, schedule: str, frames: int = 40, **changes):
    sim = sim_cache(**{**PILE, **changes})
    sim.schedule = schedule
    for _ in range(frames):
        sim.step_frame()
    return sim


@pytest.mark.parametrize("schedule", ["serial", "parallel"])
def test_a_changing_skin_keeps_the_bits(sim_cache, monkeypatch, schedule):
    from rigid.engine import neighbours, skin

    wide = _run(sim_cache, schedule)
    assert wide._skin.fraction == neighbours.SKIN_FRACTION  # a pile that reuses its lists keeps its skin
    monkeypatch.setattr(skin, "SHRINK_ABOVE", 0.0)  # shrink after every frame, down to the least
    thin = _run(sim_cache, schedule)
    assert thin._skin.fraction == skin.MIN_FRACTION
    assert thin.neighbour_builds > wide.neighbour_builds  # (so the lists were not the same)
    a, b = wide.snapshot(), thin.snapshot()
    for key in ("x", "q", "P", "L"):
        assert np.array_equal(a[key], b[key]), (key, np.abs(a[key] - b[key]).max())


@pytest.mark.parametrize("schedule", ["serial", "parallel"])
def test_a_changing_skin_keeps_the_bits_while_bodies_fall_asleep(sim_cache, monkeypatch, schedule):
    """A body that falls asleep mid-frame is not placed again (sleep.py): its particles must lie at
    its final pose at once, not a step behind until the next rebuild (which the skin times). Left
    a step behind, both schedules' runs here parted by ~4e-7 m by frame 80."""
    from rigid.engine import skin

    wide = _run(sim_cache, schedule, frames=80, sleep=True)
    monkeypatch.setattr(skin, "SHRINK_ABOVE", 0.0)  # down to a skin so thin that the lists are
    monkeypatch.setattr(skin, "MIN_FRACTION", 1e-4)  # rebuilt at nearly every substep, mid-frame
    thin = _run(sim_cache, schedule, frames=80, sleep=True)
    assert thin.neighbour_builds > 8 * wide.neighbour_builds
    assert 0 < wide.asleep().sum() < 27  # sleepers among moving bodies
    assert np.array_equal(wide.asleep(), thin.asleep())
    a, b = wide.snapshot(), thin.snapshot()
    for key in ("x", "q", "P", "L"):
        assert np.array_equal(a[key], b[key]), (key, np.abs(a[key] - b[key]).max())
