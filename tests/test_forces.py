"""Forces through the seam (rigid.engine.forces), against closed forms.

- drag: a body falling with f = −c vᵢ on each particle reaches v(t) = v_t (1 − e^{−c t / m}),
  v_t = m g / c (m: a particle's mass), within 1 %;
- a spring from a world point to a body's centre of mass: vertical oscillation of period
  2π √(M / k) within 1 %;
- the mouse's grab moves a body in a scene with materials (restitution), as in one without;
- a [[spring]] table's bad values: one line each, before anything is built.
The two-body spring's conservation of P and L is in test_many_bodies.py (float64 worker).
"""
import numpy as np
import pytest

from conftest import ASSETS

SPHERE = dict(mesh=str(ASSETS / "sphere.obj"), scale=0.3, walls=False)


def _sim(units, **values):
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    return Simulator(SimConfig(**{**SPHERE, **values}).validate(), units)


def test_linear_drag_reaches_the_terminal_velocity_as_an_exponential(units):
    m, c, g = 1.0, 1.0, 9.8  # time constant m / c = 1 s
    rows = _sim(units, particle_mass=m, drag=c).advance_frames(150)
    t, v = rows["t"], rows["v"][:, 0, 1]
    expected = -(m * g / c) * (1.0 - np.exp(-c * t / m))
    late = t > 0.2  # past the first frames, where both are near zero
    assert t[-1] > 2.0 * m / c, "the fall should last two time constants"
    np.testing.assert_allclose(v[late], expected[late], rtol=0.01)
    assert 0.85 < abs(v[-1]) / (m * g / c) < 0.95, "near the terminal speed, still short of it"


def test_a_body_on_a_spring_to_a_world_point_oscillates_with_the_closed_form_period(units):
    m, k = 0.1, 200.0
    spring = dict(bodies=[-1, 0], points=[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], stiffness=k, rest_length=0.0)
    sim = _sim(units, particle_mass=m, springs=(spring,))
    M = m * sim.num_particles
    rows = sim.advance_frames(200)
    t, y = rows["t"], rows["x"][:, 0, 1]
    first = t < 2 * np.pi * np.sqrt(M / k)  # the first period (explicit Euler's gain: ~1 % by its trough)
    assert y[first].min() == pytest.approx(-2 * M * 9.8 / k, rel=0.02), "released at rest, it sinks to twice the sag"
    centred = y + M * 9.8 / k
    up = np.where((centred[:-1] < 0) & (centred[1:] >= 0))[0]
    crossings = t[up] - centred[up] * (t[up + 1] - t[up]) / (centred[up + 1] - centred[up])
    assert len(crossings) >= 3
    period = np.diff(crossings).mean()
    assert period == pytest.approx(2 * np.pi * np.sqrt(M / k), rel=0.01)
    assert np.abs(rows["x"][:, 0, [0, 2]]).max() < 1e-6, "pulled at its centre: no sideways motion"


def test_the_grab_moves_a_body_in_a_scene_with_materials(units):
    from rigid.config import SimConfig, load_scene
    from rigid.engine.simulator import Simulator

    sim = Simulator(SimConfig(**load_scene(ASSETS / "scenes" / "bounce.toml")).validate(), units)
    sim.advance_frames(20)  # the balls land
    x0 = sim.snapshot()["x"][0].copy()
    particle = 0  # ball 0's first particle: mesh files' order, body by body
    sim.grab(particle, sim.particle_positions()[particle] + np.array([0.0, 0.6, 0.0]))
    sim.advance_frames(30)
    lift = sim.snapshot()["x"][0] - x0
    assert lift[1] > 0.3, f"the held ball rose {lift[1]:.3f} m toward a target 0.6 m up"


@pytest.mark.parametrize("table, message", [
    (dict(bodies=[0, 5], points=[[0, 0, 0], [0, 0, 0]], stiffness=1.0), "body 5 does not exist: the scene has 1 bodies"),
    (dict(bodies=[-1, 0], points=[[0, 0, 0], [0, 0, 0]], stiffness=-3.0), "stiffness = -3.0; use a number >= 0"),
    (dict(bodies=[-1, 0], points=[[0, 0, 0]], stiffness=1.0), "give two points, one for each end"),
    (dict(bodies=[-1, 0], points=[[0, 0, 0], [0, 0, 0]]), "no 'stiffness'"),
    (dict(bodies=[0, 0], points=[[0, 0, 0], [0, 0, 0]], stiffness=1.0), "both ends are on body 0"),
])
def test_bad_spring_tables_are_one_line_each(units, table, message):
    from rigid.errors import UserError

    with pytest.raises(UserError, match=message) as err:
        _sim(units, springs=(table,))
    assert "\n" not in str(err.value) and str(err.value).startswith("[[spring]] 1:")


def test_springs_are_drawn_as_lines_between_their_ends(units):
    from rigid.view.render import SceneRenderer

    # A sphere hung 0.3 m below a hook by a spring: the hook and the top of the sphere, in the world.
    spring = dict(bodies=[-1, 0], points=[[0.0, 0.6, 0.0], [0.0, 0.3, 0.0]], stiffness=50.0)
    sim = _sim(units, particle_mass=0.01, springs=(spring,), walls=True)
    np.testing.assert_allclose(sim.spring_ends(), [[0.0, 0.6, 0.0], [0.0, 0.3, 0.0]], atol=1e-6)
    renderer = SceneRenderer(sim, (160, 120), offscreen=True)
    renderer.draw()
    with_spring = renderer.read_rgba()[..., :3].astype(int)
    renderer._scene_springs = None
    renderer.draw()
    without = renderer.read_rgba()[..., :3].astype(int)
    changed = np.abs(with_spring - without).sum(axis=-1) > 30
    assert 3 <= changed.sum() < 0.02 * changed.size, "a thin line, somewhere"
    assert with_spring[changed].mean() < without[changed].mean(), "drawn darker than what lies behind it"
