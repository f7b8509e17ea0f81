"""The one walk over a particle's contact candidates, which every pair consumer calls.

A candidate of slot i (of body a) is another body's particle that i's neighbour list holds
(neighbours.py: within reach + skin when the lists were built). Where i's list overflowed (more
than K candidates: it kept only its count), the same candidates come, in the same order, from
the build's grid around i's build position (grid.py). Consumers never see which: they pass a
visitor and a context,

    each_candidate(model, state, scratch, i, a, visit, ctx)   calls   visit(ctx, j)   for each candidate j,

in ascending slot order (lists are sorted by slot; the grid's cells are sorted by slot too, so
an overflowed particle's order is the grid's fixed cell order). ``visit`` is a ``ti.func`` and
``ctx`` a namedtuple of what it reads and the sums it adds to: Taichi inlines both (template
arguments), so the walk costs what a hand-written loop costs, and ``ctx.f += ...`` in the
visitor adds to the caller's local variable f.
"""
from collections import namedtuple

import taichi as ti

from . import grid, neighbours


_Overflow = namedtuple("_Overflow", "model scratch body visit ctx entries")


@ti.func
def _grid_candidate(model: ti.template(), scratch: ti.template(), a, slot):
    """The particle at ``slot`` of the sorted grid if it is a candidate of a particle of body a
    (not of a's own body, nor of another world), else −1."""
    j = -1
    b = scratch.sorted_body[slot]
    if b != a and grid.same_world(model, b, a):
        j = scratch.sorted_particle[slot]
    return j


@ti.func
def _other_body(c: ti.template(), slot):
    """each_candidate's overflow walk: visit the slot's particle if it is a candidate."""
    j = _grid_candidate(c.model, c.scratch, c.body, slot)
    if j >= 0:
        if ti.static(c.entries):
            ti.static(c.visit)(c.ctx, j, -1)
        else:
            ti.static(c.visit)(c.ctx, j)


ALL, ABOVE, BELOW = 0, 1, 2  # which of a listed particle's candidates each_candidate visits


@ti.func
def _first_above(scratch: ti.template(), base, n, i):
    """The first entry of the sorted list at ``base`` (n entries) above slot i (n if none)."""
    lo, hi = 0, n
    while lo < hi:
        mid = (lo + hi) >> 1
        if scratch.nbr_list[base + mid] > i:
            hi = mid
        else:
            lo = mid + 1
    return lo


@ti.func
def _listed_range(scratch: ti.template(), base, n, i, which: ti.template()):
    """The entries [first, end) of the sorted list at ``base`` (n entries) that ``which`` asks for."""
    first, end = 0, n
    if ti.static(which == ABOVE):
        first = _first_above(scratch, base, n, i)
    elif ti.static(which == BELOW):
        end = _first_above(scratch, base, n, i)
    return first, end


@ti.func
def each_candidate(model: ti.template(), state: ti.template(), scratch: ti.template(), i, a, visit: ti.template(),
                   ctx: ti.template(), which: ti.template() = ALL, entries: ti.template() = False,
                   one_call: ti.template() = False):
    """visit(ctx, j) for each candidate j of slot i (of body a): its neighbour list in order, or,
    where the list overflowed, the build's grid around i's build position. ``which``: ABOVE or
    BELOW, of a listed particle only the candidates above (below) slot i, found by bisection in
    the sorted list (the sweep's turns: pair_once.py, pair_parts.py); an overflowed one's all.
    With ``entries``, visit(ctx, j, e): e = i·K + t, the index of j's entry in i's list (and of
    what arrays beside the lists keep for it: pair_slip.py), or −1 where the grid is walked.

    Taichi inlines the visitor at each of its calls. By default the list's loop and the grid's
    walk call it apart, the list's loop kept as tight as a hand-written one (the plain law's hot
    loop); ``one_call`` walks both as one loop with one call (a list is one range of entries,
    the grid ROWS_AROUND ranges of sorted slots), for a big visitor such as the materials' law,
    whose second copy would be a large share of its kernel to compile. The same visits, in the
    same order, either way."""
    stride = neighbours.list_stride(scratch, state)
    n = scratch.nbr_count[i]
    base = i * stride
    if ti.static(one_call):
        _each_in_one_loop(model, scratch, i, a, visit, ctx, which, entries, n, stride, base)
    elif n <= stride:
        first, end = _listed_range(scratch, base, n, i, which)
        for t in range(first, end):
            if ti.static(entries):
                visit(ctx, scratch.nbr_list[base + t], base + t)
            else:
                visit(ctx, scratch.nbr_list[base + t])
    else:
        grid.each_slot_around(scratch, grid.particle_coords(scratch, model, i, scratch.build_x[i]), _other_body,
                              ti.static(_Overflow(model, scratch, a, visit, ctx, entries)))


@ti.func
def _each_in_one_loop(model: ti.template(), scratch: ti.template(), i, a, visit: ti.template(), ctx: ti.template(),
                      which: ti.template(), entries: ti.template(), n, stride, base):
    """each_candidate's walk with one call of ``visit``: the list's range, or the grid's ranges."""
    listed = n <= stride
    first, end = 0, n
    if listed:
        first, end = _listed_range(scratch, base, n, i, which)
    g = ti.Vector([0, 0, 0])
    ranges = 1
    if not listed:
        g = grid.particle_coords(scratch, model, i, scratch.build_x[i])
        ranges = grid.ROWS_AROUND
    for r in range(ranges):
        if not listed:
            first, end = grid.around_range(scratch, g, r)
        for t in range(first, end):
            j, e = -1, -1
            if listed:
                j, e = scratch.nbr_list[base + t], base + t
            else:
                j = _grid_candidate(model, scratch, a, t)
            if j >= 0:
                if ti.static(entries):
                    visit(ctx, j, e)
                else:
                    visit(ctx, j)
