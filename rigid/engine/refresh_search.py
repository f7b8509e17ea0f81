"""Where a refreshed body's particles find their partners (refresh.py), at their new references.

The particles not refreshed since the last full build are in the build's grid (grid.py), at
their references (build_x): the 27 cells around (no half shell: only the refreshed side
looks). The refreshed ones are not (the grid holds where they were at the build), so at each
refresh their references are hashed again: cells of the grid's size into H buckets (a power
of two, at least twice the refreshed particles), a counting sort (count, running sum, scatter)
in the grid's cell_count array, which the build uses only while it sorts and is free between
builds: cell_count[h] is where bucket h ends in cell_count[H ...], which holds the refreshed
particles' slots bucket after bucket. Hashing the refreshed bodies' reference spheres against
each other instead (each new one against all) cost up to 33 ms a substep on the 24,000-body
pile with 9,000 bodies refreshed. Cells far apart may share a bucket (the distance test sorts
them out) and two of the 27 cells around a particle may too, so ``insert`` passes over a slot
the list already holds. One thread: the lists of two bodies may share a partner.
"""
import taichi as ti

from . import grid
from .refresh_state import body_state, marked, num_refreshed, refreshed_body, refreshed_particles

CELL_BITS = 1023  # each cell coordinate's low 10 bits go into the hash (no i32 overflow below)


@ti.func
def _bucket(g, H):
    """The bucket of cell g (integer coordinates, any sign) among H (a power of two)."""
    return ((g[0] & CELL_BITS) + (g[1] & CELL_BITS) * 7919 + (g[2] & CELL_BITS) * 104729) & (H - 1)


@ti.func
def hash_refreshed(model: ti.template(), state: ti.template(), scratch: ti.template()):
    """The refreshed particles' references hashed into cell_count (one thread, after the marked
    bodies took their new ones); the number of buckets H, or 0 if cell_count has no room."""
    n = refreshed_particles(state, scratch)
    H = 8
    while H < 2 * n:
        H *= 2
    if H + n > scratch.cell_count.shape[0]:
        H = 0
    if H > 0:
        for h in range(H):
            scratch.cell_count[h] = 0
        for k in range(num_refreshed(state, scratch)):
            b = refreshed_body(state, scratch, k)
            for j in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
                scratch.cell_count[_bucket(grid.cell_coords(scratch, scratch.build_x[j]), H)] += 1
        run = 0
        for h in range(H):  # each bucket's start; the scatter leaves its end there
            count = scratch.cell_count[h]
            scratch.cell_count[h] = run
            run += count
        for k in range(num_refreshed(state, scratch)):
            b = refreshed_body(state, scratch, k)
            for j in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
                h = _bucket(grid.cell_coords(scratch, scratch.build_x[j]), H)
                scratch.cell_count[H + scratch.cell_count[h]] = j
                scratch.cell_count[h] += 1
    return H


@ti.func
def insert(scratch: ti.template(), i, j, stride):
    """Slot j into slot i's list, in slot order (nothing if it holds j); 0 if the list is full
    (then a full build follows)."""
    n = scratch.nbr_count[i]
    base, k = i * stride, n - 1
    while k >= 0 and scratch.nbr_list[base + k] > j:
        k -= 1
    fits = 1
    if k < 0 or scratch.nbr_list[base + k] != j:
        if n < stride:
            for t in range(n - 1 - k):  # the entries above j move up one
                scratch.nbr_list[base + n - t] = scratch.nbr_list[base + n - 1 - t]
            scratch.nbr_list[base + k + 1] = j
            scratch.nbr_count[i] = n + 1
        else:
            fits = 0
    return fits


@ti.func
def find_partners(model: ti.template(), state: ti.template(), scratch: ti.template(), a, stride, H):
    """Marked body a's pairs, its particles at their new references (build_x): with the particles
    not refreshed since the full build, in the build's grid; with the refreshed ones, in the hash
    (H buckets; each pair of two marked bodies from the lower body's side). 0 if a list was full."""
    skin = scratch.grid_params[1]
    r_a = model.particle_radius[a]
    ok = 1
    for i in range(model.body_start[a], model.body_start[a] + model.body_count[a]):
        p = scratch.build_x[i]
        g = grid.cell_coords(scratch, p)
        for r in range(grid.ROWS_AROUND):
            lo, hi = grid.around_range(scratch, g, r)
            slot = lo
            while slot < hi:
                b = scratch.sorted_body[slot]
                if b == a:  # its own run in this cell, passed over at once
                    slot = scratch.sorted_run_end[slot]
                else:
                    if body_state(state, scratch, b) == 0:  # not refreshed since the full build
                        d = scratch.sorted_x[slot] - p
                        reach = r_a + model.particle_radius[b] + skin
                        if d.dot(d) < reach * reach:
                            j = scratch.sorted_particle[slot]
                            ok &= insert(scratch, i, j, stride) & insert(scratch, j, i, stride)
                    slot += 1
        for c in range(27):
            h = _bucket(g + ti.Vector([c % 3 - 1, (c // 3) % 3 - 1, c // 9 - 1]), H)
            lo = 0
            if h > 0:
                lo = scratch.cell_count[h - 1]
            for t in range(lo, scratch.cell_count[h]):
                j = scratch.cell_count[H + t]
                b = model.particle_body[j]
                if b != a and (not marked(state, scratch, b) or b > a):
                    d = scratch.build_x[j] - p
                    reach = r_a + model.particle_radius[b] + skin
                    if d.dot(d) < reach * reach:
                        ok &= insert(scratch, i, j, stride) & insert(scratch, j, i, stride)
    return ok
