"""Particles grouped into small, spatially compact blocks: the unit of work of a substep.

The force stage visits a body's particles block by block (stages.py). Each block
carries the bounding box of its particles' centres in the body frame (centre c, half
extents h) and the sphere about c that holds them (reach ρ); once per substep these,
moved to the world by (x, R), say which static planes a particle of the block may touch,
and the block's particles are tested against those planes only: the others' forces would
be exactly zero there. A body in flight tests no plane at all. (The box is the tighter
bound for flat and cubic blocks: a torus at rest reaches the floor with 13 of its 32
blocks by their boxes, 31 by their spheres; the sphere for round ones.) The block is also
the unit of summation: F and τ are summed per block over its particles in slot order, then
over the body's blocks in block order, so the sums do not depend on how many threads ran
the blocks.

Blocks are cut from the body's particles sorted along a Morton (Z-order) curve
of their body-frame positions, so consecutive particles are close in space: a
volume-sampled body gives 8×4×4-cell boxes. The order inside the blocks is
this sorted order, which is the Model's slot order (``Model.order``, ``Model.slot_of``).

The layout (numpy arrays), N particles, K blocks, B bodies:
- ``order``        [N]   the particles (file order) in slot order: the Model stores them so
- ``block_start``, ``block_count`` [K]  block k holds slots start .. start + count − 1
- ``block_body``   [K]   the body that owns block k
- ``block_centre`` [K, 3] centre of the block's bounding box, body frame
- ``block_half``   [K, 3] that box's half extents along the body's axes (it holds every particle centre)
- ``block_reach``  [K]   radius of the sphere about that centre holding every particle centre
- ``body_block_start``, ``body_block_count`` [B]  body b's blocks, consecutive
"""
from __future__ import annotations

import numpy as np

# Particles per block for bodies up to MANY_BLOCKS * SMALL_BLOCK particles. Each block costs a
# reach test and a share of the sums every substep: 128 ran a lone big mesh (the course's cat,
# the torus, a 4,096-particle cube) 11-20 % faster than 64, whose tighter bounds test fewer
# particles against the planes, and 256 no faster again (report/bench_versions.md).
SMALL_BLOCK = 128
MANY_BLOCKS = 4096  # bigger bodies get bigger blocks, so the per-substep sum over blocks stays short


def block_size_for(num_particles: int) -> int:
    """128 particles per block, doubled until a body has at most ~4096 blocks (1M -> 256)."""
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
    """Host-side layout (numpy) of the blocks of every body; see the module docstring."""
    order, starts, counts, owners, centres, halves, reaches = [], [], [], [], [], [], []
    body_block_start, body_block_count = [], []
    for b, (start, count) in enumerate(zip(body_start, body_count)):
        body_order = start + morton_order(r0[start:start + count])
        body_block_start.append(len(starts))
        for k0 in range(0, count, block_size):
            members = body_order[k0:k0 + block_size]
            points = r0[members]
            centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
            starts.append(start + k0)
            counts.append(len(members))
            owners.append(b)
            centres.append(centre)
            halves.append(np.abs(points - centre).max(axis=0))
            reaches.append(float(np.sqrt(((points - centre) ** 2).sum(axis=1).max())))
        body_block_count.append(len(starts) - body_block_start[-1])
        order.append(body_order)
    return dict(order=np.concatenate(order), block_start=np.array(starts), block_count=np.array(counts),
                block_body=np.array(owners), block_centre=np.array(centres), block_half=np.array(halves),
                block_reach=np.array(reaches), body_block_start=np.array(body_block_start),
                body_block_count=np.array(body_block_count))
