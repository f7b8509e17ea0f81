"""The software renderer's data: its triangle list, and smooth vertex normals of indexed meshes.

``Triangles``: the projected triangles of one frame (see raster.py).

``VertexNormals``: each vertex's normal is the normalised sum of the area-weighted normals of
the faces around it, recomputed each frame. The faces around each vertex are listed once
(numpy, from the index array) so the sum runs in the same order every frame: no float
atomics, the same picture on every run.

All of it is Taichi ndarrays, taken by the kernels as arguments: the kernels compile once per
process (per element type), not once per renderer, mesh or larger triangle list, as kernels
that capture fields do.
"""
# (no "from __future__ import annotations": Taichi reads the kernels' annotations as objects)

import numpy as np
import taichi as ti

from ..engine.arrays import download, upload


def vec3_array(rows) -> "ti.Ndarray":
    """Rows (N, 3) as the (N,) vec3 f32 ndarray the rasteriser's kernels take."""
    rows = np.asarray(rows, np.float32).reshape(-1, 3)
    out = ti.Vector.ndarray(3, ti.f32, shape=len(rows))
    upload(out, rows)
    return out


class Triangles:
    """Room for ``capacity`` triangles, 3 vertices each: screen x, y, depth key and 1/distance
    (``vs`` [3C] vec4 f32), world normal (``vn``), world position (``vp``), colour (``vc``), each
    [3C] vec3 f32; a kind per triangle (``kind`` [C] i32). A fuller frame gets a new, larger one
    holding the first ``keep`` triangles of the ``old``."""

    def __init__(self, capacity: int, old=None, keep: int = 0):
        self.capacity = int(capacity)
        self.vs = ti.Vector.ndarray(4, ti.f32, shape=3 * self.capacity)
        self.vn = ti.Vector.ndarray(3, ti.f32, shape=3 * self.capacity)
        self.vp = ti.Vector.ndarray(3, ti.f32, shape=3 * self.capacity)
        self.vc = ti.Vector.ndarray(3, ti.f32, shape=3 * self.capacity)
        self.kind = ti.ndarray(ti.i32, shape=self.capacity)
        if old is not None and keep:
            for name in ("vs", "vn", "vp", "vc"):
                _copy_prefix(getattr(self, name), getattr(old, name), 3 * keep)
            _copy_prefix(self.kind, old.kind, keep)

    @property
    def arrays(self) -> tuple:
        """(vs, vn, vp, vc, kind), in the order the kernels take them."""
        return self.vs, self.vn, self.vp, self.vc, self.kind


class VertexNormals:
    def __init__(self):
        self._cache = {}  # id(vertices), id(indices) -> (vertices, indices, offsets, faces, face normals, normals)

    def of(self, vertices, indices):
        """The normals (V,) vec3 f32 ndarray for this frame's ``vertices`` and the fixed ``indices``."""
        key = (id(vertices), id(indices))
        entry = self._cache.get(key)
        if entry is None:
            entry = self._cache[key] = (vertices, indices, *_adjacency(download(indices), vertices.shape[0]))
        _, _, offsets, faces, face_normals, normals = entry
        _smooth_normals(vertices, indices, offsets, faces, face_normals, normals)
        return normals


def _adjacency(idx: np.ndarray, num_vertices: int):
    """Faces around each vertex: offsets (V+1,) into faces (3F,), and the ndarrays of the faces'
    normals (F,) and the vertices' (V,)."""
    idx = idx.reshape(-1).astype(np.int64)
    face_of = np.repeat(np.arange(len(idx) // 3), 3)
    order = np.argsort(idx, kind="stable")
    counts = np.bincount(idx, minlength=num_vertices)
    offsets = ti.ndarray(ti.i32, shape=num_vertices + 1)
    upload(offsets, np.concatenate([[0], np.cumsum(counts)]))
    faces = ti.ndarray(ti.i32, shape=max(1, len(idx)))
    upload(faces, face_of[order] if len(idx) else np.zeros(1))
    return (offsets, faces, ti.Vector.ndarray(3, ti.f32, shape=max(1, len(idx) // 3)),
            ti.Vector.ndarray(3, ti.f32, shape=num_vertices))


@ti.kernel
def _smooth_normals(verts: ti.types.ndarray(), idx: ti.types.ndarray(), offsets: ti.types.ndarray(),
                    faces: ti.types.ndarray(), face_n: ti.types.ndarray(), out: ti.types.ndarray()):
    # Each face's (area-weighted) normal once, then each vertex's sum of its faces' in a fixed
    # order: the same sums as crossing each face again at each of its three vertices, a third
    # of the work (the pile's 24 tori alone have 196,000 faces).
    for f in range(idx.shape[0] // 3):
        p0 = ti.cast(verts[idx[3 * f]], ti.f32)
        p1 = ti.cast(verts[idx[3 * f + 1]], ti.f32)
        p2 = ti.cast(verts[idx[3 * f + 2]], ti.f32)
        face_n[f] = (p1 - p0).cross(p2 - p0)
    for v in range(out.shape[0]):
        total = ti.Vector([0.0, 0.0, 0.0], ti.f32)
        for j in range(offsets[v], offsets[v + 1]):
            total += face_n[faces[j]]
        out[v] = ti.cast(total.normalized(1e-20), ti.f32)


@ti.kernel
def _copy_prefix(dst: ti.types.ndarray(), src: ti.types.ndarray(), n: ti.i32):
    for i in range(n):
        dst[i] = src[i]


def closed_and_outward(vertices: np.ndarray, faces: np.ndarray, face_body: np.ndarray) -> bool:
    """Whether back faces may be skipped: every edge is met by exactly two triangles in opposite
    directions (closed, consistently wound), and each body's signed volume is positive (its
    triangles wind counter-clockwise seen from outside). Then no back face can be seen from
    outside a body, and skipping them halves the triangles to rasterise."""
    faces = np.asarray(faces, np.int64).reshape(-1, 3)
    if not len(faces):
        return False
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    n = int(faces.max()) + 1
    forward = directed[:, 0] * n + directed[:, 1]
    backward = directed[:, 1] * n + directed[:, 0]
    unique, counts = np.unique(forward, return_counts=True)
    if (counts != 1).any() or not np.isin(backward, unique).all():
        return False
    v = np.asarray(vertices, np.float64)
    a, b, c = v[faces[:, 0]], v[faces[:, 1]], v[faces[:, 2]]
    volume = np.bincount(face_body, weights=(a * np.cross(b, c)).sum(axis=1) / 6.0)
    return bool((volume[np.unique(face_body)] > 0).all())
