"""Checks 1 and 2: linear momentum in free flight, angular momentum without torque (float64).

References: P(t) = P0 + M g t; the explicit-Euler parabola
x_n = x0 + v0 n Δt + g Δt² n(n−1)/2 (semi-implicit Euler: n(n+1)/2), which lies
|g| Δt t / 2 from the true parabola; L constant (gravity has no torque about
the centre of mass). Body: the T-handle, particle mass 0.7, tumbling.
"""
import pytest

import physics_results

physics_results.start()
ROUND_OFF = 1e-12  # float64, relative to the trajectory's scale, after ~1000 steps


@pytest.fixture(scope="module")
def fp64():
    return physics_results.results()


def test_free_fall_momentum_and_explicit_parabola(fp64):
    r = fp64["free_fall_euler"]
    assert r["momentum_error"] <= ROUND_OFF
    assert r["explicit_parabola_error"] <= ROUND_OFF
    # The two Euler parabolas differ by g Δt² n: this run tells explicit from semi-implicit.
    assert r["semi_implicit_parabola_error"] > 1e3 * ROUND_OFF
    # The true parabola within O(Δt): the offset is exactly |g| Δt t / 2.
    assert r["continuous_parabola_error"] == pytest.approx(r["continuous_bound"], rel=1e-6)


def test_free_fall_symplectic_follows_semi_implicit_parabola(fp64):
    r = fp64["free_fall_symplectic"]
    assert r["momentum_error"] <= ROUND_OFF
    assert r["semi_implicit_parabola_error"] <= ROUND_OFF
    assert r["explicit_parabola_error"] > 1e3 * ROUND_OFF


def test_angular_momentum_is_conserved_without_torque(fp64):
    """|L(t) − L0| / |L0| <= 1e-6 over 10 s, gravity on (no torque about the centre of mass)."""
    assert fp64["angular_momentum"]["L_drift"] <= 1e-6
