"""Where a refreshed body's particles find their partners (refresh.py), at their new references.

The particles not refreshed since the last full build are in the build's grid (grid.py), at
their references (build_x): the 27 cells around (no half shell: only the refreshed side
looks). The refreshed ones are not (the grid holds where they were at the build), so they are
kept in a hash of their references: cells of the grid's size into H buckets (a power of two, at
least twice the most particles a refresh may cover), each bucket a chain through the particles,
in the grid's cell_count array, which the build uses only while it sorts and is free between
builds: cell_count[h] is the first particle of bucket h (-1: none), cell_count[H + j] the one
after slot j. A refreshed body's particles leave their old buckets and enter their new ones, so a
refresh costs its own particles, not all those refreshed since the build (a counting sort of all
of them at each refresh ran as fast on the 24,000-body pile, interleaved, but its cost grows with
them; testing each new body's reference sphere against every refreshed one, and then all their
particle pairs, cost the 1,012,000-particle volume soup, 125 bodies of 8,096 particles, 60 → 99
ns a particle-substep). Cells far apart may share a bucket (the distance test sorts them out)
and two of the 27 cells around a particle may too, so ``insert`` passes over a slot the list
already holds. Each marked particle fills only its own list, so they may search side by side
(refresh.finish then enters the other sides on one thread); a list is a sorted set, so neither
the order they search in nor the chains' order changes it.
"""
import taichi as ti

from . import broadphase as bp
from . import grid
from .broadphase import body_state
from .matvec import dot

CELL_BITS = 1023  # each cell coordinate's low 10 bits go into the hash (no i32 overflow below)


@ti.func
def _bucket(g, H):
    """The bucket of cell g (integer coordinates, any sign) among H (a power of two)."""
    return ((g[0] & CELL_BITS) + (g[1] & CELL_BITS) * 7919 + (g[2] & CELL_BITS) * 104729) & (H - 1)


@ti.func
def buckets(scratch: ti.template(), n):
    """H for ``n`` particles: the power of two at least twice the most a refresh may cover
    (broadphase.MAX_REFRESHED of them); 0 if cell_count (H heads, then a link per slot) has no room."""
    H = 8
    while H < 2.0 * bp.value(scratch, bp.MAX_REFRESHED) * n:
        H *= 2
    if H + n > scratch.cell_count.shape[0]:
        H = 0
    return H


@ti.func
def empty_hash(scratch: ti.template(), H):
    """No particle hashed (the first refresh after a full build)."""
    for h in range(H):
        scratch.cell_count[h] = -1


@ti.func
def _reference_bucket(model: ti.template(), scratch: ti.template(), j, H):
    return _bucket(grid.particle_coords(scratch, model, j, scratch.build_x[j]), H)


@ti.func
def hash_body(model: ti.template(), scratch: ti.template(), b, H):
    """Body b's particles into the buckets of their references (build_x)."""
    for j in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
        h = _reference_bucket(model, scratch, j, H)
        scratch.cell_count[H + j] = scratch.cell_count[h]
        scratch.cell_count[h] = j


@ti.func
def unhash_body(model: ti.template(), scratch: ti.template(), b, H):
    """Body b's particles out of their buckets (before their references change)."""
    for j in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
        h = _reference_bucket(model, scratch, j, H)
        if scratch.cell_count[h] == j:
            scratch.cell_count[h] = scratch.cell_count[H + j]
        else:
            k = scratch.cell_count[h]
            while k >= 0 and scratch.cell_count[H + k] != j:
                k = scratch.cell_count[H + k]
            if k >= 0:  # (always: it was hashed at these references)
                scratch.cell_count[H + k] = scratch.cell_count[H + j]


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
def find_partners(model: ti.template(), state: ti.template(), scratch: ti.template(), i, stride, H):
    """The partners of slot i, of a marked body, at its new reference (build_x), into its own list
    only: the particles not refreshed since the full build in the build's grid, the refreshed ones
    (marked too or not) in the hash (H buckets). 0 if the list was full."""
    skin = bp.value(scratch, bp.SKIN)
    a = model.particle_body[i]
    r_a = model.particle_radius[a]
    p = scratch.build_x[i]
    g = grid.particle_coords(scratch, model, i, p)
    ok = 1
    for r in range(grid.ROWS_AROUND):
        lo, hi = grid.around_range(scratch, g, r)
        slot = lo
        while slot < hi:
            b = scratch.sorted_body[slot]
            if b == a:  # its own run in this cell, passed over at once
                slot = scratch.sorted_run_end[slot]
            else:
                if body_state(scratch, b) == 0 and grid.same_world(model, a, b):  # not refreshed since the build
                    d = scratch.sorted_x[slot] - p
                    reach = r_a + model.particle_radius[b] + skin
                    if dot(d, d) < reach * reach:
                        ok &= insert(scratch, i, scratch.sorted_particle[slot], stride)
                slot += 1
    for c in range(27):
        j = scratch.cell_count[_bucket(g + ti.Vector([c % 3 - 1, (c // 3) % 3 - 1, c // 9 - 1]), H)]
        while j >= 0:
            b = model.particle_body[j]
            if b != a and grid.same_world(model, a, b):
                d = scratch.build_x[j] - p
                reach = r_a + model.particle_radius[b] + skin
                if dot(d, d) < reach * reach:
                    ok &= insert(scratch, i, j, stride)
            j = scratch.cell_count[H + j]
    return ok
