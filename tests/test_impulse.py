"""Simulator.apply_impulse (the window's random kick) against rigid-body impulse laws, in numpy."""
import numpy as np


def _inertia_world(particles, x, m):
    """I = Σ m (rᵀr E − r rᵀ) about x, from world particle positions (numpy, independent of the engine)."""
    r = particles - x
    return m * (np.einsum("ij,ij", r, r) * np.eye(3) - r.T @ r)


def test_impulse_changes_momenta_by_J_and_r_cross_J(sim_cache):
    sim = sim_cache(particle_mass=2.5, gravity=(0, 0, 0), walls=False,  # the mass test_core builds
                    initial_velocity=(0.3, -0.1, 0.2), initial_angular_velocity=(1.0, -2.0, 0.5))
    for _ in range(5):  # a generic, rotated orientation
        sim.step_frame()
    before = {key: value[0] for key, value in sim.snapshot().items() if key not in ("t", "kinetic_energy", "potential_energy")}
    particles = sim.particle_positions()
    i, J = 7, np.array([0.4, 1.5, -0.9])
    sim.apply_impulse(i, J)
    after = {key: value[0] for key, value in sim.snapshot().items() if key not in ("t", "kinetic_energy", "potential_energy")}

    expected_L = before["L"] + np.cross(particles[i] - before["x"], J)
    np.testing.assert_allclose(after["P"], before["P"] + J, atol=1e-5)
    np.testing.assert_allclose(after["L"], expected_L, atol=1e-4)
    np.testing.assert_allclose(after["v"], after["P"] / sim.model.mass, atol=1e-5)
    inertia = _inertia_world(particles, before["x"], 2.5)
    np.testing.assert_allclose(after["omega"], np.linalg.solve(inertia, expected_L), rtol=1e-3, atol=1e-4)
    np.testing.assert_allclose(after["x"], before["x"])  # an impulse moves nothing by itself
    # the particle velocities follow: vᵢ = v + ω × rᵢ
    pv = sim.particle_velocities()[i]
    np.testing.assert_allclose(pv, after["v"] + np.cross(after["omega"], particles[i] - after["x"]),
                               rtol=1e-4, atol=1e-4)


def test_impulse_through_centre_of_mass_does_not_spin(sim_cache):
    sim = sim_cache(gravity=(0, 0, 0), walls=False)
    particles = sim.particle_positions()
    x = sim.snapshot()["x"][0]
    # the farthest particle, hit along its own offset from x: r × J = 0
    i = int(np.argmax(np.linalg.norm(particles - x, axis=1)))
    J = 2.0 * (particles[i] - x)
    sim.apply_impulse(i, J)
    np.testing.assert_allclose(sim.snapshot()["L"][0], 0, atol=1e-5)
    np.testing.assert_allclose(sim.snapshot()["P"][0], J, atol=1e-5)
