"""[[static]] meshes: shapes that never move (a bowl, stairs, a funnel), as static bodies.

A static mesh is a body of the engine whose particles sit on its surface and take part in
the pair stage like any body's, but which gets no force and is never integrated (its mass
counts as infinite in every contact: rigid.engine.material_stages). So nothing new is needed
to find its contacts (the grid), to draw it (its mesh is a body surface: windows, videos) or
to export it (a node that never moves, in glTF and USD; the NPZ's last bodies, at rest).

Its particles: the surface, its triangles split until no edge is longer than the spacing h,
then every vertex; each particle's radius is h, so neighbouring spheres overlap by half and
leave no gap a particle could pass through (bumps of 0.13 h). A closed mesh (each edge shared
by two triangles: a box, stairs) has its spheres moved inside it, tangent to its faces, as a
body's are (rigid.bodies.inset), so that bodies touch it at its surface; an open one (the bowl)
has no inside to move them to: its spheres stay centred on the surface, a shell h thick on
either side. h is 2.5 times the smallest
radius of the scene's moving particles (bumps of a third of their radius, which they roll
over; a finer h costs particles as 1/h²), or 1 % of the mesh's size if they have none. ``position`` is where the mesh file's origin goes and ``orientation`` turns
the mesh about it (a static has no centre of mass to speak of).

A convex closed mesh (a box, a ramp) is touched at its faces instead (rigid.engine.static_faces):
``face_planes`` gives its face planes in the world, coplanar triangles merged, and the engine
keeps its particles out of the pair stage, so that a body slides on the flat face, not over
the spheres' bumps. Its particles stay: they are what the start's overlap check compares.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import UserError
from .colliders import MAX_PLANES
from .mesh import BodyGeometry, read_mesh
from .inset import collision_centres
from .placement import BodySpec
from .quaternion import quaternion_to_matrix_np

MAX_STATIC_PARTICLES = 400_000
STATIC_SPACING = 2.5  # the static particles' spacing and radius, in the moving particles' smallest radius


def static_bodies(config, bodies: list) -> list[BodySpec]:
    """One static BodySpec per [[static]] table of the config (``bodies``: the moving ones)."""
    out = []
    moving = [b.radius for b in bodies if b.radius > 0]
    for index, table in enumerate(config.statics):
        where = f"[[static]] {index + 1}"
        mesh = read_mesh(table["mesh"], float(table.get("scale", 1.0)))
        size = float(np.ptp(mesh.vertices, axis=0).max())
        h = STATIC_SPACING * min(moving) if moving else 0.01 * size
        particles, faces = surface_particles(mesh.vertices, mesh.faces, h, where)
        if closed(mesh.faces):
            particles = collision_centres(particles, particles, faces, h)
        q = np.asarray(table.get("orientation", (1.0, 0.0, 0.0, 0.0)), float)
        q = q / np.linalg.norm(q)
        origin = np.asarray(table.get("position", (0.0, 0.0, 0.0)), float)
        centre = particles.mean(axis=0)
        note = f"{len(particles)} particles {h:.3g} m apart on the surface of {Path(table['mesh']).name}"
        geometry = BodyGeometry(particles, mesh.vertices, mesh.faces, note)
        out.append(BodySpec(f"static_{Path(table['mesh']).stem}_{index}", geometry, 1.0, h,
                            origin + quaternion_to_matrix_np(q) @ centre, q, np.zeros(3), np.zeros(3),
                            table.get("restitution", config.restitution), table.get("friction", config.friction),
                            static=True))
    return out


def static_faces(config, bodies: list) -> dict:
    """{index in ``bodies``: (face planes (F, 4), (μ, e) or None where unset)} for the static bodies touched at their
    faces: convex closed meshes, in order, while their faces fit the planes' slots beside the
    box's five (reserved: ``walls`` may be switched on later) and the [[plane]] tables."""
    free = MAX_PLANES - 5 - len(config.planes)
    out = {}
    for index, body in enumerate(bodies):
        planes = face_planes(body) if body.static else None
        if planes is not None and len(planes) <= free:
            free -= len(planes)
            out[index] = (planes, (body.friction, body.restitution))
    return out


def face_planes(body: BodySpec, tolerance: float = 1e-6):
    """A static body's face planes in the world, (F, 4) rows (outward unit normal n, offset n·p),
    coplanar triangles merged, if its mesh is closed and convex (every vertex on or behind every
    face plane, within ``tolerance`` of its size); else None (it keeps the particles' contact)."""
    g = body.geometry
    faces = np.asarray(g.faces, np.int64).reshape(-1, 3)
    if not closed(faces):
        return None
    R = quaternion_to_matrix_np(np.asarray(body.orientation, float))
    v = np.asarray(body.position, float) + (np.asarray(g.vertices, float) - g.particles.mean(axis=0)) @ R.T
    inside = v.mean(axis=0)
    size = float(np.ptp(v, axis=0).max())
    n = np.cross(v[faces[:, 1]] - v[faces[:, 0]], v[faces[:, 2]] - v[faces[:, 0]])
    area = np.linalg.norm(n, axis=1)
    keep = area > 1e-12 * size * size
    n = n[keep] / area[keep, None]
    n = np.where(((v[faces[keep, 0]] - inside) * n).sum(axis=1, keepdims=True) < 0, -n, n)  # outward
    d = (n * v[faces[keep, 0]]).sum(axis=1)
    planes = np.column_stack([n, d])
    if np.any(v @ n.T - d > tolerance * size):
        return None  # a vertex in front of a face: not convex
    out = []
    for row in planes:  # coplanar triangles are one face
        if not any(np.all(np.abs(row - o) < np.array([1e-6, 1e-6, 1e-6, 1e-6 * size])) for o in out):
            out.append(row)
    return np.array(out)


def closed(faces: np.ndarray) -> bool:
    """Whether every edge of the triangles is shared by exactly two of them."""
    faces = np.asarray(faces, np.int64).reshape(-1, 3)
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    _edges, counts = np.unique(edges, axis=0, return_counts=True)
    return len(faces) > 0 and bool(np.all(counts == 2))


def surface_particles(vertices: np.ndarray, faces: np.ndarray, h: float, where: str):
    """The mesh's vertices after splitting its triangles to edges <= h, coincident ones merged, and
    the split triangles on them."""
    if len(faces) == 0:
        raise UserError(f"{where}: the mesh has no triangles; a static mesh needs a surface")
    import trimesh  # deferred: slow to import

    area = float(trimesh.Trimesh(vertices, faces, process=False).area)
    if area / (h * h) > MAX_STATIC_PARTICLES:
        raise UserError(f"{where}: its surface ({area:.3g} m²) would take ~{area / h / h:,.0f} particles "
                        f"{h:.3g} m apart; use a smaller scale or larger moving particles (particle_radius)")
    v, f = trimesh.remesh.subdivide_to_size(vertices, faces, max_edge=h)
    v, inverse = np.unique(np.round(np.asarray(v, np.float64) / (1e-6 * h)) * (1e-6 * h), axis=0, return_inverse=True)
    return v, inverse.reshape(-1)[np.asarray(f, np.int64)]
