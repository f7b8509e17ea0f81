"""A body's update from its wrench (F, τ), built from TODO units 5, 6 and 7: the three schemes.

Every function works on body b of the packs it is given (``u`` the TODO units, ``model``
ModelArgs, ``state`` StateArgs, ``scratch`` ScratchArgs for RK4):

- ``store``: write x, q, P, L and the auxiliaries v = P/M, R = R(q), I⁻¹ and ω from TODO 7
  (with zero torque and Δt = 0, so a student's TODO 7 is what turns L into ω everywhere);
- ``euler_update`` (scheme "euler", the slides): x, P from the old P (TODO 5), q from the old
  ω (TODO 6), then L, I⁻¹, ω with the new R (TODO 7);
- ``symplectic_update`` ("symplectic", semi-implicit Euler): P and L first, then x and q move
  with the new v and ω (the same units, called in another order);
- RK4 ("rk4", classical fourth order on Y = (x, q, P, L), Ẏ = (P/M, ½ [0, ω] ⊗ q, F, τ)):
  ``rk4_begin`` keeps Y₀, each of the four stages evaluates the wrench at its state (the
  engine runs the whole force pipeline there: walls, pairs) and ``rk4_stage`` accumulates
  k_s and moves the state to Y₀ + c_{s+1} Δt k_s; ``rk4_finish`` sets Y = Y₀ + Δt/6 (k₁ + 2k₂ +
  2k₃ + k₄) and renormalises q. Inside a step q is not renormalised (that would break the
  order); a stage's rotation is built from q/|q|. Global error O(Δt⁴) for smooth forces; the
  penalty contact is only piecewise smooth, so through a contact the order drops.
- ``init_body``: the initial state; L = R I0 Rᵀ ω (ω in the world frame);
- ``impulse``: an impulse J (N s, world) at a particle: ΔP = J, ΔL = (R r0) × J.
"""
import taichi as ti

from .matvec import ZERO3, body_offset, cross, matvec
from .rotation import quaternion_multiplication, quaternion_to_matrix

RK4_NODES = (0.0, 0.5, 0.5, 1.0)  # c_s: stage s is evaluated at Y₀ + c_s Δt k_{s−1}
RK4_WEIGHTS = (1.0, 2.0, 2.0, 1.0)  # times Δt / 6


@ti.func
def store(u: ti.template(), model: ti.template(), state: ti.template(), b, x, q, P, L, R):
    L_same, inertia_inv, omega = u.update_angular(L, ZERO3, R, model.inertia_body_inv[b], 0.0)
    state.x[b], state.q[b], state.P[b], state.L[b] = x, q, P, L_same
    state.v[b], state.R[b], state.inertia_inv[b], state.omega[b] = P / model.body_mass[b], R, inertia_inv, omega


@ti.func
def euler_update(u: ti.template(), model: ti.template(), state: ti.template(), b, dt, F, tau):
    x, q, P, L, omega = state.x[b], state.q[b], state.P[b], state.L[b], state.omega[b]
    M = model.body_mass[b]
    x_new, P_new = u.update_linear(x, P, F, M, dt)
    q_new = u.update_orientation(q, omega, dt)
    R_new = quaternion_to_matrix(q_new)
    L_new, inertia_inv, omega_new = u.update_angular(L, tau, R_new, model.inertia_body_inv[b], dt)
    state.x[b], state.q[b], state.P[b], state.L[b] = x_new, q_new, P_new, L_new
    state.v[b], state.R[b], state.inertia_inv[b], state.omega[b] = P_new / M, R_new, inertia_inv, omega_new


@ti.func
def symplectic_update(u: ti.template(), model: ti.template(), state: ti.template(), b, dt, F, tau):
    x, q, P, L, R = state.x[b], state.q[b], state.P[b], state.L[b], state.R[b]
    M = model.body_mass[b]
    _x, P_new = u.update_linear(x, P, F, M, dt)  # momenta first ...
    L_new, _i, omega_mid = u.update_angular(L, tau, R, model.inertia_body_inv[b], dt)
    x_new, _P = u.update_linear(x, P_new, ZERO3, M, dt)  # ... then move with the new v, ω
    q_new = u.update_orientation(q, omega_mid, dt)
    store(u, model, state, b, x_new, q_new, P_new, L_new, quaternion_to_matrix(q_new))


@ti.func
def _pack13(x, q, P, L):
    return ti.Vector([x[0], x[1], x[2], q[0], q[1], q[2], q[3], P[0], P[1], P[2], L[0], L[1], L[2]])


@ti.func
def _store13(u: ti.template(), model: ti.template(), state: ti.template(), b, y):
    q = ti.Vector([y[3], y[4], y[5], y[6]])
    store(u, model, state, b, ti.Vector([y[0], y[1], y[2]]), q, ti.Vector([y[7], y[8], y[9]]),
          ti.Vector([y[10], y[11], y[12]]), quaternion_to_matrix(q / q.norm()))


@ti.func
def rk4_begin(state: ti.template(), scratch: ti.template(), b):
    scratch.rk[b] = _pack13(state.x[b], state.q[b], state.P[b], state.L[b])
    scratch.rk[state.x.shape[0] + b] = ti.Vector.zero(float, 13)


@ti.func
def rk4_weight(stage):
    """RK4_WEIGHTS[stage] for a constant or a run-time stage 0..3."""
    return RK4_WEIGHTS[0] if stage == 0 or stage == 3 else RK4_WEIGHTS[1]


@ti.func
def rk4_stage(u: ti.template(), model: ti.template(), state: ti.template(), scratch: ti.template(), b, dt,
              F, tau, stage):
    """k_s = Ẏ at the current (stage) state with wrench (F, τ); accumulate it; move to the next
    stage. ``stage`` 0..3, a constant or a run-time loop index (the weights and nodes are exact)."""
    w = state.omega[b]
    q_dot = 0.5 * quaternion_multiplication(ti.Vector([0.0, w[0], w[1], w[2]]), state.q[b])
    k = _pack13(state.v[b], q_dot, F, tau)
    weight = rk4_weight(stage)
    scratch.rk[state.x.shape[0] + b] += weight * k
    if stage < 3:
        node = RK4_NODES[1] if stage < 2 else RK4_NODES[3]  # c_{s+1}
        _store13(u, model, state, b, scratch.rk[b] + (node * dt) * k)


@ti.func
def rk4_finish(u: ti.template(), model: ti.template(), state: ti.template(), scratch: ti.template(), b, dt):
    y = scratch.rk[b] + (dt / 6.0) * scratch.rk[state.x.shape[0] + b]
    q = ti.Vector([y[3], y[4], y[5], y[6]])
    q = q / q.norm()
    store(u, model, state, b, ti.Vector([y[0], y[1], y[2]]), q, ti.Vector([y[7], y[8], y[9]]),
          ti.Vector([y[10], y[11], y[12]]), quaternion_to_matrix(q))


@ti.func
def init_body(u: ti.template(), model: ti.template(), state: ti.template(), b, x, q, v, omega):
    # L = I ω with I = R I0 Rᵀ; at q = identity R is exactly I, so L = I0 ω bit for bit.
    R = quaternion_to_matrix(q)
    L = matvec(R, matvec(model.inertia_body[b], matvec(R.transpose(), omega)))
    store(u, model, state, b, x, q, model.body_mass[b] * v, L, R)


@ti.func
def impulse(u: ti.template(), model: ti.template(), state: ti.template(), i, J):
    b = model.particle_body[i]
    r = matvec(state.R[b], body_offset(model, i))
    store(u, model, state, b, state.x[b], state.q[b], state.P[b] + J, state.L[b] + cross(r, J), state.R[b])
