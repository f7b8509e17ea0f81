"""The substep, built from the 7 TODO units, and the kernels that run whole frames.

``Integrator(model, state, params, units, scheme)`` compiles kernels that call
the TODO units (``units`` is any object with the 7 ``ti.func``s, e.g. the
module ``rigid_body_dynamic``); the engine never imports that module itself.

One substep, as on the slides (explicit Euler, scheme "euler"):
  for each particle i:  rᵢ = R r0ᵢ, pᵢ = x + rᵢ, vᵢ = v + ω × rᵢ
                        fᵢ = m g (TODO 2) + contact(pᵢ, vᵢ)
                        F += fᵢ (TODO 3),  τ += rᵢ × fᵢ (TODO 4)
  x, P ← x + Δt P/M, P + Δt F            (TODO 5, old P)
  q    ← normalise(q + Δt ½ [0, ω] ⊗ q)   (TODO 6, old ω)
  R    ← R(q)
  L, I⁻¹, ω ← L + Δt τ, R I0⁻¹ Rᵀ, I⁻¹ L  (TODO 7, new R)
Particle positions are never stored per substep: the force loop computes them
from (x, R), and ``write_particles`` stores them once per frame.

"symplectic" (semi-implicit Euler) updates P and L first, then moves x and q
with the new v and ω; it reuses the same units. "rk4" lives in rk4.py.
"""
import taichi as ti

from .contact import box_force
from .rotation import quaternion_to_matrix


class Integrator:
    def __init__(self, model, state, params, units, scheme: str = "euler"):
        self.model, self.state, self.params, self.scheme = model, state, params, scheme
        self._build(units)

    def _build(self, u):
        model, s, prm = self.model, self.state, self.params
        num_bodies = model.num_bodies
        scheme = self.scheme

        @ti.func
        def particle_force(b, p, pv):
            """Force on one particle of body b at world position p, velocity pv; and its elastic energy."""
            f = u.gravity_force(model.particle_mass[b], prm.gravity[None])
            energy = 0.0
            if prm.walls[None]:
                fc, energy = box_force(p, pv, prm.floor[None], prm.wall[None],
                                       prm.collision_stiffness[None],
                                       prm.velocity_damping_stiffness[None],
                                       prm.friction_stiffness[None])
                f += fc
            return f, energy

        @ti.func
        def body_wrench(b, x, R, v, omega):
            """Total force F (TODO 3) and torque τ about x (TODO 4) on body b, serial sum."""
            F = ti.Vector.zero(float, 3)
            tau = ti.Vector.zero(float, 3)
            start = model.body_start[b]
            for i in range(start, start + model.body_count[b]):
                r = R @ model.r0[i]
                p = x + r
                f, _ = particle_force(b, p, v + omega.cross(r))
                F += u.total_force_term(f)
                tau += u.torque_term(p, x, R, model.r0[i], f)
            return F, tau

        @ti.func
        def store(b, x, q, P, L):
            """Write the new state and its auxiliaries (R, I⁻¹, ω from TODO 7 with zero torque)."""
            R = quaternion_to_matrix(q)
            L_same, inertia_inv, omega = u.update_angular(L, ti.Vector.zero(float, 3), R,
                                                          model.inertia_body_inv[b], 0.0)
            s.x[b], s.q[b], s.P[b], s.L[b] = x, q, P, L_same
            s.v[b], s.R[b], s.inertia_inv[b], s.omega[b] = P / model.body_mass[b], R, inertia_inv, omega

        @ti.func
        def substep_euler(b, dt):
            x, q, P, L, R, omega = s.x[b], s.q[b], s.P[b], s.L[b], s.R[b], s.omega[b]
            M = model.body_mass[b]
            F, tau = body_wrench(b, x, R, P / M, omega)
            x_new, P_new = u.update_linear(x, P, F, M, dt)
            q_new = u.update_orientation(q, omega, dt)
            R_new = quaternion_to_matrix(q_new)
            L_new, inertia_inv, omega_new = u.update_angular(L, tau, R_new, model.inertia_body_inv[b], dt)
            s.x[b], s.q[b], s.P[b], s.L[b] = x_new, q_new, P_new, L_new
            s.v[b], s.R[b], s.inertia_inv[b], s.omega[b] = P_new / M, R_new, inertia_inv, omega_new

        @ti.func
        def substep_symplectic(b, dt):
            x, q, P, L, R, omega = s.x[b], s.q[b], s.P[b], s.L[b], s.R[b], s.omega[b]
            M = model.body_mass[b]
            zero = ti.Vector.zero(float, 3)
            F, tau = body_wrench(b, x, R, P / M, omega)
            _x, P_new = u.update_linear(x, P, F, M, dt)  # momenta first ...
            L_new, _i, omega_mid = u.update_angular(L, tau, R, model.inertia_body_inv[b], dt)
            x_new, _P = u.update_linear(x, P_new, zero, M, dt)  # ... then move with the new v, ω
            q_new = u.update_orientation(q, omega_mid, dt)
            store(b, x_new, q_new, P_new, L_new)

        substep = substep_symplectic if scheme == "symplectic" else substep_euler
        if scheme == "rk4":
            from .rk4 import make_rk4_substep

            substep = make_rk4_substep(model, s, body_wrench, store, u)

        @ti.func
        def write_particles_serial():
            for i in range(model.num_particles):
                b = model.particle_body[i]
                r = s.R[b] @ model.r0[i]
                s.particle_x[i] = s.x[b] + r
                s.particle_v[i] = s.v[b] + s.omega[b].cross(r)
            for k in range(model.num_surface):
                s.surface_x[k] = s.x[0] + s.R[0] @ model.surface_r0[k]

        @ti.kernel
        def advance_serial(n: ti.i32):
            # One launch, one thread: n substeps of every body, then the particles once.
            ti.loop_config(serialize=True)
            for _ in range(1):
                dt = prm.dt[None]
                for _step in range(n):
                    for b in range(num_bodies):
                        substep(b, dt)
                write_particles_serial()

        @ti.kernel
        def init_state(x0: ti.types.vector(3, float), v0: ti.types.vector(3, float),
                       w0: ti.types.vector(3, float)):
            ti.loop_config(serialize=True)
            for b in range(num_bodies):
                # At q = identity the world and body frames agree: L = I0 ω0.
                q = ti.Vector([1.0, 0.0, 0.0, 0.0])
                store(b, x0, q, model.body_mass[b] * v0, model.inertia_body[b] @ w0)
            write_particles_serial()

        @ti.kernel
        def contact_energy() -> float:
            # Elastic energy ½ k depth² stored in the contact springs, serial (fixed order).
            total = 0.0
            ti.loop_config(serialize=True)
            for i in range(model.num_particles):
                b = model.particle_body[i]
                _f, e = particle_force(b, s.particle_x[i], s.particle_v[i])
                total += e
            return total

        @ti.kernel
        def apply_impulse(i: ti.i32, J: ti.types.vector(3, float)):
            # An instantaneous impulse J (N s, world) at particle i: ΔP = J, ΔL = (R r0ᵢ) × J
            # about x; store() refreshes v, I⁻¹ and ω through TODO 7, as init_state does.
            ti.loop_config(serialize=True)
            for _ in range(1):
                b = model.particle_body[i]
                r = s.R[b] @ model.r0[i]
                store(b, s.x[b], s.q[b], s.P[b] + J, s.L[b] + r.cross(J))
            write_particles_serial()

        self.advance_serial = advance_serial
        self.init_state = init_state
        self.apply_impulse = apply_impulse
        self.contact_energy = contact_energy

    def advance(self, substeps: int):
        """Advance every body by ``substeps`` substeps in one kernel launch."""
        self.advance_serial(substeps)
