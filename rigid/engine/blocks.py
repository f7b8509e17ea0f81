"""Particles grouped into small, spatially compact blocks, for the force loop.

The force loop visits a body's particles block by block. Each block carries a
bounding box in the body frame (centre c, half-extents h); once per substep the
box, moved to the world by (x, R), says which planes of the box a particle of
the block may be behind, and the block's particles are tested against those
planes only (wrench.py): the others' forces would be exactly zero there. A body
in flight tests no plane at all. The block is also the unit of work and of
summation of the parallel path: F and τ are summed per block in a fixed order,
then over blocks in block order, so the result does not depend on how many
threads ran the blocks.

Blocks are cut from the body's particles sorted along a Morton (Z-order) curve
of their body-frame positions, so consecutive particles are close in space: a
volume-sampled body gives 4×4×4-cell cubes. The order inside the blocks is
this sorted order; the Model keeps the original one (particle i = vertex i).

Fields (float is the run's precision), N particles, K blocks, B bodies:
- ``r0``           [N] vec3  body-frame offsets from the centre of mass, block order (SoA)
- ``block_start``, ``block_count`` [K] i32  block k holds r0[start : start + count]
- ``block_body``   [K] i32   the body that owns block k
- ``block_centre`` [K] vec3  centre of the block's bounding box, body frame
- ``block_half``   [K] vec3  half-extents of that box (rounded up), body frame
- ``body_block_start``, ``body_block_count`` [B] i32  body b's blocks, consecutive
"""
from __future__ import annotations

import numpy as np
import taichi as ti

SMALL_BLOCK = 64  # particles per block for bodies up to MANY_BLOCKS * SMALL_BLOCK particles
MANY_BLOCKS = 4096  # bigger bodies get bigger blocks, so the per-substep sum over blocks stays short


def block_size_for(num_particles: int) -> int:
    """64 particles per block, doubled until a body has at most ~4096 blocks (1M -> 256)."""
    size = SMALL_BLOCK
    while num_particles > MANY_BLOCKS * size:
        size *= 2
    return size


def morton_order(points: np.ndarray) -> np.ndarray:
    """Indices sorting points (n, 3) along a Z-order curve of 10 bits per axis."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    span = np.where(hi > lo, hi - lo, 1.0)
    cells = np.minimum((points - lo) / span * 1024, 1023).astype(np.uint64)

    def spread(v):  # put two zero bits between the bits of a 10-bit integer
        v = (v | (v << np.uint64(16))) & np.uint64(0x030000FF)
        v = (v | (v << np.uint64(8))) & np.uint64(0x0300F00F)
        v = (v | (v << np.uint64(4))) & np.uint64(0x030C30C3)
        return (v | (v << np.uint64(2))) & np.uint64(0x09249249)

    code = spread(cells[:, 0]) | (spread(cells[:, 1]) << np.uint64(1)) | (spread(cells[:, 2]) << np.uint64(2))
    return np.argsort(code, kind="stable")


def block_layout(r0: np.ndarray, body_start, body_count, block_size: int) -> dict:
    """Host-side layout (float64 numpy) of the blocks of every body; see the module docstring."""
    order, starts, counts, owners, centres, halves = [], [], [], [], [], []
    body_block_start, body_block_count = [], []
    for b, (start, count) in enumerate(zip(body_start, body_count)):
        body_order = start + morton_order(r0[start:start + count])
        body_block_start.append(len(starts))
        for k0 in range(0, count, block_size):
            members = body_order[k0:k0 + block_size]
            points = r0[members]
            lo, hi = points.min(axis=0), points.max(axis=0)
            starts.append(start + k0)
            counts.append(len(members))
            owners.append(b)
            centres.append(0.5 * (lo + hi))
            halves.append(np.maximum(hi - 0.5 * (lo + hi), 0.5 * (lo + hi) - lo))
        body_block_count.append(len(starts) - body_block_start[-1])
        order.append(body_order)
    return dict(order=np.concatenate(order), block_start=np.array(starts), block_count=np.array(counts),
                block_body=np.array(owners), block_centre=np.array(centres), block_half=np.array(halves),
                body_block_start=np.array(body_block_start), body_block_count=np.array(body_block_count))


class ParticleBlocks:
    """The blocks of a Model's bodies as Taichi fields (see the module docstring)."""

    def __init__(self, model, block_size: int | None = None):
        r0 = model.r0_np
        body_start = model.body_start.to_numpy()
        body_count = model.body_count.to_numpy()
        self.largest_body = int(body_count.max())  # particles
        self.block_size = block_size or block_size_for(self.largest_body)
        layout = block_layout(r0, body_start, body_count, self.block_size)
        self.num_blocks = k = len(layout["block_start"])
        self.order = layout["order"]  # r0 here = model r0[order]
        fp = np.float64 if ti.lang.impl.current_cfg().default_fp == ti.f64 else np.float32
        # Structure of arrays: the vectorised particle loop loads 8 x, 8 y, 8 z at once.
        self.r0 = ti.Vector.field(3, float, shape=len(r0), layout=ti.Layout.SOA)
        self.block_start = ti.field(ti.i32, shape=k)
        self.block_count = ti.field(ti.i32, shape=k)
        self.block_body = ti.field(ti.i32, shape=k)
        self.block_centre = ti.Vector.field(3, float, shape=k)
        self.block_half = ti.Vector.field(3, float, shape=k)
        self.body_block_start = ti.field(ti.i32, shape=len(body_start))
        self.body_block_count = ti.field(ti.i32, shape=len(body_start))
        self.r0.from_numpy(r0[self.order].astype(fp))
        for name in ("block_start", "block_count", "block_body", "body_block_start", "body_block_count"):
            getattr(self, name).from_numpy(layout[name].astype(np.int32))
        self.block_centre.from_numpy(layout["block_centre"].astype(fp))
        # Round the half-extents up so that the float copy never under-covers its block.
        self.block_half.from_numpy(np.nextafter(layout["block_half"].astype(fp), fp(np.inf)))
