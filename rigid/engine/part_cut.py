"""The bodies cut into the parallel pair stage's parts (pair_parts.py) by where they are, each substep.

A part's pairs with another part's particles are evaluated twice, once on each side, so the cut
should cross few pairs. Cutting by slot follows the order the scene laid the bodies out in,
which the bodies forget: 1,000 volume spheres dropped as a 10 × 10 × 10 lattice lie on the floor
at 1 s as a layer two or three spheres deep, and the slot cut (the lattice's middle layer) then
crossed 54 % of the list entries (the 125 volume spheres of 235,000 particles: 41 %); a cut across
the layer's widest axis crossed 1.5 % (6.6 %). The pair stage of the 1,000 spheres spent 9 of its
13.5 ms a substep collecting the terms across the slot cut.

So each substep, one thread cuts the bodies along the axis of the largest extent of their
centres into ``parts`` groups, ordered by (coordinate, body index), of about equal weight: a
body weighs its particles plus TOUCH_WEIGHT for each that touched another body's when the
parts last ran (counted by pair_parts.sweep_part into broadphase.TOUCHES; kept with the
state by list growth's copy, cleared by a reset). On 125 volume spheres of 235,000 particles
equal counts left the parts at 8.6 and 6.7 ms, the weights at 7.8 and 7.8 (the sweep alone:
14.9-16.5 ms on one thread); a substep 56.6-58.7 → 52.7-54.2 ns a particle. The cut and the weights
are fixed functions of the state (the touching pairs do not depend on the lists), so the runs
stay bit-reproducible whatever the lists' skin, rebuilds and chunks. The groups' edges come
from Hoare's selection (O(B), no sort) on a copy of the keys, (coordinate, body index) at
position t in broadphase.CUT_KEY and CUT_INDEX; each body's part goes into broadphase.PART.
"""
import taichi as ti

from . import broadphase as bp

TOUCH_WEIGHT = 6.0  # a touching particle's work in the sweep against one that only reads its list


@ti.func
def _ordered(key_a, index_a, key_b, index_b):
    """Whether key (key_a, index_a) comes before (key_b, index_b): coordinate, then index."""
    return key_a < key_b or (key_a == key_b and index_a < index_b)


@ti.func
def _key(scratch: ti.template(), t):
    return bp.body_float(scratch, t, bp.CUT_KEY)


@ti.func
def _index(scratch: ti.template(), t):
    return bp.body_int(scratch, t, bp.CUT_INDEX)


@ti.func
def _set(scratch: ti.template(), t, key, index):
    """Selection position t ← (key, index)."""
    bp.set_body_float(scratch, t, bp.CUT_KEY, key)
    bp.set_body_int(scratch, t, bp.CUT_INDEX, index)


@ti.func
def _before(scratch: ti.template(), s, t):
    """Whether the key at selection position s comes before that at position t."""
    return _ordered(_key(scratch, s), _index(scratch, s), _key(scratch, t), _index(scratch, t))


@ti.func
def _swap(scratch: ti.template(), s, t):
    key, index = _key(scratch, s), _index(scratch, s)
    _set(scratch, s, _key(scratch, t), _index(scratch, t))
    _set(scratch, t, key, index)


@ti.func
def _weight(model: ti.template(), scratch: ti.template(), b):
    """Body b's share of the pair stage's work: its particles, and more for those that touched
    another body's in the last substep the parts ran (a fixed function of the state: the
    touching pairs do not depend on the lists)."""
    return ti.cast(model.body_count[b], float) + TOUCH_WEIGHT * ti.cast(bp.body_int(scratch, b, bp.TOUCHES), float)


@ti.func
def _weight_at(model: ti.template(), scratch: ti.template(), t):
    return _weight(model, scratch, _index(scratch, t))


@ti.func
def _select_weight(model: ti.template(), scratch: ti.template(), first, last, before, target):
    """Reorder selection slots first..last (the keys there all after those before ``first``, whose
    weights sum to ``before``) and return the position c of the first key, in key order, whose
    weight summed with all the keys' before it reaches ``target`` (or ``last``): every key
    before c then lies before it and every key after it after it (Hoare's partition, the pivot
    the median of the first, middle and last keys, narrowing to the side that holds c)."""
    lo, hi, acc = first, last, before
    while lo < hi:
        mid = (lo + hi) // 2
        if _before(scratch, mid, lo):
            _swap(scratch, mid, lo)
        if _before(scratch, hi, lo):
            _swap(scratch, hi, lo)
        if _before(scratch, hi, mid):
            _swap(scratch, hi, mid)
        pivot_key, pivot_index = _key(scratch, mid), _index(scratch, mid)
        i, j = lo, hi
        while i <= j:
            while _ordered(_key(scratch, i), _index(scratch, i), pivot_key, pivot_index):
                i += 1
            while _ordered(pivot_key, pivot_index, _key(scratch, j), _index(scratch, j)):
                j -= 1
            if i <= j:
                _swap(scratch, i, j)
                i += 1
                j -= 1
        left = 0.0  # keys lo..j come before the rest (and j + 1, when i == j + 2, is the pivot's)
        for t in range(lo, j + 1):
            left += _weight_at(model, scratch, t)
        if acc + left >= target:
            hi = j
        else:
            acc += left
            lo = i
            if i == j + 2:  # the pivot's key between the sides
                acc += _weight_at(model, scratch, j + 1)
                if acc >= target:
                    lo = j + 1
                    hi = j + 1
    return lo


@ti.func
def cut_bodies(model: ti.template(), state: ti.template(), scratch: ti.template(), parts):
    """Each body's part for this substep (on one thread): ``parts`` groups along the widest axis
    of the centres, ordered by (coordinate, body index), of about equal weight (_weight): group
    k ends with the first body at which the running weight reaches k + 1 parts' share. A NaN
    centre counts as 0 (a blow-up stops the run at the frame's end; meanwhile the cut only has
    to be some fixed function of the state)."""
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
    total = 0.0
    for b in range(B):
        x = state.x[b]
        c = x[0]
        if axis == 1:
            c = x[1]
        elif axis == 2:
            c = x[2]
        if not (c == c):
            c = 0.0
        _set(scratch, b, c, b)
        total += _weight(model, scratch, b)
    first, before = 0, 0.0
    for k in range(parts - 1):
        end = first
        if first < B:
            end = _select_weight(model, scratch, first, B - 1, before, total * (k + 1) / parts) + 1
        for t in range(first, end):
            b = _index(scratch, t)
            bp.set_body_int(scratch, b, bp.PART, k)
            before += _weight(model, scratch, b)
        first = end
    for t in range(first, B):
        bp.set_body_int(scratch, _index(scratch, t), bp.PART, parts - 1)
