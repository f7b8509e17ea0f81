"""Sleeping with materials (rigid.engine.sleep, material_stages.pair_wave): a pile with friction and
restitution falls asleep exactly at rest and stays; until a first body sleeps, the same bits as
with sleeping off; a moving body wakes the sleeper it hits, momentum conserved; and both copies of
each pair's sticking spring (pair_slip.py) agree while one side rests and after it wakes."""
import numpy as np

from conftest import ASSETS

SPHERE, BOX = str(ASSETS / "sphere.obj"), str(ASSETS / "box.obj")
# tests/test_sleep.py's spheres, with materials: Coulomb friction with sticking springs, e = 0.2
SETTLING = dict(mesh=SPHERE, scale=0.15, particle_mass=0.01, velocity_damping_stiffness=12.0,
                friction_stiffness=0.4, integrator="symplectic", dt=1e-3, friction=0.5, restitution=0.2)


def _pair_springs(sim):
    from rigid.engine.pair_slip import springs_by_pair

    return springs_by_pair(sim)


def _agree(sim):
    """Both copies of every listed pair's spring the same bits; the number of stretched ones."""
    springs = _pair_springs(sim)
    stretched = 0
    for (i, j), s in springs.items():
        if (j, i) in springs:
            assert np.array_equal(s, springs[j, i]), (i, j, s, springs[j, i])
        stretched += bool(np.any(s != 0))
    return stretched


def test_a_materials_pile_sleeps_exactly_at_rest_and_until_then_keeps_the_bits(sim_cache):
    on = sim_cache(count=6, position=(0.0, -0.8, 0.0), **SETTLING)
    off = sim_cache(count=6, position=(0.0, -0.8, 0.0), sleep=False, **SETTLING)
    first = None
    for frame in range(480):
        on.step_frame()
        if first is None:
            off.step_frame()
            if on.asleep().any():
                first = frame
            else:  # no body asleep yet: the same bits as with sleeping off
                a, b = on.snapshot(), off.snapshot()
                for key in ("x", "q", "P", "L"):
                    assert np.array_equal(a[key], b[key]), (frame, key)
        if on.asleep().all():
            break
    assert first is not None and first > 30, f"first sleeper at frame {first}"
    assert on.asleep().all(), f"{on.asleep().sum()} of 6 asleep after {on.time:.1f} s"
    assert not off.asleep().any()
    row = on.snapshot()
    assert np.all(row["P"] == 0) and np.all(row["L"] == 0) and np.all(row["v"] == 0) and np.all(row["omega"] == 0)
    assert row["kinetic_energy"] == 0.0
    assert np.all(row["x"][:, 1] > -1.0 + 0.1)  # on the floor, not through it
    block = on.advance_frames(30)  # and stays: nothing moves
    assert on.asleep().all()
    assert np.all(block["x"] == row["x"][None]) and np.all(block["q"] == row["q"][None])
    _agree(on)


def test_a_moving_body_wakes_the_sleeper_it_hits_and_momentum_is_kept(sim_cache):
    """test_sleep.py's row of three resting spheres and a fourth arriving, with materials; both
    copies of every spring agree after each frame."""
    from test_sleep import through_a_wake

    through_a_wake(sim_cache, SETTLING, _agree)


def test_both_copies_of_the_springs_agree_while_a_sleeper_holds_a_woken_box_and_after_it_wakes(sim_cache):
    """Two boxes of stack.toml with friction, settled and asleep; the top one woken rests on the
    resting one (held by its springs, the lower side's copies written by the upper side), then
    the lower one woken: every pair's two copies agree throughout, and the stack holds."""
    below, above = dict(position=(0.0, -0.898, 0.0)), dict(position=(0.02, -0.7077, 0.02))
    sim = sim_cache(bodies=(below, above), particles="volume", mesh=BOX, scale=0.2, grid=5, particle_mass=0.01,
                    velocity_damping_stiffness=12.0, friction_stiffness=0.6, integrator="symplectic",
                    friction=0.6, restitution=0.2)
    for _ in range(300):
        sim.step_frame()
        if sim.asleep().all():
            break
    assert sim.asleep().all(), f"the stack did not sleep in {sim.time:.1f} s"
    assert _agree(sim) >= 8, "few springs stretched: the test would prove little"
    x0 = sim.snapshot()["x"].copy()
    sim.wake(1)
    for _ in range(10):
        sim.step_frame()
        assert sim.asleep()[0], "the quiet box woke the sleeper below it"
        _agree(sim)
    sim.wake(0)
    for _ in range(10):
        sim.step_frame()
        _agree(sim)
    moved = np.linalg.norm(sim.snapshot()["x"] - x0, axis=1)
    assert moved.max() < 1e-3, f"the boxes moved {moved} m"
