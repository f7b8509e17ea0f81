"""Grabbing a body with the mouse: the engine's spring (closed form after one substep), and the
window's picking and dragging driven by a simulated mouse (no window: the camera's rays only)."""
import numpy as np


def test_the_grab_spring_is_a_particle_force_through_todo_3_and_4(sim_cache):
    """After one explicit Euler substep from rest in free space: ΔP = f Δt and ΔL = r × f Δt with
    f = k (target − p) − c v_p (v_p = 0 at rest), r the particle's arm: the force went through the
    particle sums, with its torque."""
    sim = sim_cache(walls=False, gravity=(0.0, 0.0, 0.0))
    p0, x0 = sim.particle_positions()[5], sim.snapshot()["x"][0]
    target = p0 + np.array([1.0, 0.5, -0.25])
    sim.grab(5, target, stiffness=100.0, damping=3.0)
    assert sim.grabbed == 5
    sim.step_frame(substeps=1)
    snap, dt = sim.snapshot(), float(sim.params.dt)
    f = 100.0 * (target - p0)
    np.testing.assert_allclose(snap["P"][0], f * dt, rtol=1e-5)
    np.testing.assert_allclose(snap["L"][0], np.cross(p0 - x0, f) * dt, rtol=1e-4, atol=1e-8)
    sim.release()
    assert sim.grabbed is None
    before = sim.snapshot()
    sim.step_frame()
    np.testing.assert_allclose(sim.snapshot()["P"], before["P"], rtol=1e-6)  # let go: no force, P constant
    sim.grab(5, target)
    sim.reset()  # a reset lets go too
    assert sim.grabbed is None


def _screen(orbit, size, point):
    """Where a world point is drawn, in cursor coordinates ([0, 1]², y up): the pinhole of raster.py."""
    eye = np.asarray(orbit.position())
    forward = np.asarray(orbit.target) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rel = np.asarray(point) - eye
    tan = np.tan(np.radians(orbit.fov) / 2)
    depth = rel @ forward
    return 0.5 + 0.5 * (rel @ right) / (depth * tan * size[0] / size[1]), 0.5 + 0.5 * (rel @ up) / (depth * tan)


def test_a_simulated_mouse_drags_the_body_toward_the_cursor_and_release_lets_go(sim_cache):
    from rigid.view.grab import MouseGrab
    from rigid.view.orbit import OrbitCamera

    sim = sim_cache()  # the sphere, in the box, under gravity
    sim.advance_frames(40)  # fallen onto the floor
    size, orbit = (640, 360), OrbitCamera()
    mouse = MouseGrab(sim, orbit, size)
    assert not mouse.track((0.02, 0.02), True) and mouse.particle is None  # a press on the floor's corner: a miss
    mouse.track((0.02, 0.02), False)
    x0 = sim.snapshot()["x"][0]
    cursor = _screen(orbit, size, x0)
    assert mouse.track(cursor, True)  # pressed on the body: held
    held, grabbed_at = mouse.particle, mouse.target.copy()
    assert sim.grabbed == held and np.linalg.norm(grabbed_at - x0) < 0.35  # on the sphere (radius 0.3)
    # Drag up and to the right of the picture; hold it there for a second.
    goal = (cursor[0] + 0.12, cursor[1] + 0.15)
    start_gap = None
    for step in range(60):
        mouse.track(goal, True)
        if start_gap is None:
            start_gap = np.linalg.norm(sim.particle_positions()[held] - mouse.target)
        sim.step_frame()
    gap = np.linalg.norm(sim.particle_positions()[held] - mouse.target)
    x1 = sim.snapshot()["x"][0]
    on_screen = _screen(orbit, size, sim.particle_positions()[held])
    assert gap < 0.3 * start_gap, (gap, start_gap)  # the spring pulled it (2 Hz: a second is two periods)
    assert x1[1] > x0[1] + 0.2  # lifted off the floor
    assert abs(on_screen[0] - goal[0]) < 0.05 and abs(on_screen[1] - goal[1]) < 0.05  # under the cursor
    assert np.dot(mouse.target - mouse.plane_point, mouse.plane_normal) < 1e-9  # dragged in the grab plane
    mouse.track(goal, False)  # released
    assert mouse.particle is None and sim.grabbed is None
    from rigid.engine.grab import GRAB_SLOT

    assert sim.params.values.to_numpy()[GRAB_SLOT] == -1.0  # the engine's grab slot is empty
    for _ in range(40):
        sim.step_frame()
    assert sim.snapshot()["x"][0][1] < x1[1] - 0.1  # it falls again
    press_on_panel = (0.85, 0.8)
    assert not mouse.track(press_on_panel, True) and mouse.particle is None  # the panel's, not a grab
