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
- a volume particle (a grid cell's centre, inside the mesh) stays where it is: its sphere of
  r = h / 2 fills its cell, so the spheres' surface follows the mesh's within half a cell either
  way, with no bias outward (an axis-aligned box's cells are exactly r from its faces; two
  spheres R = 0.15 at grid 6 or 8 touch at 0.98 x 2R). Pushing the outer cells off the surface
  was tried: their spheres then sank into each other's bumps (0.92 x 2R) and the front layer's
  uneven depths lowered a head-on bounce's e by up to 12 %.

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


def radius_cap(vertices: np.ndarray) -> float:
    """A quarter of the mesh's thinnest extent along its principal axes (m)."""
    v = np.asarray(vertices, np.float64)
    centred = v - v.mean(axis=0)
    _w, axes = np.linalg.eigh(centred.T @ centred)
    return 0.25 * float(np.ptp(centred @ axes, axis=0).min())


def collision_centres(particles: np.ndarray, vertices: np.ndarray, faces: np.ndarray, radius: float) -> np.ndarray:
    """The particles' sphere centres (N, 3): particles that are the mesh's vertices (V, 3) moved in
    along their faces' (F, 3) normals so that spheres of ``radius`` lie inside the mesh, tangent to
    it; any other particles (volume ones, inside the mesh) and radius 0 or no faces: unmoved."""
    particles = np.asarray(particles, np.float64)
    faces = np.asarray(faces, np.int64).reshape(-1, 3)
    if radius <= 0 or len(faces) == 0:
        return particles
    vertices = np.asarray(vertices, np.float64)
    if not (particles.shape == vertices.shape and np.array_equal(particles, vertices)):
        return particles
    return particles - radius * _vertex_insets(len(vertices), faces, _outward_normals(vertices, faces))


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
