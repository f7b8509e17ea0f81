"""Soft contact shadows on the floor: a dark blur under each body that sharpens as it lands.

Height above a checkered floor is hard to judge without shadows. A shadow map proper needs a
second rasterisation from the light; a contact shadow is cheaper and reads height as well: each
body darkens the floor under it with an elliptical Gaussian of its footprint (the mean and
covariance of its drawn vertices' x, z), blurred and faded with the height of its lowest point
above the floor. The floor is sampled on a small grid (``SIZE``² cells over the box) once per
frame, each cell multiplying the bodies' factors in body order (the same picture on every
run), and the rasteriser's floor pixels are multiplied by it (bilinear). Cost: rows × bodies
cheap tests, then the cells of each body's box, an exponential only near a body.
"""
# (no "from __future__ import annotations": Taichi reads the kernels' annotations as objects)

import numpy as np
import taichi as ti

from ..engine.arrays import upload

SIZE = 96  # cells along each side of the floor (2 cm in the 2 m box; the shadows are soft)
DARKEST = 0.55  # a body resting on the floor takes this fraction of the light under its middle
BLUR, MAX_BLUR = 0.35, 0.12  # m: the blur's standard deviation grows by BLUR per metre of height, to MAX_BLUR
FADE = 0.6  # m: the shadow's darkness falls as 1 / (1 + h / FADE), h the lowest point's height
CUTOFF = 12.0  # Mahalanobis² beyond which a body's factor is 1 (exp(-6) ~ 0.25 %)


class ContactShadows:
    def __init__(self, num_bodies: int, floor: float, half_width: float, points=None, counts=None):
        """``points`` (V, 3) and ``counts`` (B,): the drawn points of each body, in its own frame
        about its centre of mass (body after body); their mean and covariance there give the
        footprint, turned with the body every frame (no per-vertex work per frame). Its arrays
        are ndarrays, so its kernels compile once per process, whatever the scene."""
        self.floor, self.half = float(floor), float(half_width)
        self.shade = ti.ndarray(ti.f32, shape=(SIZE, SIZE))
        # per body: mean x, mean z, inverse covariance (xx, xz, zz), darkness, cell box (i0, i1, k0, k1)
        self.blobs = ti.Vector.ndarray(10, ti.f32, shape=max(1, num_bodies))
        self.box = ti.Vector.ndarray(3, ti.f32, shape=1)  # x0, z0, cells per metre
        upload(self.box, [-self.half, -self.half, SIZE / (2.0 * self.half)])
        self.num_bodies = num_bodies
        points = np.asarray(points, np.float64).reshape(-1, 3)
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        n = np.maximum(np.asarray(counts, np.float64), 1.0)[:, None]
        mean0 = np.add.reduceat(points, starts) / n  # (B, 3) in the body frame
        rel = points - np.repeat(mean0, counts, axis=0)
        cov0 = np.add.reduceat(rel[:, :, None] * rel[:, None, :], starts) / n[:, :, None]  # (B, 3, 3)
        self.mean0 = ti.Vector.ndarray(3, ti.f32, shape=max(1, num_bodies))
        self.cov0 = ti.Matrix.ndarray(3, 3, ti.f32, shape=max(1, num_bodies))
        upload(self.mean0, mean0)
        upload(self.cov0, cov0)

    def update(self, x, R) -> None:
        """Recompute the floor's shade for bodies at centres ``x`` (an ndarray of B vec3, e.g. the
        simulator's ``state.x``), rotations ``R`` (B mat3, ``state.R``): read on the device, no copy
        to the host."""
        _blobs(x, R, self.mean0, self.cov0, self.blobs, self.num_bodies, self.floor, self.half)
        _shade(self.shade, self.box, self.blobs, self.num_bodies)


@ti.kernel
def _blobs(x: ti.types.ndarray(), R: ti.types.ndarray(), mean0: ti.types.ndarray(), cov0: ti.types.ndarray(),
           blobs: ti.types.ndarray(), num_bodies: ti.i32, floor: ti.f32, half: ti.f32):
    cells = SIZE / (2.0 * half)
    for b in range(num_bodies):
        rot = ti.cast(R[b], ti.f32)
        mean = ti.cast(x[b], ti.f32) + rot @ mean0[b]
        cov = rot @ cov0[b] @ rot.transpose()
        # The lowest point, as for a uniform spread: the mean less √3 standard deviations
        # (exact for a sphere's surface), never below the floor.
        height = ti.max(mean[1] - ti.sqrt(3.0 * ti.max(cov[1, 1], 0.0)) - floor, 0.0)
        blur = ti.min(BLUR * height + 0.01, MAX_BLUR) ** 2  # (and a small box of cells for each body)
        sxx, szz, sxz = cov[0, 0] + blur, cov[2, 2] + blur, cov[0, 2]
        det = ti.max(sxx * szz - sxz * sxz, 1e-12)
        # The cells where the factor matters: |d_x| <= sqrt(CUTOFF sxx), likewise in z.
        rx, rz = ti.sqrt(CUTOFF * sxx) * cells, ti.sqrt(CUTOFF * szz) * cells
        ci, ck = (mean[0] + half) * cells, (mean[2] + half) * cells
        box = ti.math.clamp(ti.Vector([ci - rx, ci + rx, ck - rz, ck + rz]), -1.0, SIZE * 1.0)
        blobs[b] = ti.Vector([mean[0], mean[2], szz / det, -sxz / det, sxx / det,
                              DARKEST / (1.0 + height / FADE), box[0], box[1], box[2], box[3]], ti.f32)


@ti.kernel
def _shade(shade: ti.types.ndarray(), boxes: ti.types.ndarray(), blobs: ti.types.ndarray(), num_bodies: ti.i32):
    # Row by row; in each, the bodies in order, each multiplying only the cells of its box in
    # that row: every cell gets its factors in body order, as from a loop over all bodies at
    # each cell, for rows x bodies box tests instead of cells x bodies (1,000 bodies: 96
    # thousand, not 9.2 million). Taichi's CPU backend runs a loop of 96 on one thread (it hands
    # out 512 iterations at a time; rigid.engine.schedule), which is still faster here.
    # The shade agrees with that loop's to float32 round-off (LLVM contracts q differently).
    box = boxes[0]
    for i in range(SIZE):
        for k in range(SIZE):
            shade[i, k] = 1.0
        for b in range(num_bodies):
            blob = blobs[b]
            if blob[6] <= i and i <= blob[7]:
                dx = box[0] + (i + 0.5) / box[2] - blob[0]
                k0 = ti.max(0, ti.cast(ti.ceil(blob[8]), ti.i32))
                k1 = ti.min(SIZE - 1, ti.cast(ti.floor(blob[9]), ti.i32))
                for k in range(k0, k1 + 1):
                    dz = box[1] + (k + 0.5) / box[2] - blob[1]
                    q = blob[2] * dx * dx + 2.0 * blob[3] * dx * dz + blob[4] * dz * dz
                    if q < CUTOFF:
                        shade[i, k] *= 1.0 - blob[5] * ti.exp(-0.5 * q)


@ti.func
def shade_at(shade: ti.template(), boxes: ti.template(), p):
    """The shade (ContactShadows' ``shade``, ``box``) at world point p on the floor (bilinear
    between cell centres; 1 off the grid)."""
    box = boxes[0]
    u = (p[0] - box[0]) * box[2] - 0.5
    v = (p[2] - box[1]) * box[2] - 0.5
    i0 = ti.cast(ti.floor(u), ti.i32)
    k0 = ti.cast(ti.floor(v), ti.i32)
    fu, fv = u - i0, v - k0
    total = 0.0
    for di, dk in ti.static(ti.ndrange(2, 2)):
        i = ti.min(ti.max(i0 + di, 0), SIZE - 1)
        k = ti.min(ti.max(k0 + dk, 0), SIZE - 1)
        weight = (fu if di else 1.0 - fu) * (fv if dk else 1.0 - fv)
        total += weight * shade[i, k]
    return total
