"""A uniform grid over the particles, rebuilt every substep by a counting sort.

Cells are cubes of side h = the largest particle diameter, so two particles
that touch lie in the same or adjacent cells. The grid has D³ cells (D a power
of two, D³ about twice the particle count) and wraps: particle p lies in cell
(⌊p/h⌋ mod D) on each axis, so the world needs no bounds and far-apart
particles that share a wrapped cell only cost a distance test. Every particle
goes in its cell: no cap per cell (Harada's GPU Gems 3 grid keeps 4 a cell and
drops the rest, which drops contacts).

Build (taichi_dem's count / prefix sum / scatter):
  count:   cell_count[c] = particles in c                 (atomic add, per particle)
  scan:    cell_start[c] = Σ_{c' < c} cell_count[c']       (scan.py)
  scatter: sorted_particle[cell_start[c] ...] = particles of c (atomic cursor)
  order:   each cell's particles by index (parallel scatter order varies; a fixed
           order keeps every later sum, and so every run, bit-reproducible)
Neighbours of a particle: the 3 × 3 rows of 3 cells around it; a row's three
cells are consecutive in memory unless it wraps, so it is one range of
sorted_particle (9 ranges instead of 27 cells).
"""
import taichi as ti

from .scan import make_scan


def grid_dimension(num_particles: int) -> int:
    """Cells per axis: the power of two with D³ >= 2 N, at least 8 and at most 256."""
    d = 8
    while d * d * d < 2 * num_particles and d < 256:
        d *= 2
    return d


class NeighbourGrid:
    def __init__(self, num_particles: int, cell_size: float):
        self.dim = D = grid_dimension(num_particles)
        self.num_cells = C = D * D * D
        self.cell_size = float(cell_size)
        n = max(num_particles, 1)
        self.cell_count = ti.field(ti.i32, shape=C)
        self.cell_start = ti.field(ti.i32, shape=C + 1)
        self.cell_cursor = ti.field(ti.i32, shape=C)
        self.particle_cell = ti.field(ti.i32, shape=n)
        self.sorted_particle = ti.field(ti.i32, shape=n)
        self.scan_parallel, self.scan_serial = make_scan(self.cell_count, self.cell_start, C)
        self._build_funcs()

    def _build_funcs(self):
        D, mask = self.dim, self.dim - 1
        inv_h = 1.0 / self.cell_size
        count, start, cursor = self.cell_count, self.cell_start, self.cell_cursor
        cell_of, order = self.particle_cell, self.sorted_particle

        @ti.func
        def cell_coords(p):
            """Integer cell coordinates (unwrapped) of a world point."""
            return ti.floor(p * inv_h, ti.i32)

        @ti.func
        def cell_index(ix, iy, iz):
            return ((iz & mask) * D + (iy & mask)) * D + (ix & mask)

        @ti.func
        def clear_cell(c):
            count[c] = 0

        @ti.func
        def insert(i, p):
            """Record particle i at p in its cell (atomic: particles run in parallel)."""
            g = cell_coords(p)
            c = cell_index(g[0], g[1], g[2])
            cell_of[i] = c
            ti.atomic_add(count[c], 1)

        @ti.func
        def open_cell(c):
            cursor[c] = start[c]

        @ti.func
        def scatter(i):
            slot = ti.atomic_add(cursor[cell_of[i]], 1)
            order[slot] = i

        @ti.func
        def sort_cell(c):
            """Insertion sort of one cell's particles by index (cells hold a few particles)."""
            lo, hi = start[c], start[c + 1]
            for a in range(lo + 1, hi):
                value = order[a]
                k = a - 1
                while k >= lo and order[k] > value:
                    order[k + 1] = order[k]
                    k -= 1
                order[k + 1] = value

        @ti.func
        def row_range(ix, iy, iz, part):
            """The ``part``-th range of sorted_particle holding row (iy, iz)'s cells ix-1..ix+1:
            one range (part 0) where the row does not wrap, else one per cell (parts 0..2)."""
            lo, hi = 0, 0
            x = ix & mask
            if 1 <= x and x <= D - 2:
                if part == 0:
                    c = cell_index(ix, iy, iz)
                    lo, hi = start[c - 1], start[c + 2]
            else:
                c = cell_index(ix - 1 + part, iy, iz)
                lo, hi = start[c], start[c + 1]
            return lo, hi

        self.cell_coords, self.cell_index, self.clear_cell, self.insert = cell_coords, cell_index, clear_cell, insert
        self.open_cell, self.scatter, self.sort_cell, self.row_range = open_cell, scatter, sort_cell, row_range
