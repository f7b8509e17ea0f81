"""Static data of the bodies: everything that does not change during a run.

Like Warp's ``Model`` (and MuJoCo's mjModel): built once from the particles,
read by every substep, never written by it. Shapes use B bodies and N
particles in one flat array with a body index (B = 1 today):

- ``r0``            [N] vec3   particle offset from its body's centre of mass, body frame
- ``particle_body`` [N] i32    index of the body a particle belongs to
- ``body_start``, ``body_count`` [B] i32  the body's particles are r0[start : start + count]
- ``particle_mass`` [B] float  mass of each of the body's particles (all equal)
- ``body_mass``     [B] float  M = Σ m
- ``inertia_body``  [B] mat3   I0 about the centre of mass, body frame (from TODO 1)
- ``inertia_body_inv`` [B] mat3  I0⁻¹ (zero where TODO 1 gave a singular I0)
- ``surface_r0``    [V] vec3   the drawn mesh's vertices, body frame (= r0 for vertex particles)
- ``indices``       [3F] i32   triangle indices into surface_r0, flat, for GGUI
"""
import sys

import numpy as np
import taichi as ti



class Model:
    def __init__(self, particles: np.ndarray, surface: np.ndarray, faces: np.ndarray,
                 particle_mass: float, units):
        particles = np.asarray(particles, dtype=np.float64)
        n, v = len(particles), len(surface)
        self.num_bodies, self.num_particles, self.num_surface = 1, n, v
        # The centre of mass in float64 on the host: x = Σ m r / M (equal masses).
        self.center_of_mass = particles.mean(axis=0)
        self.r0_np = particles - self.center_of_mass
        self.mass = particle_mass * n

        self.r0 = ti.Vector.field(3, float, shape=n)
        self.particle_body = ti.field(ti.i32, shape=n)
        self.body_start = ti.field(ti.i32, shape=1)
        self.body_count = ti.field(ti.i32, shape=1)
        self.particle_mass = ti.field(float, shape=1)
        self.body_mass = ti.field(float, shape=1)
        self.inertia_body = ti.Matrix.field(3, 3, float, shape=1)
        self.inertia_body_inv = ti.Matrix.field(3, 3, float, shape=1)
        self.surface_r0 = ti.Vector.field(3, float, shape=max(v, 1))
        self.indices = ti.field(ti.i32, shape=max(3 * len(faces), 3))

        _load(self.r0, self.r0_np)
        self.particle_body.fill(0)
        self.body_start[0], self.body_count[0] = 0, n
        self.particle_mass[0], self.body_mass[0] = particle_mass, self.mass
        self.surface_np = np.asarray(surface, dtype=np.float64).reshape(-1, 3) - self.center_of_mass
        self.faces_np = np.asarray(faces, dtype=np.int32).reshape(-1, 3)
        self.body_names = ["body"]
        if v:
            _load(self.surface_r0, self.surface_np)
        if len(faces):
            self.indices.from_numpy(np.asarray(faces, dtype=np.int32).reshape(-1))
        self.num_faces = len(faces)
        self._compute_inertia(units)

    def body_surfaces(self) -> list:
        """Per body: (name, drawn vertices (V, 3) float64 in the body frame about its centre of
        mass, triangles (F, 3) int32 into those vertices). Exporters (glTF, USD) write these."""
        return [(self.body_names[0], self.surface_np, self.faces_np)]

    def _compute_inertia(self, units):
        """I0 = Σ TODO1(m, r0ᵢ), summed in a fixed (serial) order; I0⁻¹ on the host in float64."""
        r0, mass, inertia = self.r0, self.particle_mass, self.inertia_body
        particle_inertia = units.particle_inertia

        @ti.kernel
        def sum_inertia(n: ti.i32):
            ti.loop_config(serialize=True)
            for _ in range(1):
                total = ti.Matrix.zero(float, 3, 3)
                for i in range(n):
                    total += particle_inertia(mass[0], r0[i])
                inertia[0] = total

        sum_inertia(self.num_particles)
        inertia_np = self.inertia_body.to_numpy()[0].astype(np.float64)
        self.inertia_body_np = inertia_np
        inverse = np.zeros((3, 3))
        if np.all(np.isfinite(inertia_np)) and np.linalg.cond(inertia_np) < 1e12:
            inverse = np.linalg.inv(inertia_np)
        else:
            print("warning: TODO 1 gives a singular inertia tensor; the body will not rotate "
                  "until TODO 1 is solved", file=sys.stderr)
        self.inertia_body_inv_np = inverse
        _load(self.inertia_body_inv, inverse[None])


def _load(field, array: np.ndarray) -> None:
    """Copy a float64 host array into a field of the run's precision (f32 or f64)."""
    field.from_numpy(np.ascontiguousarray(array, dtype=np.float64 if field.dtype == ti.f64 else np.float32))
