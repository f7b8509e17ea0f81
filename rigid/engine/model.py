"""Static data of the bodies: everything that does not change during a run.

Like Warp's ``Model`` (and MuJoCo's mjModel): built once from the particles,
read by every substep, never written by it. B bodies and N particles live in
one flat array with a body index:

- ``r0``            [N] vec3   particle offset from its body's centre of mass, body frame
- ``particle_body`` [N] i32    index of the body a particle belongs to
- ``body_start``, ``body_count`` [B] i32  the body's particles are r0[start : start + count]
- ``particle_mass`` [B] float  mass of each of the body's particles (all equal)
- ``particle_radius`` [B] float  collision radius of the body's particles against other bodies
- ``body_mass``     [B] float  M = Σ m
- ``inertia_body``  [B] mat3   I0 about the centre of mass, body frame (from TODO 1)
- ``inertia_body_inv`` [B] mat3  I0⁻¹ (zero where TODO 1 gave a singular I0)
- ``surface_r0``    [V] vec3   the drawn meshes' vertices, each in its body's frame
- ``surface_body``  [V] i32    the body a drawn vertex belongs to
- ``indices``       [3F] i32   triangle indices into surface_r0, flat, for GGUI
Host copies (float64 numpy) keep what the exporters and diagnostics need.
"""

import sys
from dataclasses import dataclass

import numpy as np
import taichi as ti


@dataclass
class BodyParts:
    """One body's input to the Model: particles and drawn mesh in the mesh frame (not centred)."""

    particles: np.ndarray  # (N, 3)
    surface: np.ndarray  # (V, 3)
    faces: np.ndarray  # (F, 3) into surface
    particle_mass: float
    radius: float = 0.0
    name: str = "body"


class Model:
    def __init__(self, bodies: list[BodyParts], units):
        bodies = list(bodies)
        self.num_bodies = B = len(bodies)
        counts = np.array([len(b.particles) for b in bodies])
        surface_counts = np.array([len(b.surface) for b in bodies])
        self.num_particles, self.num_surface = n, v = int(counts.sum()), int(surface_counts.sum())
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        surface_starts = np.concatenate([[0], np.cumsum(surface_counts)[:-1]])
        # The centre of mass in float64 on the host: x = Σ m r / M (equal masses).
        coms = np.array([np.asarray(b.particles, np.float64).mean(axis=0) for b in bodies])
        self.center_of_mass = coms[0]
        self.r0_np = np.concatenate([np.asarray(b.particles, np.float64) - c for b, c in zip(bodies, coms)])
        self.surfaces_np = [np.asarray(b.surface, np.float64).reshape(-1, 3) - c for b, c in zip(bodies, coms)]
        self.faces_list = [np.asarray(b.faces, np.int32).reshape(-1, 3) for b in bodies]
        self.body_names = [b.name for b in bodies]
        self.body_mass_np = np.array([b.particle_mass * c for b, c in zip(bodies, counts)], np.float64)
        self.mass = float(self.body_mass_np[0]) if B == 1 else float(self.body_mass_np.sum())
        self.radius_np = np.array([b.radius for b in bodies], np.float64)

        self.r0 = ti.Vector.field(3, float, shape=n)
        self.particle_body = ti.field(ti.i32, shape=n)
        self.body_start = ti.field(ti.i32, shape=B)
        self.body_count = ti.field(ti.i32, shape=B)
        self.particle_mass = ti.field(float, shape=B)
        self.particle_radius = ti.field(float, shape=B)
        self.body_mass = ti.field(float, shape=B)
        self.inertia_body = ti.Matrix.field(3, 3, float, shape=B)
        self.inertia_body_inv = ti.Matrix.field(3, 3, float, shape=B)
        self.surface_r0 = ti.Vector.field(3, float, shape=max(v, 1))
        self.surface_body = ti.field(ti.i32, shape=max(v, 1))
        faces = [f + s for f, s in zip(self.faces_list, surface_starts)]
        all_faces = np.concatenate(faces) if faces else np.zeros((0, 3), np.int32)
        self.num_faces = len(all_faces)
        self.indices = ti.field(ti.i32, shape=max(3 * self.num_faces, 3))

        _load(self.r0, self.r0_np)
        self.particle_body.from_numpy(np.repeat(np.arange(B, dtype=np.int32), counts))
        self.body_start.from_numpy(starts.astype(np.int32))
        self.body_count.from_numpy(counts.astype(np.int32))
        _load(self.particle_mass, np.array([b.particle_mass for b in bodies], np.float64))
        _load(self.particle_radius, self.radius_np)
        _load(self.body_mass, self.body_mass_np)
        if v:
            _load(self.surface_r0, np.concatenate(self.surfaces_np))
            self.surface_body.from_numpy(np.repeat(np.arange(B, dtype=np.int32), surface_counts))
        if self.num_faces:
            self.indices.from_numpy(all_faces.astype(np.int32).reshape(-1))
        self._compute_inertia(units)

    def body_surfaces(self) -> list:
        """Per body: (name, drawn vertices (V, 3) float64 in the body frame about its centre of
        mass, triangles (F, 3) int32 into those vertices). Exporters (glTF, USD) write these."""
        return list(zip(self.body_names, self.surfaces_np, self.faces_list))

    def _compute_inertia(self, units):
        """I0 = Σ TODO1(m, r0ᵢ) per body, summed in a fixed (serial) order; I0⁻¹ on the host in float64."""
        r0, mass, inertia = self.r0, self.particle_mass, self.inertia_body
        start, count = self.body_start, self.body_count
        particle_inertia = units.particle_inertia

        @ti.kernel
        def sum_inertia(num_bodies: ti.i32):
            ti.loop_config(serialize=True)
            for b in range(num_bodies):
                total = ti.Matrix.zero(float, 3, 3)
                for i in range(start[b], start[b] + count[b]):
                    total += particle_inertia(mass[b], r0[i])
                inertia[b] = total

        sum_inertia(self.num_bodies)
        inertia_np = self.inertia_body.to_numpy().astype(np.float64)
        self.inertia_body_np = inertia_np[0]
        self.inertia_all_np = inertia_np
        inverse = np.zeros_like(inertia_np)
        singular = False
        for b, tensor in enumerate(inertia_np):
            if np.all(np.isfinite(tensor)) and np.linalg.cond(tensor) < 1e12:
                inverse[b] = np.linalg.inv(tensor)
            else:
                singular = True
        if singular:
            print("warning: TODO 1 gives a singular inertia tensor; the body will not rotate "
                  "until TODO 1 is solved", file=sys.stderr)
        self.inertia_body_inv_np = inverse[0]
        _load(self.inertia_body_inv, inverse)


def _load(field, array: np.ndarray) -> None:
    """Copy a float64 host array into a field of the run's precision (f32 or f64)."""
    field.from_numpy(np.ascontiguousarray(array, dtype=np.float64 if field.dtype == ti.f64 else np.float32))
