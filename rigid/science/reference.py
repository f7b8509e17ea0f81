"""Ground truth from outside the simulator: closed forms and scipy, float64.

Used by the physics tests and scripts/validate.py to judge the simulator;
the engine never imports this module. Conventions as in the engine:
quaternions scalar first, ω world frame unless named ``omega_body``.
"""
from __future__ import annotations

import numpy as np

from ..engine.rotation import quaternion_multiplication_np, quaternion_to_matrix_np


def explicit_euler_free_fall(x0, v0, g, dt: float, n) -> np.ndarray:
    """x_n of explicit Euler under constant g: x0 + v0 n Δt + g Δt² n(n−1)/2; (len(n), 3)."""
    n = np.asarray(n, dtype=np.float64)[:, None]
    return np.asarray(x0) + np.asarray(v0) * n * dt + np.asarray(g) * dt * dt * n * (n - 1) / 2


def semi_implicit_free_fall(x0, v0, g, dt: float, n) -> np.ndarray:
    """x_n of semi-implicit (symplectic) Euler: x0 + v0 n Δt + g Δt² n(n+1)/2; (len(n), 3)."""
    n = np.asarray(n, dtype=np.float64)[:, None]
    return np.asarray(x0) + np.asarray(v0) * n * dt + np.asarray(g) * dt * dt * n * (n + 1) / 2


def torque_free_rotation(inertia_body, omega0, times, rtol: float = 1e-12):
    """Euler's equations I ω̇ = −ω × I ω in the body frame with q̇ = ½ q ⊗ [0, ω_body], q(0) = 1.

    inertia_body (3, 3) about the centre of mass; omega0 (3,) at t = 0, when the body and
    world frames agree; times (T,) increasing from >= 0. Returns (omega_world (T, 3),
    q (T, 4) scalar first, omega_body (T, 3)), from scipy's DOP853 at ``rtol``.
    """
    from scipy.integrate import solve_ivp

    inertia = np.asarray(inertia_body, dtype=np.float64)
    inertia_inv = np.linalg.inv(inertia)
    scale = float(np.linalg.norm(omega0))

    def rhs(_t, y):
        w, q = y[:3], y[3:]
        w_dot = inertia_inv @ (-np.cross(w, inertia @ w))
        q_dot = 0.5 * quaternion_multiplication_np(q, np.array([0.0, *w]))
        return np.concatenate([w_dot, q_dot])

    y0 = np.concatenate([np.asarray(omega0, dtype=np.float64), [1.0, 0.0, 0.0, 0.0]])
    times = np.asarray(times, dtype=np.float64)
    sol = solve_ivp(rhs, (0.0, float(times[-1])), y0, method="DOP853", t_eval=times,
                    rtol=rtol, atol=rtol * np.array([scale] * 3 + [1.0] * 4))
    omega_body = sol.y[:3].T
    q = sol.y[3:].T / np.linalg.norm(sol.y[3:].T, axis=1, keepdims=True)
    omega_world = np.einsum("tij,tj->ti", np.array([quaternion_to_matrix_np(qq) for qq in q]), omega_body)
    return omega_world, q, omega_body


def torque_free_period(principal_moments, omega_body0) -> float:
    """Period of ω_body(t) of a free rigid body (Landau & Lifshitz §37), from Jacobi's K(k).

    principal_moments (3,) in any order, distinct; omega_body0 (3,) along those axes.
    For a spin near the middle axis this is the time between two flips the same way
    (the middle component of ω changes sign twice per period).
    """
    from scipy.special import ellipk

    order = np.argsort(principal_moments)
    i1, i2, i3 = np.asarray(principal_moments, dtype=np.float64)[order]
    w = np.asarray(omega_body0, dtype=np.float64)[order]
    m2 = float(np.sum((np.array([i1, i2, i3]) * w) ** 2))  # |L|²
    e2 = float(np.sum(np.array([i1, i2, i3]) * w * w))  # 2 E
    if m2 < e2 * i2:  # the other side of the separatrix: swap the roles of axes 1 and 3
        i1, i3 = i3, i1
    rate = np.sqrt((i3 - i2) * (m2 - e2 * i1) / (i1 * i2 * i3))
    k2 = (i2 - i1) * (e2 * i3 - m2) / ((i3 - i2) * (m2 - e2 * i1))
    return float(4.0 * ellipk(k2) / rate)


def quaternion_distance(q, p) -> np.ndarray:
    """min(|q − p|, |q + p|) row by row: q and −q are the same rotation. (T, 4) -> (T,)."""
    q, p = np.atleast_2d(q), np.atleast_2d(p)
    return np.minimum(np.linalg.norm(q - p, axis=1), np.linalg.norm(q + p, axis=1))


def order_of_convergence(dts, errors) -> list[float]:
    """Observed orders log(e_i / e_{i+1}) / log(Δt_i / Δt_{i+1}) between successive Δt."""
    dts, errors = np.asarray(dts, dtype=np.float64), np.asarray(errors, dtype=np.float64)
    return list(np.log(errors[:-1] / errors[1:]) / np.log(dts[:-1] / dts[1:]))


def zero_crossings(t, y) -> np.ndarray:
    """Times where y(t) changes sign, linearly interpolated between samples."""
    t, y = np.asarray(t, dtype=np.float64), np.asarray(y, dtype=np.float64)
    idx = np.nonzero(np.signbit(y[:-1]) != np.signbit(y[1:]))[0]
    return t[idx] - y[idx] * (t[idx + 1] - t[idx]) / (y[idx + 1] - y[idx])
