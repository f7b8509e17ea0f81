"""Soft contact shadows on the floor: a dark blur under each body that sharpens as it lands.

Height above a checkered floor is hard to judge without shadows. A shadow map proper needs a
second rasterisation from the light; a contact shadow is cheaper and reads height as well: each
body darkens the floor under it with an elliptical Gaussian of its footprint (the mean and
covariance of its drawn vertices' x, z), blurred and faded with the height of its lowest point
above the floor. The floor is sampled on a small grid (``SIZE``² cells over the box) once per
frame, each cell multiplying the bodies' factors in body order (the same picture on every
run), and the rasteriser's floor pixels are multiplied by it (bilinear). Cost: cells × bodies
cheap tests, an exponential only near a body.
"""
# (no "from __future__ import annotations": Taichi reads the kernels' annotations as objects)

import numpy as np
import taichi as ti

SIZE = 128  # cells along each side of the floor
DARKEST = 0.55  # a body resting on the floor takes this fraction of the light under its middle
BLUR = 0.35  # the blur's standard deviation grows by this many metres per metre of height
FADE = 0.6  # m: the shadow's darkness falls as 1 / (1 + h / FADE), h the lowest point's height
CUTOFF = 18.0  # Mahalanobis² beyond which a body's factor is 1 (exp(-9) ~ 1e-4)


@ti.data_oriented
class ContactShadows:
    def __init__(self, num_bodies: int, floor: float, half_width: float):
        self.floor, self.half = float(floor), float(half_width)
        self.shade = ti.field(ti.f32, shape=(SIZE, SIZE))
        # per body: mean x, mean z, inverse covariance (xx, xz, zz), darkness
        self.blobs = ti.Vector.field(6, ti.f32, shape=max(1, num_bodies))
        self.box = ti.Vector.field(3, ti.f32, shape=1)  # x0, z0, cells per metre
        self.box.from_numpy(np.array([[-self.half, -self.half, SIZE / (2.0 * self.half)]], np.float32))
        self.num_bodies = num_bodies

    def update(self, points: np.ndarray, counts: np.ndarray) -> None:
        """Recompute the floor's shade from the bodies' drawn points ((V, 3), body after body,
        ``counts`` per body)."""
        points = np.asarray(points, np.float64)
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        n = np.maximum(np.asarray(counts, np.float64), 1.0)
        x, z = points[:, 0], points[:, 2]
        mx, mz = np.add.reduceat(x, starts) / n, np.add.reduceat(z, starts) / n
        sxx = np.add.reduceat(x * x, starts) / n - mx * mx
        szz = np.add.reduceat(z * z, starts) / n - mz * mz
        sxz = np.add.reduceat(x * z, starts) / n - mx * mz
        height = np.maximum(np.minimum.reduceat(points[:, 1], starts) - self.floor, 0.0)
        blur = (BLUR * height + 0.01) ** 2
        sxx, szz = sxx + blur, szz + blur
        det = np.maximum(sxx * szz - sxz * sxz, 1e-12)
        dark = DARKEST / (1.0 + height / FADE)
        blobs = np.stack([mx, mz, szz / det, -sxz / det, sxx / det, dark], axis=1)
        self.blobs.from_numpy(blobs.astype(np.float32))
        self._shade(self.num_bodies)

    @ti.kernel
    def _shade(self, num_bodies: ti.i32):
        box = self.box[0]
        for i, k in self.shade:
            px = box[0] + (i + 0.5) / box[2]
            pz = box[1] + (k + 0.5) / box[2]
            light = 1.0
            for b in range(num_bodies):  # in body order: the same product every run
                blob = self.blobs[b]
                dx, dz = px - blob[0], pz - blob[1]
                q = blob[2] * dx * dx + 2.0 * blob[3] * dx * dz + blob[4] * dz * dz
                if q < CUTOFF:
                    light *= 1.0 - blob[5] * ti.exp(-0.5 * q)
            self.shade[i, k] = light

    @ti.func
    def at(self, p):
        """The shade at world point p on the floor (bilinear between cell centres; 1 off the grid)."""
        box = self.box[0]
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
            total += weight * self.shade[i, k]
        return total
