"""The bodies cut into the parallel pair stage's parts (pair_parts.py) by where they are, each substep.

A part's pairs with another part's particles are evaluated twice, once on each side, so the cut
should cross few pairs. Cutting by slot follows the order the scene laid the bodies out in,
which the bodies forget: 1,000 volume spheres dropped as a 10 × 10 × 10 lattice lie on the floor
at 1 s as a layer two or three spheres deep, and the slot cut (the lattice's middle layer) then
crossed 54 % of the list entries (the 125 volume spheres of 235,000 particles: 41 %); a cut across
the layer's widest axis crossed 1.5 % (6.6 %). The pair stage of the 1,000 spheres spent 9 of its
13.5 ms a substep collecting the terms across the slot cut.

So each substep, one thread cuts the bodies along the axis of the largest extent of their
centres into ``parts`` groups of equal count, ordered by (coordinate, body index): a fixed
function of the state, so the runs stay bit-reproducible whatever the lists' skin, rebuilds and
chunks. It selects the groups' edges by Hoare's selection (O(B), no sort) on a copy of the keys
in slots 13 and 14 of build_pose, which hold the motion test's values only during that test
(motion.py), and writes each body's part into nbr_flags (neighbours.py).
"""
import taichi as ti

KEY, INDEX = 13, 14  # build_pose slots the selection works in: a body's coordinate, its index


@ti.func
def part_of(state: ti.template(), scratch: ti.template(), b):
    """The part body b's particles belong to (after cut_bodies in this substep)."""
    return scratch.nbr_flags[4 + 2 * state.x.shape[0] + b]


@ti.func
def _before(scratch: ti.template(), s, t):
    """Whether the key in selection slot s comes before that in slot t (coordinate, then index)."""
    a, b = scratch.build_pose[s], scratch.build_pose[t]
    return a[KEY] < b[KEY] or (a[KEY] == b[KEY] and a[INDEX] < b[INDEX])


@ti.func
def _swap(scratch: ti.template(), s, t):
    a, b = scratch.build_pose[s], scratch.build_pose[t]
    key, index = a[KEY], a[INDEX]
    scratch.build_pose[s][KEY] = b[KEY]
    scratch.build_pose[s][INDEX] = b[INDEX]
    scratch.build_pose[t][KEY] = key
    scratch.build_pose[t][INDEX] = index


@ti.func
def _select(scratch: ti.template(), first, last, rank):
    """Reorder selection slots first..last so that slot ``rank`` holds the key of that rank, none
    after it before it and none before it after it (Hoare's selection; the pivot is the median
    of the first, middle and last keys, moved to the middle)."""
    lo, hi = first, last
    while lo < hi:
        mid = (lo + hi) // 2
        if _before(scratch, mid, lo):
            _swap(scratch, mid, lo)
        if _before(scratch, hi, lo):
            _swap(scratch, hi, lo)
        if _before(scratch, hi, mid):
            _swap(scratch, hi, mid)
        pivot_key, pivot_index = scratch.build_pose[mid][KEY], scratch.build_pose[mid][INDEX]
        i, j = lo, hi
        while i <= j:
            while (scratch.build_pose[i][KEY] < pivot_key
                   or (scratch.build_pose[i][KEY] == pivot_key and scratch.build_pose[i][INDEX] < pivot_index)):
                i += 1
            while (scratch.build_pose[j][KEY] > pivot_key
                   or (scratch.build_pose[j][KEY] == pivot_key and scratch.build_pose[j][INDEX] > pivot_index)):
                j -= 1
            if i <= j:
                _swap(scratch, i, j)
                i += 1
                j -= 1
        if rank <= j:
            hi = j
        elif rank >= i:
            lo = i
        else:
            lo = hi  # i - 1 == rank == j + 1: in place


@ti.func
def cut_bodies(state: ti.template(), scratch: ti.template(), parts):
    """Each body's part for this substep (on one thread): ``parts`` groups of equal count (to
    one) along the widest axis of the centres. A NaN centre counts as 0 (a blow-up stops the run
    at the frame's end; meanwhile the cut only has to be some fixed function of the state)."""
    B = state.x.shape[0]
    lo = ti.Vector([1e30, 1e30, 1e30], float)
    hi = -lo
    for b in range(B):
        lo = ti.min(lo, state.x[b])
        hi = ti.max(hi, state.x[b])
    extent = hi - lo
    axis = 0
    if extent[1] > extent[axis]:
        axis = 1
    if extent[2] > extent[axis]:
        axis = 2
    for b in range(B):
        x = state.x[b]
        c = x[0]
        if axis == 1:
            c = x[1]
        elif axis == 2:
            c = x[2]
        if not (c == c):
            c = 0.0
        scratch.build_pose[b][KEY] = c
        scratch.build_pose[b][INDEX] = ti.cast(b, float)  # exact up to 2**24 bodies in float32
    first = 0
    for k in range(1, parts):
        rank = (B * k + parts - 1) // parts  # the first position of group k: t * parts >= B * k
        if rank < B:
            _select(scratch, first, B - 1, rank)
            first = rank
    for t in range(B):
        b = ti.cast(scratch.build_pose[t][INDEX], ti.i32)
        scratch.nbr_flags[4 + 2 * B + b] = (t * parts) // B
