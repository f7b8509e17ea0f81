"""Sleeping bodies (rigid.engine.sleep): a settled pile sleeps, is exactly at rest and costs no
motion; contact with a moving body, an impulse, a wake call or a parameter change wakes it;
momentum is conserved through a wake; with sleepers exactly at rest, sleeping changes no bit."""
import numpy as np
import pytest

from conftest import ASSETS

SPHERE = str(ASSETS / "sphere.obj")
# Spheres of 42 vertex particles (collision radius ~0.03 m at scale 0.15), light particles as in
# the shipped scenes: they settle in a few seconds.
SETTLING = dict(mesh=SPHERE, scale=0.15, particle_mass=0.01, velocity_damping_stiffness=12.0,
                friction_stiffness=0.4, integrator="symplectic", dt=1e-3)


def _row(sim):
    return sim.snapshot()


@pytest.fixture(scope="module")
def settled(sim_cache):
    """Eight spheres dropped on the floor, run until every one sleeps (at most 8 s)."""
    sim = sim_cache(count=8, position=(0.0, -0.8, 0.0), **SETTLING)
    for frame in range(480):
        sim.step_frame()
        if sim.asleep().all():
            break
    return sim


def test_a_settled_pile_falls_asleep_exactly_at_rest(settled):
    sim = settled
    assert sim.asleep().all(), f"{sim.asleep().sum()} of 8 asleep after {sim.time:.1f} s"
    row = _row(sim)
    assert np.all(row["P"] == 0) and np.all(row["L"] == 0) and np.all(row["v"] == 0) and np.all(row["omega"] == 0)
    assert row["kinetic_energy"] == 0.0
    block = sim.advance_frames(30)  # sleepers do not move, and their contact springs keep their energy
    assert np.all(block["x"] == row["x"][None]) and np.all(block["q"] == row["q"][None])
    assert np.all(block["potential_energy"] == block["potential_energy"][0])
    # (a block's energies come from the one-thread kernel, a snapshot's from another: round-off apart)
    assert abs(block["potential_energy"][0] - row["potential_energy"]) < 1e-6 * abs(row["potential_energy"])
    # resting on the floor: every centre above it by about a sphere's radius (0.15 m) or more
    assert np.all(row["x"][:, 1] > -1.0 + 0.1)


def test_the_window_draws_sleepers_greyer_and_the_toggle_restores_their_colours(settled):
    from rigid.view.render import SLEEP_GREY, SceneRenderer, body_palette

    sim = settled
    assert sim.asleep().all()
    renderer = SceneRenderer(sim, (64, 48), offscreen=True)
    m = sim.model
    palette = body_palette(m.num_bodies)[m.surface_body_np]
    renderer.draw()
    greyed = renderer.vertex_colors.to_numpy()
    np.testing.assert_allclose(greyed, 0.5 * palette + 0.5 * SLEEP_GREY, atol=1e-6)
    renderer.grey_sleepers = False  # the panel's checkbox
    renderer.draw()
    np.testing.assert_allclose(renderer.vertex_colors.to_numpy(), palette, atol=1e-6)


def test_a_grab_wakes_the_held_body_only(settled):
    sim = settled
    assert sim.asleep().all()
    held = 0
    particle = int(np.flatnonzero(sim.particle_bodies() == held)[0])
    sim.grab(particle, sim.particle_positions()[particle])  # held where it is: no pull
    assert not sim.asleep()[held] and sim.asleep()[held + 1:].all()
    sim.step_frame()  # the spring's upload is not a parameter change: the others sleep on
    assert sim.asleep()[held + 1:].all()
    sim.release()
    for _ in range(120):  # at rest, it falls asleep again (0.5 s), as the next tests expect
        sim.step_frame()
        if sim.asleep().all():
            break
    assert sim.asleep().all()


def test_a_kick_wakes_the_body_and_a_moving_body_wakes_the_sleepers_it_touches(settled):
    sim = settled
    assert sim.asleep().all()
    x = sim.snapshot()["x"]
    # the body farthest from the pile's middle, kicked at its centre towards the middle
    centre = x.mean(axis=0)
    b = int(np.argmax(np.linalg.norm(x - centre, axis=1)))
    towards = centre - x[b]
    towards[1] = 0.0
    towards /= np.linalg.norm(towards)
    mass = sim.model.body_mass_np[b]
    particles = sim.particle_positions()
    mine = np.flatnonzero(sim.particle_bodies() == b)
    i = mine[np.argmin(np.linalg.norm(particles[mine] - x[b], axis=1))]  # near its centre: little spin
    sim.apply_impulse(int(i), mass * 2.0 * towards)  # 2 m/s
    assert not sim.asleep()[b] and sim.asleep().sum() == 7
    woke = np.zeros(8, bool)
    for _ in range(60):
        sim.step_frame()
        woke |= ~sim.asleep()
    others = woke.copy()
    others[b] = False
    assert others.any(), "the kicked body hit no sleeper awake"


def test_wake_and_a_parameter_change_wake_every_body(settled):
    sim = settled
    for _ in range(600):
        if sim.asleep().all():
            break
        sim.step_frame()
    assert sim.asleep().all()
    sim.wake(3)
    assert sim.asleep().sum() == 7 and not sim.asleep()[3]
    for _ in range(60):  # back to sleep: nothing moves it
        sim.step_frame()
    assert sim.asleep().all()
    sim.params.friction_stiffness = 0.5  # a slider: every body wakes at the next step
    sim.step_frame()
    assert not sim.asleep().any()


def _free_space(sim_cache, sleep, settling=SETTLING):
    """Three spheres at rest in a row, 0.45 m apart (0.36 m wide with their particles' radius),
    and a fourth arriving at 1 m/s along the row, spinning (no gravity, no walls): the resting
    ones sleep at 0.5 s, before it arrives at ~0.85 s."""
    bodies = tuple(dict(position=(0.45 * k, 0.0, 0.0)) for k in range(3)) + (
        dict(position=(-1.2, 0.0, 0.0), initial_velocity=(1.0, 0.0, 0.0), initial_angular_velocity=(0.0, 0.0, 2.0)),)
    return sim_cache(bodies=bodies, gravity=(0.0, 0.0, 0.0), walls=False, sleep=sleep, **settling)


def test_momentum_through_a_wake_and_the_same_bits_as_without_sleeping(sim_cache):
    through_a_wake(sim_cache)


def through_a_wake(sim_cache, settling=SETTLING, each_frame=lambda sim: None):
    """The free-space row (``settling``'s spheres) with sleeping on and off: the resting spheres
    sleep, the arriving one wakes the first, total P and L are kept, and the runs are the same
    bits; ``each_frame(sim)`` checks the sleeping run after every frame."""
    on, off = _free_space(sim_cache, True, settling), _free_space(sim_cache, False, settling)
    start = on.snapshot()
    P0, L0 = start["P"].sum(axis=0), (np.cross(start["x"], start["P"]) + start["L"]).sum(axis=0)
    slept = False
    for _ in range(120):  # 2 s: the first hit after ~0.85 m travelled, then the chain
        on.step_frame()
        off.step_frame()
        slept |= bool(on.asleep()[:3].all())
        each_frame(on)
    assert slept, "the resting spheres never slept: the test would prove nothing"
    assert not off.asleep().any()
    a, b = on.snapshot(), off.snapshot()
    assert not on.asleep()[0], "the struck sphere stayed asleep"
    assert np.abs(a["v"][:3]).max() > 0.1, "the moving sphere hit nothing"
    P, L = a["P"].sum(axis=0), (np.cross(a["x"], a["P"]) + a["L"]).sum(axis=0)
    scale = np.abs(start["P"]).sum()
    np.testing.assert_allclose(P, P0, atol=1e-5 * scale)
    np.testing.assert_allclose(L, L0, atol=1e-5 * (scale + np.abs(start["L"]).sum()))
    # the sleepers were exactly at rest already (no force acts on them): the same bits either way
    for key in ("x", "q", "P", "L"):
        assert np.array_equal(a[key], b[key]), key


def test_sleep_false_never_sleeps_and_runs_repeat_bit_for_bit(sim_cache):
    runs = []
    for sleep in (True, True, False):
        sim = sim_cache(count=4, position=(0.0, -0.8, 0.0), sleep=sleep, **SETTLING)
        block = sim.advance_frames(120)
        runs.append((block, sim.asleep()))
    assert runs[0][1].any(), "nothing slept in 2 s"
    assert not runs[2][1].any()
    for key in ("x", "q", "P", "L", "kinetic_energy", "potential_energy"):
        assert np.array_equal(runs[0][0][key], runs[1][0][key]), key


@pytest.mark.parametrize("top", [1, 0])
def test_a_quiet_awake_body_rests_on_a_sleeper_whichever_slot_comes_first(sim_cache, top):
    """Two boxes of stack.toml, settled and asleep; the top one woken stays where it is, held by the
    sleeper below as by a floor, and wakes nothing (it is quiet). With top = 1 the sleeper's slots
    come first: each pair is evaluated at its lower slot's turn, so the one-thread sweep must visit
    a resting sleeper that an awake body has in its lists (pair_once.py); left out, the box would
    fall into the one below."""
    below, above = dict(position=(0.0, -0.898, 0.0)), dict(position=(0.02, -0.7077, 0.02))
    bodies = (below, above) if top == 1 else (above, below)
    sim = sim_cache(bodies=bodies, particles="volume", mesh=str(ASSETS / "box.obj"), scale=0.2, grid=5,
                    particle_mass=0.01, velocity_damping_stiffness=12.0, friction_stiffness=0.6,
                    integrator="symplectic")
    for _ in range(300):
        sim.step_frame()
        if sim.asleep().all():
            break
    assert sim.asleep().all(), f"the stack did not sleep in {sim.time:.1f} s"
    x0 = sim.snapshot()["x"][top].copy()
    sim.wake(top)
    for _ in range(20):
        sim.step_frame()
        assert sim.asleep()[1 - top], "the quiet box woke the sleeper below it"
    moved = np.linalg.norm(sim.snapshot()["x"][top] - x0)
    assert moved < 1e-3, f"the woken box moved {moved:.4f} m"
