"""Neighbour lists that grow (rigid.engine.list_growth): lists of 2 slots overflow in the
27-sphere pile at once and double, chunk by chunk, to 16; the run keeps the bits of the run that
had 16 slots from the start (which never overflow in this pile), whether its frames go in one
chunk or one at a time, on both schedules."""
import numpy as np
import pytest

from conftest import ASSETS

PILE = dict(mesh=str(ASSETS / "sphere.obj"), count=27, scale=0.15, position=(0.0, -0.8, 0.0),
            particle_mass=0.01, velocity_damping_stiffness=12.0, friction_stiffness=0.4,
            integrator="symplectic", sleep=False)
FRAMES = 40


def _run(sim_cache, schedule: str, chunked: bool):
    sim = sim_cache(**PILE)
    sim.schedule = schedule
    most = 0
    if chunked:
        sim.advance_frames(FRAMES)
    else:
        for _ in range(FRAMES):
            sim.step_frame()
            most = max(most, int(sim.neighbour_counts().max()))
    stride = sim._scratch_arrays["nbr_list"].shape[0] // sim.num_particles
    return sim.snapshot(), stride, most


@pytest.mark.parametrize("schedule", ["serial", "parallel"])
def test_grown_lists_give_the_bits_of_long_lists(sim_cache, monkeypatch, schedule):
    from rigid.engine import list_growth, neighbours

    monkeypatch.setattr(list_growth, "MAX_NEIGHBOURS", 16)
    monkeypatch.setattr(neighbours, "NEIGHBOURS_PER_PARTICLE", 16)
    long, stride, most = _run(sim_cache, schedule, chunked=False)
    assert stride == 16 and 2 < most <= 16, (stride, most)  # never overflowed, yet more than 2 candidates
    monkeypatch.setattr(neighbours, "NEIGHBOURS_PER_PARTICLE", 2)
    for chunked in (True, False):
        grown, stride, _most = _run(sim_cache, schedule, chunked)
        assert stride > 2, "the lists did not grow: the test would prove nothing"
        for key in ("x", "q", "P", "L"):
            assert np.array_equal(grown[key], long[key]), (chunked, key, np.abs(grown[key] - long[key]).max())


def test_lists_grow_only_as_far_as_they_overflow(sim_cache, monkeypatch):
    """A flag raised before a chunk (here by hand, as a build outside a chunk could) is not taken
    for the chunk's own: lists that hold every candidate stay as they are."""
    from rigid.engine import broadphase, broadphase_host, neighbours

    monkeypatch.setattr(neighbours, "NEIGHBOURS_PER_PARTICLE", 16)
    sim = sim_cache(**PILE)
    broadphase_host.cell(sim._scratch_arrays, broadphase.OVERFLOW).value = 1
    sim.advance_frames(5)
    assert sim._scratch_arrays["nbr_list"].shape[0] == 16 * sim.num_particles
    assert sim.neighbour_counts().max() <= 16
