"""Classical fourth-order Runge–Kutta on the rigid body state Y = (x, q, P, L).

    Ẏ = f(Y):  ẋ = P / M,   q̇ = ½ [0, ω] ⊗ q,   Ṗ = F,   L̇ = τ
    with R = R(q/|q|), ω = R I0⁻¹ Rᵀ L (TODO 7's formula) and (F, τ) the body's
    wrench from gravity and contact, evaluated at every stage's (x, R, v, ω).
    k1 = f(Y), k2 = f(Y + Δt/2 k1), k3 = f(Y + Δt/2 k2), k4 = f(Y + Δt k3)
    Y ← Y + Δt/6 (k1 + 2 k2 + 2 k3 + k4), then q ← q / |q|.

Inside a step q is not renormalised (that would break the order); a stage's
rotation is built from q/|q|, which is the same smooth function on the exact
solution, where |q| = 1. Global error O(Δt⁴) for smooth forces; the penalty
contact is only piecewise smooth, so through a contact the order drops.
Four wrench evaluations per substep: four times the cost of explicit Euler.
"""
import taichi as ti

from .rotation import quaternion_multiplication, quaternion_to_matrix


def make_rk4_substep(model, state, body_wrench, store, units):
    """Return a ``ti.func`` ``substep(b, dt)`` advancing body b by one RK4 step.

    ``body_wrench(b, x, R, v, omega) -> (F, τ)`` (world frame, τ about x) and
    ``store(b, x, q, P, L)`` (writes the state and its auxiliaries) come from
    the integrator; ``units`` provides TODO 7 for ω = I⁻¹ L.
    """
    s = state

    @ti.func
    def derivative(b, x, q, P, L):
        """Time derivatives (ẋ, q̇, Ṗ, L̇) of the state at (x, q, P, L)."""
        R = quaternion_to_matrix(q / q.norm())
        zero = ti.Vector.zero(float, 3)
        _L, _inertia_inv, omega = units.update_angular(L, zero, R, model.inertia_body_inv[b], 0.0)
        v = P / model.body_mass[b]
        F, tau = body_wrench(b, x, R, v, omega)
        q_dot = 0.5 * quaternion_multiplication(ti.Vector([0.0, omega[0], omega[1], omega[2]]), q)
        return v, q_dot, F, tau

    @ti.func
    def substep(b, dt):
        x, q, P, L = s.x[b], s.q[b], s.P[b], s.L[b]
        h = 0.5 * dt
        dx1, dq1, dP1, dL1 = derivative(b, x, q, P, L)
        dx2, dq2, dP2, dL2 = derivative(b, x + h * dx1, q + h * dq1, P + h * dP1, L + h * dL1)
        dx3, dq3, dP3, dL3 = derivative(b, x + h * dx2, q + h * dq2, P + h * dP2, L + h * dL2)
        dx4, dq4, dP4, dL4 = derivative(b, x + dt * dx3, q + dt * dq3, P + dt * dP3, L + dt * dL3)
        w = dt / 6.0
        x_new = x + w * (dx1 + 2.0 * dx2 + 2.0 * dx3 + dx4)
        q_new = q + w * (dq1 + 2.0 * dq2 + 2.0 * dq3 + dq4)
        P_new = P + w * (dP1 + 2.0 * dP2 + 2.0 * dP3 + dP4)
        L_new = L + w * (dL1 + 2.0 * dL2 + 2.0 * dL3 + dL4)
        store(b, x_new, q_new / q_new.norm(), P_new, L_new)

    return substep
