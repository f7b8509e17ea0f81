"""Static data of the bodies: everything that does not change during a run (Warp's ``Model``).

Built once from the bodies' particles, read by every substep, never written by it.
B bodies, N particles, K blocks; the particles of all bodies live in one flat array,
body by body, and inside a body in blocks (``blocks.py``: spatially compact runs of at
most 128 particles, sorted along a Z-order curve). Device arrays (Taichi ndarrays; float
is the run's precision, f32 or f64), all read-only during a run:

- ``r0_x``, ``r0_y``, ``r0_z``  [N] float  particle offset from its body's centre of mass, body frame,
                                    one array per axis (vectorised loops; matvec.body_offset): the
                                    centre of its collision sphere, moved inside the mesh by the
                                    body's radius (rigid.bodies.inset; unmoved at radius 0)
- ``particle_body``      [N] i32    body of each particle
- ``body_start``, ``body_count``  [B] i32   body b's particles are slots start .. start + count − 1
- ``particle_mass``      [B] float  mass of each of the body's particles (all equal), kg
- ``particle_radius``    [B] float  collision radius of the body's particles, m (0: the particle centre)
- ``body_mass``          [B] float  M = Σ m, kg
- ``inertia_body``       [B] mat3   I0 about the centre of mass, body frame (from TODO 1 over the
                                    particles as the mesh places them, before the inset: a body turns
                                    alike alone and in company), kg m²
- ``inertia_body_inv``   [B] mat3   I0⁻¹ (zero where TODO 1 gave a singular I0)
- ``block_start``, ``block_count``, ``block_body``  [K] i32   block k: its particle slots and body
- ``block_centre``       [K] vec3   centre of the block's particles' bounding box, body frame
- ``block_bounds``       [K] vec4   that box's half extents along the body's axes (3), and the radius of
                                    the sphere about that centre holding every particle centre (one
                                    array: a kernel takes at most 64 argument elements), m
- ``body_blocks``        [B] 2×i32  body b's blocks, consecutive: (first, how many)
- ``body_material``      [B] vec4   (Coulomb μ, restitution e, static: 0 no, 1 of particles, 2 touched at its
                                    faces (static_faces.py), drag c in N s/m):
                                    materials.py, −1 for an unset μ or e; a static mesh has infinite mass,
                                    is not integrated; the drag is forces.particle_force's
- ``body_world``         [B] 4×i32  (the grid's cell shift of the body's world, 10 bits an axis; its
                                    world w; the world's first body; bodies a world): no contact
                                    across worlds (worlds.py); one world: (0, 0, 0, B)

The drawn meshes (``surface``, for windows, videos and exports) are not read by a substep:
``surface_r0`` [V] vec3 (body frame about the centre of mass), ``surface_body`` [V] i32 and
``indices`` (host (F, 3) triangles). Host copies (float64 numpy, ``*_np``) serve the
exporters and diagnostics (``inertia_body_np`` (B, 3, 3), ``body_mass_np`` (B,), ...); ``slot_of`` maps a particle's index in its mesh file order (body
by body) to its slot, ``order`` the other way round.

A Model is passed to the kernels as one argument pack (``args``): kernels are compiled once
per process and run on any Model (rigid.engine.kernels).
"""
from __future__ import annotations

import sys
from dataclasses import dataclass

import numpy as np
import taichi as ti

from .arrays import ModelArgs, SurfaceArgs, device_array, download, float_dtype, host_float, upload
from .blocks import block_layout, block_size_for
from .materials import friction_value
from .worlds import world_table


@dataclass
class BodyParts:
    """One body's input to the Model: particles and drawn mesh in the mesh frame (not centred)."""

    particles: np.ndarray  # (N, 3): where the mesh puts the mass (vertices or cell centres)
    surface: np.ndarray  # (V, 3)
    faces: np.ndarray  # (F, 3) into surface
    particle_mass: float
    radius: float = 0.0
    name: str = "body"
    restitution: float | None = None  # e, None: unset (velocity_damping_stiffness)
    friction: float | None = None  # Coulomb μ, None: unset (friction_stiffness)
    static: bool = False  # a [[static]] mesh: never moves (rigid.engine.material_stages)
    drag: float = 0.0  # linear drag c, N s/m per particle: f = −c vᵢ (rigid.engine.forces)
    faced: bool = False  # a static touched at its faces, not its particles (rigid.engine.static_faces)


def _collision_centres(bodies) -> list:
    """Per body, its particles' collision-sphere centres (N, 3) float64 (rigid.bodies.inset); a
    static mesh's and a radius-0 body's are its particles. Copies sharing one particle array are
    computed once."""
    from ..bodies.inset import collision_centres

    done: dict = {}
    out = []
    for b in bodies:
        particles = np.asarray(b.particles, np.float64)
        if b.static or b.radius <= 0:
            out.append(particles)
            continue
        key = (id(b.particles), id(b.surface), float(b.radius))
        if key not in done:
            done[key] = (b.particles, collision_centres(particles, b.surface, b.faces, b.radius))
        out.append(done[key][1])
    return out


class Model:
    def __init__(self, bodies: list[BodyParts], kernels, worlds: int = 1):
        """``kernels``: the process's compiled kernels for the run's TODO units (kernels.py);
        TODO 1 gives I0. ``worlds``: the bodies are that many worlds' copies, world by world
        (worlds.py), each the same number of bodies."""
        bodies = list(bodies)
        self.num_bodies = B = len(bodies)
        self.num_worlds = W = int(worlds)
        if W < 1 or B % W:
            raise ValueError(f"{B} bodies are not {W} worlds of equal size")
        counts = np.array([len(b.particles) for b in bodies])
        self.num_particles = int(counts.sum())
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        # Each particle's collision sphere sits inside the mesh (rigid.bodies.inset): its centre is
        # where gravity and contacts act, so the centre of mass is theirs, x = Σ m r / M (equal
        # masses, float64 on the host), and Σ r0 = 0 keeps gravity torque-free.
        centres = _collision_centres(bodies)
        coms = np.array([c.mean(axis=0) for c in centres])
        r0_file = np.concatenate([c - com for c, com in zip(centres, coms)])
        r0_mass = np.concatenate([np.asarray(b.particles, np.float64) - com for b, com in zip(bodies, coms)])
        self.center_of_mass_np = coms  # (B, 3): each body's centre of mass in its mesh frame
        self.body_names = [b.name for b in bodies]
        self.body_mass_np = np.array([b.particle_mass * c for b, c in zip(bodies, counts)], np.float64)
        self.particle_mass_np = np.array([b.particle_mass for b in bodies], np.float64)
        self.radius_np = np.array([b.radius for b in bodies], np.float64)
        self.body_start_np, self.body_count_np = starts, counts

        layout = block_layout(r0_file, starts, counts, block_size_for(int(counts.max())))
        self.order = layout["order"]  # slot -> index in file order
        self.slot_of = np.empty_like(self.order)
        self.slot_of[self.order] = np.arange(len(self.order))
        self.r0_np = r0_file[self.order]  # in slot order
        self.num_blocks = len(layout["block_start"])
        particle_body = np.repeat(np.arange(B), counts)

        # The same offsets as three arrays x, y, z (structure of arrays): the block loop loads 8 x,
        # 8 y, 8 z at once when LLVM vectorises it.
        self.r0_x, self.r0_y, self.r0_z = (device_array(self.r0_np[:, c]) for c in range(3))
        self.particle_body = device_array(particle_body, dtype=ti.i32)
        self.body_start = device_array(starts, dtype=ti.i32)
        self.body_count = device_array(counts, dtype=ti.i32)
        self.particle_mass = device_array(self.particle_mass_np)
        self.particle_radius = device_array(self.radius_np)
        self.body_mass = device_array(self.body_mass_np)
        self.inertia_body = ti.ndarray(ti.types.matrix(3, 3, float_dtype()), B)
        self.inertia_body_inv = ti.ndarray(ti.types.matrix(3, 3, float_dtype()), B)
        for name in ("block_start", "block_count", "block_body"):
            setattr(self, name, device_array(layout[name], dtype=ti.i32))
        self.body_blocks = device_array(np.column_stack([layout["body_block_start"], layout["body_block_count"]]),
                                        2, dtype=ti.i32)
        self.block_centre = device_array(layout["block_centre"], 3)
        # Rounded up, so that the float copies never under-cover their blocks.
        bounds = np.column_stack([layout["block_half"], layout["block_reach"]])
        self.block_bounds = device_array(np.nextafter(bounds.astype(host_float()), np.inf), 4)

        self.static_np = np.array([bool(b.static) for b in bodies])
        self.body_material = device_array(np.array([(friction_value(b.friction), friction_value(b.restitution),
                                                     float(b.static) + float(b.faced), float(b.drag)) for b in bodies]), 4)

        self.body_world_np = world_table(W, B // W, np.zeros((B, 3), np.int64))
        self.body_world = device_array(self.body_world_np, 4, dtype=ti.i32)

        self._surfaces(bodies, coms)
        self.args = ModelArgs()(**{name: getattr(self, name) for name in ModelArgs.NAMES})
        self._sum_inertia(kernels, r0_mass[self.order])
        self._invert_inertia()

    def _sum_inertia(self, kernels, r0_mass: np.ndarray):
        """I0 by TODO 1 over the particles where the mesh puts them (about the centre of mass): the
        r0 arrays hold those offsets while it sums, then the collision spheres' again."""
        moved = not np.array_equal(r0_mass, self.r0_np)
        if moved:
            for array, c in zip((self.r0_x, self.r0_y, self.r0_z), range(3)):
                upload(array, r0_mass[:, c])
        kernels.sum_inertia(self.args)
        if moved:
            for array, c in zip((self.r0_x, self.r0_y, self.r0_z), range(3)):
                upload(array, self.r0_np[:, c])

    @property
    def mass(self) -> float:
        """Total mass of the scene, kg (one body: its M)."""
        return float(self.body_mass_np.sum())

    def _surfaces(self, bodies, coms):
        surface_counts = np.array([len(b.surface) for b in bodies])
        self.num_surface = int(surface_counts.sum())
        self.surfaces_np = [np.asarray(b.surface, np.float64).reshape(-1, 3) - c for b, c in zip(bodies, coms)]
        self.faces_list = [np.asarray(b.faces, np.int32).reshape(-1, 3) for b in bodies]
        surface_starts = np.concatenate([[0], np.cumsum(surface_counts)[:-1]])
        faces = [f + s for f, s in zip(self.faces_list, surface_starts)]
        self.faces_np = np.concatenate(faces).astype(np.int32) if faces else np.zeros((0, 3), np.int32)
        self.num_faces = len(self.faces_np)
        self.surface_body_np = np.repeat(np.arange(self.num_bodies), surface_counts)
        surface = np.concatenate(self.surfaces_np) if self.num_surface else np.zeros((1, 3))
        self.surface_r0 = device_array(surface, 3)
        self.surface_body = device_array(self.surface_body_np if self.num_surface else np.zeros(1), dtype=ti.i32)
        self.surface_args = SurfaceArgs()(surface_r0=self.surface_r0, surface_body=self.surface_body)

    def body_surfaces(self) -> list:
        """Per body: (name, drawn vertices (V, 3) float64 in the body frame about its centre of
        mass, triangles (F, 3) int32 into those vertices). Exporters (glTF, USD) write these."""
        return list(zip(self.body_names, self.surfaces_np, self.faces_list))

    def _invert_inertia(self):
        """I0⁻¹ on the host in float64 (a singular I0, e.g. TODO 1 unsolved, gets zero)."""
        self.inertia_body_np = inertia = download(self.inertia_body).astype(np.float64).reshape(-1, 3, 3)
        inverse = np.zeros_like(inertia)
        singular = False
        for b, tensor in enumerate(inertia):
            if np.all(np.isfinite(tensor)) and np.linalg.cond(tensor) < 1e12:
                inverse[b] = np.linalg.inv(tensor)
            else:
                singular = True
        if singular:
            print("warning: TODO 1 gives a singular inertia tensor; the body will not rotate "
                  "until TODO 1 is solved", file=sys.stderr)
        self.inertia_body_inv_np = inverse
        upload(self.inertia_body_inv, inverse)
