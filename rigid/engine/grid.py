"""A uniform grid over the particles, built by a counting sort (bodies in contact) whenever the
neighbour lists (neighbours.py) are rebuilt.

Cells are cubes of side h = the largest particle diameter + the lists' skin, so two particles
within reach + skin lie in the same or adjacent cells. The grid has D³ cells (D a power of two, D³ about twice the
particle count) and wraps: a particle at p lies in cell ⌊p/h⌋ mod D on each axis, so the world
needs no bounds and far-apart particles sharing a wrapped cell only cost a distance test.
Every particle goes in its cell: no cap per cell (Harada's GPU Gems 3 grid keeps 4 a cell and
drops the rest, which drops contacts).

Build (taichi_dem's count / prefix sum / scatter):
  count:   cell_count[c] = particles in c                 (atomic add, per particle)
  scan:    cell_start[c] = Σ_{c' < c} cell_count[c']       (scan.py)
  scatter: sorted_particle[cell_start[c] ...] = particles of c (atomic cursor)
  order:   each cell's particles by slot (a parallel scatter's order varies; a fixed order
           keeps every later sum, and so every run, bit-reproducible); then in each cell
           where each body's run of particles ends (the list build skips its own body's)
Neighbours of a particle: the 3 × 3 rows of 3 cells around it; a row's three cells are
consecutive in memory unless it wraps, so it is one range of sorted_particle.

Scratch arrays (ScratchArgs): ``cell_count`` [C] i32 (then the scatter's cursors), ``cell_start`` [C + 1] i32,
``sorted_particle`` [N] i32, and in that sorted order copies of each particle's
``sorted_x`` [N] vec3 (world) and ``sorted_body`` [N] i32, and ``sorted_run_end`` [N] i32
(mark_runs); D, C and the scan's chunks, and 1/h, are broadphase.py's named scalars (GRID_DIM,
GRID_CELLS, GRID_CHUNKS; INV_CELL). ``GridShape`` sizes them on the host.
"""

from dataclasses import dataclass

import taichi as ti

from . import broadphase as bp
from .scan import CHUNK, scan_parallel, scan_serial


SPAN_MAX_DIM = 64  # the box's span alone never asks for more than 64³ cells


def grid_dimension(num_particles: int, span_cells: float = 0.0) -> int:
    """Cells per axis: the power of two with D³ >= 2 N, at least 8 and at most 256, and at least
    the box's span in cells (up to SPAN_MAX_DIM): a small scene's grid then does not wrap inside
    the box, where wrapped cells would bring far particles in as candidates. The grid is built
    only when the neighbour lists are, so a few more cells cost little."""
    d = 8
    while d * d * d < 2 * num_particles and d < 256:
        d *= 2
    while d < span_cells and d < SPAN_MAX_DIM:
        d *= 2
    return d


@dataclass
class GridShape:
    """The grid's sizes for N particles (no grid without pairs: one cell)."""

    dim: int
    num_cells: int
    num_chunks: int

    @classmethod
    def for_particles(cls, num_particles: int, pairs: bool, span_cells: float = 0.0) -> "GridShape":
        """``span_cells``: the box's width in cells (0: no walls)."""
        dim = grid_dimension(num_particles, span_cells) if pairs else 1
        cells = dim ** 3
        return cls(dim, cells, max(1, (cells + CHUNK - 1) // CHUNK))


@ti.func
def cell_coords(s: ti.template(), p):
    """Integer cell coordinates (unwrapped) of a world point."""
    return ti.floor(p * bp.value(s, bp.INV_CELL), ti.i32)


@ti.func
def cell_index(s: ti.template(), ix, iy, iz):
    D = bp.get(s, bp.GRID_DIM)
    mask = D - 1
    return ((iz & mask) * D + (iy & mask)) * D + (ix & mask)


@ti.func
def particle_coords(s: ti.template(), model: ti.template(), i, p):
    """The cell coordinates of slot i at p: its world's cells are shifted (``model.body_world``,
    worlds.py), so that many worlds' copies of one place fall in different cells (one world: 0)."""
    packed = model.body_world[model.particle_body[i]][0]
    return cell_coords(s, p) + ti.Vector([packed & 1023, (packed >> 10) & 1023, packed >> 20])


@ti.func
def same_world(model: ti.template(), a, b):
    """Whether bodies a and b are in one world (no contact across worlds)."""
    return model.body_world[a][1] == model.body_world[b][1]


@ti.func
def particle_cell(s: ti.template(), model: ti.template(), state: ti.template(), i):
    """The cell of slot i (recomputed where needed: the same operations on the same position)."""
    g = particle_coords(s, model, i, state.particle_x[i])
    return cell_index(s, g[0], g[1], g[2])


@ti.func
def count_particle(s: ti.template(), model: ti.template(), state: ti.template(), i):
    """Count slot i in its cell (atomic: particles may run in parallel)."""
    ti.atomic_add(s.cell_count[particle_cell(s, model, state, i)], 1)


@ti.func
def scatter_particle(s: ti.template(), model: ti.template(), state: ti.template(), i):
    slot = ti.atomic_add(s.cell_count[particle_cell(s, model, state, i)], 1)
    s.sorted_particle[slot] = i


@ti.func
def sort_cell(s: ti.template(), c):
    """Insertion sort of one cell's slots (cells hold a few particles)."""
    lo, hi = s.cell_start[c], s.cell_start[c + 1]
    for a in range(lo + 1, hi):
        value = s.sorted_particle[a]
        k = a - 1
        while k >= lo and s.sorted_particle[k] > value:
            s.sorted_particle[k + 1] = s.sorted_particle[k]
            k -= 1
        s.sorted_particle[k + 1] = value


@ti.func
def mark_runs(s: ti.template(), c):
    """sorted_run_end over cell c: for each of its particles, where the run of its body's particles
    in the cell ends (a cell is sorted by slot, and a body's slots are contiguous, so its
    particles in a cell form one run): the list build passes over its own body's in one step."""
    lo, hi = s.cell_start[c], s.cell_start[c + 1]
    end = hi
    for t in range(hi - lo):  # backwards: a run's end is known from its last particle's
        k = hi - 1 - t
        if k + 1 < hi and s.sorted_body[k + 1] != s.sorted_body[k]:
            end = k + 1
        s.sorted_run_end[k] = end


@ti.func
def gather_sorted(s: ti.template(), model: ti.template(), state: ti.template(), k):
    """Slot k of the sorted order: a copy of its particle's position and body, so that the pair
    search streams through neighbours in memory order instead of jumping to each one."""
    i = s.sorted_particle[k]
    s.sorted_x[k] = state.particle_x[i]
    s.sorted_body[k] = model.particle_body[i]


# A build is clear and count (``count_particle`` for every particle), then finish_*. The
# neighbour lists (neighbours.py) rebuild the grid only when they need it: every loop of a
# build runs over ``size * gate`` items (gate 0 or 1, read from the device), so that in a
# parallel kernel it stays a top-level (parallel) loop and costs nothing when gate is 0.

@ti.func
def clear_and_count(s: ti.template(), model: ti.template(), state: ti.template(), gate):
    for c in range(bp.get(s, bp.GRID_CELLS) * gate):
        s.cell_count[c] = 0
    for i in range(state.particle_x.shape[0] * gate):
        count_particle(s, model, state, i)


@ti.func
def finish_serial(s: ti.template(), model: ti.template(), state: ti.template(), gate):
    """The rest of the build on one thread: scattering in slot order leaves every cell sorted."""
    C, N = bp.get(s, bp.GRID_CELLS) * gate, state.particle_x.shape[0] * gate
    if gate:
        scan_serial(s.cell_count, s.cell_start, C)
    for c in range(C):
        s.cell_count[c] = s.cell_start[c]  # the counts are summed: reuse them as cursors
    for i in range(N):
        scatter_particle(s, model, state, i)
    for k in range(N):
        gather_sorted(s, model, state, k)
    for c in range(C):
        mark_runs(s, c)


@ti.func
def finish_parallel(s: ti.template(), model: ti.template(), state: ti.template(), gate):
    """The rest of the build as top-level loops of a kernel (each runs in parallel); each cell is
    then sorted by slot and its copies gathered."""
    scan_parallel(s.cell_count, s.cell_start, s.chunk_total, bp.get(s, bp.GRID_CELLS) * gate,
                  bp.get(s, bp.GRID_CHUNKS) * gate)
    for c in range(bp.get(s, bp.GRID_CELLS) * gate):
        s.cell_count[c] = s.cell_start[c]  # the counts are summed: reuse them as cursors
    for i in range(state.particle_x.shape[0] * gate):
        scatter_particle(s, model, state, i)
    for c in range(bp.get(s, bp.GRID_CELLS) * gate):
        sort_cell(s, c)
        lo, hi = s.cell_start[c], s.cell_start[c + 1]
        for k in range(lo, hi):
            gather_sorted(s, model, state, k)
        mark_runs(s, c)


@ti.func
def row_range(s: ti.template(), ix, iy, iz, part):
    """The ``part``-th range of sorted_particle holding row (iy, iz)'s cells ix-1..ix+1: one range
    (part 0) where the row does not wrap, else one per cell (parts 0..2)."""
    D = bp.get(s, bp.GRID_DIM)
    lo, hi = 0, 0
    x = ix & (D - 1)
    if 1 <= x and x <= D - 2:
        if part == 0:
            c = cell_index(s, ix, iy, iz)
            lo, hi = s.cell_start[c - 1], s.cell_start[c + 2]
    else:
        c = cell_index(s, ix - 1 + part, iy, iz)
        lo, hi = s.cell_start[c], s.cell_start[c + 1]
    return lo, hi


ROWS_AROUND = 27  # around_range: 3 × 3 rows (z outer, then y) × their up to 3 ranges


@ti.func
def around_range(s: ti.template(), g, r):
    """The r-th of the ROWS_AROUND ranges of sorted_particle that hold the 27 cells around cell g
    (rows dz, dy = -1..1, z outer, each row's row_range parts 0..2): one loop over r walks them
    in that fixed order."""
    return row_range(s, g[0], g[1] + (r // 3) % 3 - 1, g[2] + r // 9 - 1, r % 3)


@ti.func
def each_slot_around(scratch: ti.template(), g, visit: ti.template(), ctx: ti.template()):
    """visit(ctx, slot) for each slot of the grid's sorted order in the 27 cells around cell g, in
    the fixed order of grid.around_range (the lists' builds and the overflow walk share it)."""
    for r in range(ROWS_AROUND):
        lo, hi = around_range(scratch, g, r)
        for slot in range(lo, hi):
            visit(ctx, slot)
