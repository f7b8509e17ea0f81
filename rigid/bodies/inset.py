"""Collision spheres inside the mesh: a body touches others at its mesh's surface, not beyond it.

Every particle of a body with company is a sphere of the body's collision radius r (rigid.bodies.
placement says how r is chosen). Centred on the mesh's vertices, those spheres would stick out of
the mesh by r and the body would rest and collide r too far out (a box of side 0.2 with 8 corner
spheres of r = 0.1 rested 10 cm higher with company than alone). So each sphere's centre is moved
in until the sphere is tangent to the mesh's faces around it:

- a vertex particle moves to v − d, where d solves n_f · d = r for the unit outward normals n_f of
  its faces, in the least-squares sense: r (1, 1, 1) at a cube's corner (tangent to all three
  faces), ≈ r n at a smooth vertex. Directions the normals hardly span (a flat or gently curved
  vertex) are left out of the solve (a truncated pseudo-inverse), and |d| is capped at
  ``MAX_INSET`` r: a needle-sharp tip keeps a little of its sphere outside instead of a centre
  far inside;
- a volume particle (a grid cell's centre, inside the mesh) closer than r to the surface is pushed
  along the inward normal of the nearest face until it is r from that face's plane, a few times so
  that a particle in a corner leaves every face. An axis-aligned box's cells are already h / 2
  = r from its faces: they do not move.

A mesh thinner than 2 r cannot hold spheres of r tangent to both sides: ``radius_cap`` is a quarter
of the mesh's thinnest extent (along its principal axes), at which the inset vertex spheres of a
box touch one another (an inner box of half the size) and a slab's two layers just meet.

The mass stays where the mesh puts it: the engine (rigid.engine.model) sums TODO 1's inertia over
the mesh's own particles about the centre of the collision spheres, so a body turns alike alone
and in company. A lone body has r = 0 and keeps its particles exactly (the slides' contact).
"""
from __future__ import annotations

import numpy as np

MAX_INSET = 3.0  # |d| <= 3 r: a cube's corner needs sqrt(3) r; a 40° cone's tip ~2.9 r
SPREAD = 0.03  # singular values of a vertex's normals below 3 % of the largest: a direction they do not fix
PUSHES = 3  # passes of the volume push: a particle near a corner of three faces leaves each


def radius_cap(vertices: np.ndarray) -> float:
    """A quarter of the mesh's thinnest extent along its principal axes (m)."""
    v = np.asarray(vertices, np.float64)
    centred = v - v.mean(axis=0)
    _w, axes = np.linalg.eigh(centred.T @ centred)
    return 0.25 * float(np.ptp(centred @ axes, axis=0).min())


def collision_centres(particles: np.ndarray, vertices: np.ndarray, faces: np.ndarray, radius: float) -> np.ndarray:
    """The particles' sphere centres (N, 3), moved in so that spheres of ``radius`` lie inside the
    mesh (vertices (V, 3), faces (F, 3)); the particles themselves for radius 0 or no faces.
    Particles that are the mesh's vertices are inset along their faces' normals; others are
    taken as volume particles and pushed off the surface."""
    particles = np.asarray(particles, np.float64)
    faces = np.asarray(faces, np.int64).reshape(-1, 3)
    if radius <= 0 or len(faces) == 0:
        return particles
    vertices = np.asarray(vertices, np.float64)
    normals = _outward_normals(vertices, faces)
    if particles.shape == vertices.shape and np.array_equal(particles, vertices):
        return particles - radius * _vertex_insets(len(vertices), faces, normals)
    return _push_off_surface(particles, vertices, faces, normals, radius)


def _outward_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit face normals (F, 3), flipped if the mesh's triangles wind inward (negative volume)."""
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    cross = np.cross(b - a, c - a)
    volume = float(np.einsum("ij,ij->", a, np.cross(b, c))) / 6.0
    length = np.linalg.norm(cross, axis=1, keepdims=True)
    normals = np.divide(cross, length, out=np.zeros_like(cross), where=length > 0)
    return -normals if volume < 0 else normals


def _vertex_insets(count: int, faces: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """d / r (count, 3) per vertex: the truncated least-squares solution of n_f · d = 1."""
    A = np.zeros((count, 3, 3))
    b = np.zeros((count, 3))
    outer = np.einsum("fi,fj->fij", normals, normals)
    for corner in range(3):  # each face's normal once at each of its corners
        np.add.at(A, faces[:, corner], outer)
        np.add.at(b, faces[:, corner], normals)
    w, U = np.linalg.eigh(A)  # A = Σ n nᵀ, symmetric: A⁺ b from its eigenvectors
    keep = w > SPREAD ** 2 * w[:, -1:]
    inverse = np.where(keep, 1.0 / np.where(keep, w, 1.0), 0.0)
    d = np.einsum("vij,vj,vkj,vk->vi", U, inverse, U, b)
    size = np.linalg.norm(d, axis=1, keepdims=True)
    return d * np.minimum(1.0, MAX_INSET / np.maximum(size, 1e-300))


def _push_off_surface(points, vertices, faces, normals, radius) -> np.ndarray:
    """Volume particles moved along the inward normal of their nearest face until each is
    ``radius`` from that face's plane (nearest face: by the centres of its pieces after splitting
    the triangles to edges of radius / 2)."""
    from scipy.spatial import cKDTree

    centres, owner = _face_pieces(vertices, faces, radius / 2)
    tree = cKDTree(centres)
    out = points.copy()
    for _ in range(PUSHES):  # each pass: the face that pushes a particle furthest, if any
        distance, piece = tree.query(out, k=min(8, len(centres)), distance_upper_bound=2 * radius)
        piece = piece.reshape(len(out), -1)
        near = piece < len(centres)
        face = owner[np.where(near, piece, 0)]
        n = normals[face]  # (N, k, 3)
        gap = np.einsum("ikj,ikj->ik", vertices[faces[face, 0]] - out[:, None], n)  # inside each plane
        push = np.where(near, np.clip(radius - gap, 0.0, None), 0.0)
        worst = push.argmax(axis=1)
        amount = push[np.arange(len(out)), worst]
        if not np.any(amount > 1e-9 * radius):
            break
        out -= amount[:, None] * n[np.arange(len(out)), worst]
    return out


def _face_pieces(vertices, faces, size):
    """Centres (P, 3) of the triangles' pieces after splitting each into k² (edges <= size), and
    the face (P,) each came from."""
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    longest = np.max([np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1),
                      np.linalg.norm(a - c, axis=1)], axis=0)
    k = np.clip(np.ceil(longest / size), 1, 64).astype(np.int64)
    centres, owner = [], []
    for level in np.unique(k):  # triangles split alike at once: barycentric centres of the k² pieces
        chosen = np.flatnonzero(k == level)
        i, j = np.meshgrid(np.arange(level), np.arange(level), indexing="ij")
        up = (i + j) < level
        wu = np.stack([i[up] + 1 / 3, j[up] + 1 / 3], axis=1) / level
        down = (i + j) < level - 1
        wd = np.stack([i[down] + 2 / 3, j[down] + 2 / 3], axis=1) / level
        w = np.concatenate([wu, wd])  # weights of b − a and c − a
        p = a[chosen, None] + w[None, :, :1] * (b - a)[chosen, None] + w[None, :, 1:] * (c - a)[chosen, None]
        centres.append(p.reshape(-1, 3))
        owner.append(np.repeat(chosen, len(w)))
    return np.concatenate(centres), np.concatenate(owner)
