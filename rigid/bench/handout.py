"""The benchmark's baseline: the handout's structure, the engine's physics.

Like the assignment's handout (its ``substep`` kernel): one kernel launch per
substep, driven by a Python loop over the frame's substeps; inside the kernel,
top-level (so parallel) loops over the particles: forces on every particle
(stored), F with atomics, τ with atomics, then one thread updates the body,
then a last loop stores every particle's position and velocity for the next
substep. The physics is the engine's: the same 7 TODO units, the same contact
(rigid.engine.contact: the box's five planes, on particle centres), explicit Euler. Only the structure differs, which is
what the benchmark measures: launches, tasks, per-substep particle stores.
The handout also runs Taichi with ``debug=True``, which makes it several times
slower again; the baseline here runs without it (one ti.init per process).

Kernels live in this file because Taichi needs kernel source on disk.
"""
import numpy as np
import taichi as ti

from rigid.engine.contact import box_force
from rigid.engine.rotation import quaternion_to_matrix


class HandoutLoop:
    """One body of particles ``r0`` (N, 3, body frame about the centre of mass), mass m each."""

    def __init__(self, r0: np.ndarray, particle_mass: float, units, config):
        u, n = units, len(r0)
        self.n = n
        fp = np.float64 if ti.lang.impl.current_cfg().default_fp == ti.f64 else np.float32
        r0_f = ti.Vector.field(3, float, shape=n)
        r0_f.from_numpy(np.asarray(r0, fp))
        px = ti.Vector.field(3, float, shape=n)  # particle positions, velocities, forces: every substep
        pv = ti.Vector.field(3, float, shape=n)
        pf = ti.Vector.field(3, float, shape=n)
        x, v, P, L, omega = (ti.Vector.field(3, float, shape=()) for _ in range(5))
        q = ti.Vector.field(4, float, shape=())
        R, inv0 = ti.Matrix.field(3, 3, float, shape=()), ti.Matrix.field(3, 3, float, shape=())
        F, tau = ti.Vector.field(3, float, shape=()), ti.Vector.field(3, float, shape=())
        mass, M = float(particle_mass), float(particle_mass) * n
        c = config
        inertia = particle_mass * ((r0 ** 2).sum() * np.eye(3) - r0.T @ r0)
        inv0[None] = np.linalg.inv(inertia).tolist()
        gravity = ti.Vector(list(c.gravity))
        k, kd, mu, floor, wall = (c.collision_stiffness, c.velocity_damping_stiffness,
                                  c.friction_stiffness, c.floor, c.wall)

        @ti.func
        def place_particles():
            for i in range(n):  # parallel: positions and velocities for the next substep and the drawing
                r = R[None] @ r0_f[i]
                px[i] = x[None] + r
                pv[i] = v[None] + omega[None].cross(r)

        @ti.kernel
        def substep(dt: float):
            for i in range(n):  # parallel: force on every particle, from last substep's positions
                fc, _e = box_force(px[i], pv[i], 0.0, floor, wall, k, kd, mu)
                pf[i] = u.gravity_force(mass, gravity) + fc
            for i in range(n):  # parallel, atomic: total force
                F[None] += u.total_force_term(pf[i])
            for i in range(n):  # parallel, atomic: total torque
                tau[None] += u.torque_term(px[i], x[None], R[None], r0_f[i], pf[i])
            for _ in range(1):  # one thread: explicit Euler on the body
                x[None], P[None] = u.update_linear(x[None], P[None], F[None], M, dt)
                q[None] = u.update_orientation(q[None], omega[None], dt)
                R[None] = quaternion_to_matrix(q[None])
                L[None], _i, omega[None] = u.update_angular(L[None], tau[None], R[None], inv0[None], dt)
                v[None] = P[None] / M
                F[None] = ti.Vector.zero(float, 3)
                tau[None] = ti.Vector.zero(float, 3)
            place_particles()

        @ti.kernel
        def place():
            place_particles()

        self._fields = dict(x=x, v=v, P=P, L=L, omega=omega, q=q, R=R, inv0=inv0, inertia=inertia, M=M)
        self._substep, self._place = substep, place
        self.dt, self.config = float(c.dt), c
        self.reset()

    def reset(self):
        """Back to the config's initial state (q = identity, so L = I0 ω0)."""
        f, c = self._fields, self.config
        position, velocity, angular_velocity = c.position, c.initial_velocity, c.initial_angular_velocity
        f["x"][None], f["v"][None], f["P"][None] = position, velocity, [f["M"] * a for a in velocity]
        f["q"][None] = [1.0, 0.0, 0.0, 0.0]
        f["R"][None] = np.eye(3).tolist()
        f["omega"][None] = angular_velocity
        f["L"][None] = (f["inertia"] @ np.asarray(angular_velocity)).tolist()
        self._place()

    def step_frame(self, substeps: int):
        for _ in range(substeps):  # the handout's Python loop: one launch per substep
            self._substep(self.dt)

    def position(self) -> np.ndarray:
        return self._fields["x"].to_numpy().astype(np.float64)
