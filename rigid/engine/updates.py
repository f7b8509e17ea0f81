"""A body's update from its wrench, built from TODO units 5, 6 and 7; shared by every path.

``make_updates(model, state, units)`` returns ``ti.func``s of a body index b:
- ``store(b, x, q, P, L)``: write the state and its auxiliaries (v = P/M, R = R(q),
  I⁻¹ and ω from TODO 7 with zero torque and Δt = 0);
- ``euler_update(b, dt, F, τ)``: explicit Euler as on the slides: x, P from the
  old P (TODO 5), q from the old ω (TODO 6), then L, I⁻¹, ω with the new R (TODO 7);
- ``symplectic_update(b, dt, F, τ)``: semi-implicit Euler: P and L first, then x
  and q move with the new v and ω (the same units, called in another order);
- ``init_body(b, x, q, v, ω)``: the initial state; L = R I0 Rᵀ ω (ω in the world frame);
- ``impulse(i, J)``: an instantaneous impulse J (N s, world) at particle i of its body:
  ΔP = J, ΔL = (R r0ᵢ) × J about x; v, I⁻¹ and ω refreshed through TODO 7.
"""
import taichi as ti

from .matvec import matvec
from .rotation import quaternion_to_matrix


def make_updates(model, state, units):
    s, u = state, units

    @ti.func
    def store(b, x, q, P, L):
        R = quaternion_to_matrix(q)
        L_same, inertia_inv, omega = u.update_angular(L, ti.Vector.zero(float, 3), R,
                                                      model.inertia_body_inv[b], 0.0)
        s.x[b], s.q[b], s.P[b], s.L[b] = x, q, P, L_same
        s.v[b], s.R[b], s.inertia_inv[b], s.omega[b] = P / model.body_mass[b], R, inertia_inv, omega

    @ti.func
    def euler_update(b, dt, F, tau):
        x, q, P, L, omega = s.x[b], s.q[b], s.P[b], s.L[b], s.omega[b]
        M = model.body_mass[b]
        x_new, P_new = u.update_linear(x, P, F, M, dt)
        q_new = u.update_orientation(q, omega, dt)
        R_new = quaternion_to_matrix(q_new)
        L_new, inertia_inv, omega_new = u.update_angular(L, tau, R_new, model.inertia_body_inv[b], dt)
        s.x[b], s.q[b], s.P[b], s.L[b] = x_new, q_new, P_new, L_new
        s.v[b], s.R[b], s.inertia_inv[b], s.omega[b] = P_new / M, R_new, inertia_inv, omega_new

    @ti.func
    def symplectic_update(b, dt, F, tau):
        x, q, P, L, R = s.x[b], s.q[b], s.P[b], s.L[b], s.R[b]
        M = model.body_mass[b]
        zero = ti.Vector.zero(float, 3)
        _x, P_new = u.update_linear(x, P, F, M, dt)  # momenta first ...
        L_new, _i, omega_mid = u.update_angular(L, tau, R, model.inertia_body_inv[b], dt)
        x_new, _P = u.update_linear(x, P_new, zero, M, dt)  # ... then move with the new v, ω
        q_new = u.update_orientation(q, omega_mid, dt)
        store(b, x_new, q_new, P_new, L_new)

    @ti.func
    def init_body(b, x, q, v, omega):
        # L = I ω with I = R I0 Rᵀ; at q = identity R is exactly I, so L = I0 ω bit for bit.
        R = quaternion_to_matrix(q)
        L = matvec(R, matvec(model.inertia_body[b], matvec(R.transpose(), omega)))
        store(b, x, q, model.body_mass[b] * v, L)

    @ti.func
    def impulse(i, J):
        b = model.particle_body[i]
        r = matvec(s.R[b], model.r0[i])
        store(b, s.x[b], s.q[b], s.P[b] + J, s.L[b] + r.cross(J))

    return store, euler_update, symplectic_update, init_body, impulse
