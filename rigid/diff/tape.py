"""The fields of the differentiable pass: state with a step axis, parameters, rows.

Taichi's reverse mode differentiates a kernel only if it never overwrites what it read (the
global data access rule), so the state is time-indexed: substep s reads step s and writes step
s + 1 (as DiffTaichi's rigid_body.py keeps x[t], v[t]). One segment of K frames is held
(``steps`` = K · substeps + 1: the whole run where it fits the pass's budget); the pass keeps a
checkpoint at each segment's start on the host and runs a segment forward again before its
backward (rigid.diff.passes), so memory is bounded by K, not by the horizon. Shapes (f the run's float; B bodies, N particles, P planes):

  x, P, L, w    [steps, B] vec3   centre of mass (m), momenta (kg m/s, kg m²/s), ω (rad/s), world
  q             [steps, B] vec4   orientation, scalar first
  F, T          [steps, B] vec3   the substep's force and torque about x (atomic sums over particles)
  fc            [steps, N, P] vec3  each plane's force on each particle (written for the pairs near)
  slip          [steps, N, P] vec3  each (particle, plane) sticking spring (materials' law only; see spring)
  count         [steps, B] i32    particles touching a plane before the forces (m_eff = M / n)
  near          [steps, N, P] u8  whether the particle's sphere is within its radius of the plane
  pairs, pair_count  [steps, N P], [steps] i32  the pairs near, listed (i P + j), and their count
  rows          r_x, r_q, r_v, r_w, r_P, r_L  [frames + 1, B]  the rows rigid.Simulator.advance gives
Parameters (all with gradients): per body m (particle mass), drag, e_b, mu_b, x0, q0, v0, w0;
per plane e_p, mu_p; k, c_world (velocity_damping_stiffness), mu_world, g. Derived (with
gradients): M = m n, I0 = Σ TODO 1, I0inv.
"""

import numpy as np
import taichi as ti

from .transfers import ROW_COLUMNS, copier, layout, padded, row_kernels

STATE = ("x", "q", "P", "L", "w")


class Tape:
    def __init__(self, steps: int, bodies: int, particles: int, planes: int, frames: int, table: int,
                 materials: bool):
        self.steps, self.bodies, self.particles, self.planes = steps, bodies, particles, planes
        self.frames, self.materials = frames, materials
        # The adjoints of what a kernel stores (fc, slip past step 0, the rows) are zero after a
        # whole backward: each store's adjoint consumes what it reads (rigid.diff.passes).
        self.clean = True
        f = ti.lang.impl.current_cfg().default_fp
        self.float = f
        vec = lambda n, shape: ti.Vector.field(n, f, shape=shape, needs_grad=True)
        sb = (steps, bodies)
        self.x, self.P, self.L, self.w, self.F, self.T = (vec(3, sb) for _ in range(6))
        self.q = vec(4, sb)
        self.slip = vec(3, (steps, particles, planes) if materials else (1, 1, 1))
        self.fc = vec(3, (steps, particles, planes))
        self.count = ti.field(ti.i32, shape=sb)
        self.near = ti.field(ti.u8, shape=(steps, particles, planes))
        self.pairs = ti.field(ti.i32, shape=(steps, particles * planes))  # i P + j of the pairs near
        self.pair_count = ti.field(ti.i32, shape=steps)
        scalar = lambda shape: ti.field(f, shape=shape, needs_grad=True)
        self.m, self.drag, self.e_b, self.mu_b, self.M = (scalar(bodies) for _ in range(5))
        self.x0, self.v0, self.w0 = (vec(3, bodies) for _ in range(3))
        self.q0 = vec(4, bodies)
        self.I0 = ti.Matrix.field(3, 3, f, shape=bodies, needs_grad=True)
        self.I0inv = ti.Matrix.field(3, 3, f, shape=bodies, needs_grad=True)
        self.e_p, self.mu_p = scalar(planes), scalar(planes)
        self.k, self.c_world, self.mu_world = scalar(()), scalar(()), scalar(())
        self.g = vec(3, ())
        # Fixed data (no gradients).
        self.r0 = ti.Vector.field(3, f, shape=particles)  # the collision spheres' centres
        self.r0_mass = ti.Vector.field(3, f, shape=particles)  # the particles themselves (TODO 1)
        self.particle_body = ti.field(ti.i32, shape=particles)
        self.body_count = ti.field(ti.i32, shape=bodies)
        self.radius = ti.field(f, shape=bodies)
        self.plane = ti.Vector.field(4, f, shape=planes)
        self.table = ti.field(f, shape=table)
        # Rows of the whole horizon (small: 19 numbers a body a frame).
        rb = (frames + 1, bodies)
        self.r_x, self.r_v, self.r_w, self.r_P, self.r_L = (vec(3, rb) for _ in range(5))
        self.r_q = vec(4, rb)
        # A checkpoint's state and a carried adjoint, one step's worth.
        self.c_x, self.c_P, self.c_L, self.c_w = (ti.Vector.field(3, f, shape=bodies) for _ in range(4))
        self.c_q = ti.Vector.field(4, f, shape=bodies)
        self.c_slip = ti.Vector.field(3, f, shape=(particles, planes) if materials else (1, 1))
        self._build_checkpoints()

    def _build_checkpoints(self) -> None:
        """``spring`` (a func: the sticking spring contacts reads) and the kernels that move a
        segment's first step to and from the checkpoint fields (c_*): save, restore, save_grad
        (the adjoint carried to the previous segment), restore_grad."""
        t, P, materials = self, self.planes, self.materials

        @ti.func
        def spring(s, i, j):
            # Pair (i, j)'s spring at step s: contacts writes it at s - 1 only where the pair was
            # near, and it is zero elsewhere; step 0's is a run's start (zero) or a checkpoint's.
            slip = ti.Vector.zero(float, 3)
            if s == 0:
                slip = t.slip[s, i, j]
            elif t.near[s - 1, i, j] != 0:
                slip = t.slip[s, i, j]
            return slip

        @ti.kernel
        def save(s: ti.i32, nb: ti.i32, n: ti.i32):
            for b in range(nb):
                t.c_x[b], t.c_q[b], t.c_P[b], t.c_L[b], t.c_w[b] = t.x[s, b], t.q[s, b], t.P[s, b], t.L[s, b], t.w[s, b]
            if ti.static(materials):
                for i, j in ti.ndrange(n, P):
                    t.c_slip[i, j] = spring(s, i, j)

        @ti.kernel
        def restore(s: ti.i32, nb: ti.i32, n: ti.i32):
            for b in range(nb):
                t.x[s, b], t.q[s, b], t.P[s, b], t.L[s, b], t.w[s, b] = t.c_x[b], t.c_q[b], t.c_P[b], t.c_L[b], t.c_w[b]
            if ti.static(materials):
                for i, j in ti.ndrange(n, P):
                    t.slip[s, i, j] = t.c_slip[i, j]

        @ti.kernel
        def save_grad(s: ti.i32, nb: ti.i32, n: ti.i32):
            for b in range(nb):
                t.c_x[b], t.c_q[b], t.c_P[b] = t.x.grad[s, b], t.q.grad[s, b], t.P.grad[s, b]
                t.c_L[b], t.c_w[b] = t.L.grad[s, b], t.w.grad[s, b]
            if ti.static(materials):
                for i, j in ti.ndrange(n, P):
                    t.c_slip[i, j] = t.slip.grad[s, i, j]

        @ti.kernel
        def restore_grad(s: ti.i32, nb: ti.i32, n: ti.i32):
            for b in range(nb):
                t.x.grad[s, b], t.q.grad[s, b], t.P.grad[s, b] = t.c_x[b], t.c_q[b], t.c_P[b]
                t.L.grad[s, b], t.w.grad[s, b] = t.c_L[b], t.c_w[b]
            if ti.static(materials):
                for i, j in ti.ndrange(n, P):
                    if t.near[s - 1, i, j] != 0:  # s > 0; a spring not near at s - 1 was zero: no adjoint
                        t.slip.grad[s, i, j] = t.c_slip[i, j]

        self.spring, self.save, self.restore, self.save_grad, self.restore_grad = \
            spring, save, restore, save_grad, restore_grad

    PARAMETERS = ("m", "drag", "e_b", "mu_b", "x0", "q0", "v0", "w0", "e_p", "mu_p", "k", "c_world", "mu_world", "g")
    DERIVED = ("M", "I0", "I0inv")

    def row_fields(self):
        return dict(x=self.r_x, q=self.r_q, v=self.r_v, omega=self.r_w, P=self.r_P, L=self.r_L)

    FIXED = ("r0", "r0_mass", "particle_body", "body_count", "radius", "plane", "table")
    CHECKPOINT = ("c_x", "c_q", "c_P", "c_L", "c_w", "c_slip")

    def load(self, problem) -> None:
        """The problem's fixed data and parameter values into the fields (padded past B, N, P)."""
        planes = np.zeros((self.planes, 4))
        planes[:] = (0.0, 1.0, 0.0, -1e30)  # stand-ins no particle is behind
        planes[:len(problem.planes)] = problem.planes
        values = dict(plane=planes, **{name: padded(getattr(self, name), getattr(problem, name))
                                       for name in self.FIXED if name != "plane"})
        for name, value in problem.values.items():
            field = getattr(self, name)
            fill = -1.0 if name in ("e_p", "mu_p") else (1.0 if name == "m" else 0.0)
            values[name] = np.asarray(value, np.float64) if field.shape == () else padded(field, value, fill)
        self._transfers()["load"](np.concatenate([np.ravel(values[name]) for name in self.FIXED + self.PARAMETERS]))

    def checkpoint(self) -> np.ndarray:
        """The checkpoint fields (c_*: a segment's first state, or the adjoint carried), flat."""
        out = np.zeros(self._transfers()["checkpoint_size"])
        self._transfers()["checkpoint_out"](out)
        return out

    def set_checkpoint(self, flat: np.ndarray) -> None:
        self._transfers()["checkpoint_in"](flat)

    def clear_parameter_grads(self) -> None:
        self._transfers()["zero"]()

    def seed(self, cotangents: dict, frames: int, bodies: int) -> None:
        """∂L/∂rows into the rows' adjoints (frames 0 .. frames; the rest stay zero: the rows'
        adjoint consumes what it reads)."""
        rows = np.zeros((frames + 1, bodies, 19))
        for key, (a, b) in ROW_COLUMNS.items():
            if key in cotangents:
                rows[:, :, a:b] = cotangents[key]
        self._transfers()["seed"](rows)

    def rows(self, frames: int, bodies: int) -> dict:
        """The rows of frames 0 .. frames, as rigid.Simulator.advance gives them (float64)."""
        rows = np.zeros((frames + 1, bodies, 19))
        self._transfers()["rows"](rows)
        return {key: rows[:, :, a:b].copy() for key, (a, b) in ROW_COLUMNS.items()}

    def parameter_grads(self) -> dict:
        """The adjoint of each of PARAMETERS, in its field's shape (float64)."""
        entries, size = layout(getattr(self, name).grad for name in self.PARAMETERS)
        flat = np.zeros(size)
        self._transfers()["grads"](flat)
        out = {}
        for name, (f, start, shape, n) in zip(self.PARAMETERS, entries):
            out[name] = flat[start:start + int(np.prod(shape)) * max(n, 1)].reshape(shape + ((n,) if n else ()))
        return out

    def _transfers(self) -> dict:
        """The copies between host and fields (rigid.diff.transfers), built on first use: load,
        zero the parameters' adjoints, seed the rows' adjoints, read the rows, read the
        parameters' adjoints, a checkpoint out and in."""
        if not hasattr(self, "_kernels"):
            field = lambda names: [getattr(self, name) for name in names]
            checkpoint, size = layout(field(self.CHECKPOINT))
            self._kernels = dict(
                row_kernels(self.row_fields(), [f.grad for f in field(self.PARAMETERS + self.DERIVED)]),
                load=copier(layout(field(self.FIXED + self.PARAMETERS))[0], True),
                grads=copier(layout(f.grad for f in field(self.PARAMETERS))[0], False),
                checkpoint_out=copier(checkpoint, False), checkpoint_in=copier(checkpoint, True), checkpoint_size=size)
        return self._kernels
