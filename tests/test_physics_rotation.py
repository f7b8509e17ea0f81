"""Checks 7 and 8: the quaternion stays a rotation; a symmetric drop stays symmetric.

The float32 bounds are round-off: a float32 quaternion normalised every substep has
| |q| − 1 | of a few ulps (6e-8 each), and R(q) then has ‖RᵀR − E‖₂ = | |q|⁴ − 1 | plus
the rounding of its entries, ~10 ulps; 1e-6 is 17 ulps.
"""
import physics_results

physics_results.start()


def test_quaternion_stays_unit_every_frame_float64():
    for name in ("angular_momentum", "drop"):  # 10 s tumbling in flight; 3 s of bounces
        r = physics_results.results()[name]
        assert r["q_norm_error"] <= 1e-12 and r["orthonormality_error"] <= 1e-12, (name, r)


def test_quaternion_stays_unit_every_frame_float32(sim_cache):
    """The handout's sphere thrown spinning into the box, 3 s of bounces, every frame."""
    from rigid.science import experiments as ex

    sim = sim_cache(initial_velocity=(3.0, 2.0, -2.0), initial_angular_velocity=(2.0, 7.0, 1.0))
    health = ex.rotation_health(ex.record(sim, 180, sim.substeps))
    assert health["q_norm_error"] <= 1e-6
    assert health["orthonormality_error"] <= 1e-6


def test_symmetric_drop_stays_on_its_vertical_line_without_spin():
    """The handout's sphere, volume-sampled at 10 cells (432 particles), dropped from rest at
    (0.3, 0.2, −0.2), off the box's centre: bounces and comes to rest in 3 s (float64).

    Why volume particles: with its 42 vertices the sphere lands on a single vertex (the
    icosphere has one at (0, −1, 0)), an unstable balance, and round-off tips it over
    (float32: it rolls 8 cm within 3 s; float64: its spin grows from 1e-14 to 1e-9 rad/s).
    That is physics, not a bug. The grid sphere rests on a flat layer of cells: a stable
    rest, so any drift or spin must come from the simulator (an asymmetric sum, a torque
    taken about the world origin instead of the centre of mass, ...).
    """
    r = physics_results.results()["drop"]
    assert r["lowest_y"] < -0.6  # it did reach the floor (y = −1; radius 0.3)
    assert r["max_horizontal_drift"] <= 1e-9  # m
    assert r["max_spin"] <= 1e-6  # rad/s, at the impacts (float64 round-off times stiff springs)
    assert r["final_spin"] <= 1e-12
