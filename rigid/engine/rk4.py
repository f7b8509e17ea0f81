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
The stages run in a loop (one copy of the wrench code), so compiling costs
about what explicit Euler's kernel costs.
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
        # k_j = f(Y + c_j Δt k_{j−1}) with c = (0, ½, ½, 1), summed with weights (1, 2, 2, 1) Δt/6.
        # A run-time loop over the stages, not four calls: the wrench (the particle loop) is
        # then compiled once, which keeps the kernel's compile time near explicit Euler's.
        dx, dq = ti.Vector.zero(float, 3), ti.Vector.zero(float, 4)
        dP, dL = ti.Vector.zero(float, 3), ti.Vector.zero(float, 3)
        sum_x, sum_q = ti.Vector.zero(float, 3), ti.Vector.zero(float, 4)
        sum_P, sum_L = ti.Vector.zero(float, 3), ti.Vector.zero(float, 3)
        for stage in range(4):
            c = 0.0
            weight = 2.0
            if stage == 1 or stage == 2:
                c = 0.5 * dt
            if stage == 3:
                c = dt
            if stage == 0 or stage == 3:
                weight = 1.0
            dx, dq, dP, dL = derivative(b, x + c * dx, q + c * dq, P + c * dP, L + c * dL)
            sum_x += weight * dx
            sum_q += weight * dq
            sum_P += weight * dP
            sum_L += weight * dL
        w = dt / 6.0
        q_new = q + w * sum_q
        store(b, x + w * sum_x, q_new / q_new.norm(), P + w * sum_P, L + w * sum_L)

    return substep
