"""Verlet neighbour lists: the pair candidates of every particle, reused across substeps.

Rebuilding the grid and walking 27 cells every substep cost most of a many-body substep (the
125-sphere pile: 14 candidates a particle, 74 % of them its own body's, 1.5 % in contact). So
each particle keeps a list of the other bodies' particles within r_a + r_b + skin of it, made
from the grid (grid.py, cells of the largest diameter + the skin) and reused until two
particles may have closed by more than the skin since the build: until then no pair can have
come from beyond reach + skin to within reach, so every pair in contact is in the
list (Verlet 1967; the classic rebuild test, here on relative motion bounded per body, and only
for pairs of bodies near enough to touch: note_motion, close_pairs_moved; when only some
bodies outran the skin, theirs alone are made again: refresh.py). Own-body
candidates never enter the list. Only the particles with a candidate (the active list) are
placed and visited by the pair stage between builds; the others' pair force stays zero.

The list of particle i is nbr_list[i·K .. i·K + nbr_count[i]) (K = its length / N), sorted by
slot, so each sum over it has a fixed order whatever the threads did, and runs are
bit-reproducible; it is symmetric (each pair is tested once, from one side, and entered in
both lists). A particle with more than K candidates keeps only its count, and its sum walks
the build's grid again around the cell of its build position, testing the candidates' current
positions (a superset of its list: exact, in the walk's fixed order): no contact is dropped.
The host then doubles K and runs the chunk again (list_growth.py).

Scratch arrays (ScratchArgs): ``nbr_count`` [N] i32, ``nbr_list`` [N·K] i32 (particle slots),
``build_x`` [N] vec3 (each particle's reference: its world position at the last build, or at
its body's last refresh, refresh.py), ``active`` [N] i32 (the slots with a candidate, the first
broadphase.ACTIVE of them). The rebuild flag, the counts, the skin and each body's reference
pose and motion bounds: broadphase.py's named slots.
"""
from collections import namedtuple

import taichi as ti

from . import broadphase as bp
from . import grid, scan, schedule
from .matvec import ZERO3, dot

NEIGHBOURS_PER_PARTICLE = 16  # list slots per particle to start with (list_growth.py doubles them where needed)
SKIN_FRACTION = 0.5  # skin = this × the largest particle diameter
ALLOWED_MOTION = 0.98  # × the skin: two particles' relative motion before a rebuild (less 2 % for round-off)


@ti.func
def start_build(scratch: ti.template()):
    """Empty the active list if a build follows (a top-level statement: no loop)."""
    bp.put(scratch, bp.ACTIVE, bp.get(scratch, bp.ACTIVE) * (1 - bp.get(scratch, bp.REBUILD)))


@ti.func
def num_active(scratch: ti.template()):
    """Particles with a candidate at the last build (the pair stage visits only these)."""
    return bp.get(scratch, bp.ACTIVE)


@ti.func
def rebuild_gate(scratch: ti.template()):
    """1 when the lists must be rebuilt this substep, else 0: the build's loops run over
    ``n * gate`` items, so that in a parallel kernel they stay top-level loops."""
    return bp.get(scratch, bp.REBUILD)


@ti.func
def clear_list(scratch: ti.template(), i):
    scratch.nbr_count[i] = 0


@ti.func
def _append(scratch: ti.template(), i, j, stride):
    n = ti.atomic_add(scratch.nbr_count[i], 1)
    if n < stride:
        scratch.nbr_list[i * stride + n] = j


@ti.func
def build_list(model: ti.template(), state: ti.template(), scratch: ti.template(), i):
    """Slot i's pairs from the freshly built grid: on a CPU each pair found once (a half shell)
    and appended to both lists (build_half_shell); on a GPU each particle walks all 27 cells
    around it and fills its own list alone (build_own_list). Then finish_list."""
    if ti.static(schedule.on_cpu()):
        build_half_shell(model, state, scratch, i)
    else:
        build_own_list(model, state, scratch, i)


OwnList = namedtuple("OwnList", "model scratch i body p r_a skin stride n")


@ti.func
def _append_near(c: ti.template(), slot):
    """build_own_list's visitor: slot (of the sorted grid) appended to i's list if it is another
    body's particle within reach + skin; counted past the stride."""
    b = c.scratch.sorted_body[slot]
    if b != c.body and grid.same_world(c.model, b, c.body):
        d = c.scratch.sorted_x[slot] - c.p
        reach = c.r_a + c.model.particle_radius[b] + c.skin
        if dot(d, d) < reach * reach:
            if c.n < c.stride:
                c.scratch.nbr_list[c.i * c.stride + c.n] = c.scratch.sorted_particle[slot]
            c.n += 1


@ti.func
def build_own_list(model: ti.template(), state: ti.template(), scratch: ti.template(), i):
    """Slot i's list from the 27 cells around it: other bodies' particles within reach + skin.
    No atomics and twice the distance tests of the half shell: a thread per particle, as a GPU
    runs it (the half shell's appends to the other side's list, atomics on other particles'
    counts, made Taichi's SPIR-V code skip some particles' stores on Vulkan/lavapipe)."""
    a = model.particle_body[i]
    p, r_a, skin = state.particle_x[i], model.particle_radius[a], bp.value(scratch, bp.SKIN)
    stride = list_stride(scratch, state)
    n = 0
    grid.each_slot_around(scratch, grid.particle_coords(scratch, model, i, p), _append_near,
                          ti.static(OwnList(model, scratch, i, a, p, r_a, skin, stride, n)))
    scratch.nbr_count[i] = n
    scratch.build_x[i] = p


@ti.func
def build_half_shell(model: ti.template(), state: ti.template(), scratch: ti.template(), i):
    """Slot i's pairs from the freshly built grid, each pair found once (a half shell: the rows
    ahead of i's in z, then in y, and in i's own row only slots j > i) and appended to both
    lists; other bodies' particles within reach + skin."""
    a = model.particle_body[i]
    p, r_a = state.particle_x[i], model.particle_radius[a]
    skin = bp.value(scratch, bp.SKIN)
    stride = list_stride(scratch, state)
    g = grid.particle_coords(scratch, model, i, p)
    for dz in range(0, 2):
        for dy in range(-1, 2):
            if dz == 1 or dy >= 0:
                own_row = dz == 0 and dy == 0
                for part in range(3):
                    lo, hi = grid.row_range(scratch, g[0], g[1] + dy, g[2] + dz, part)
                    slot = lo
                    while slot < hi:
                        b = scratch.sorted_body[slot]
                        if b == a:  # its own body's run in this cell, passed over at once
                            slot = scratch.sorted_run_end[slot]
                        else:
                            j = scratch.sorted_particle[slot]
                            if (j > i or not own_row) and grid.same_world(model, a, b):
                                d = scratch.sorted_x[slot] - p
                                reach = r_a + model.particle_radius[b] + skin
                                if dot(d, d) < reach * reach:
                                    _append(scratch, i, j, stride)
                                    _append(scratch, j, i, stride)
                            slot += 1
    scratch.build_x[i] = p


@ti.func
def finish_list(state: ti.template(), scratch: ti.template(), i, parallel: ti.template()):
    """Sort slot i's list by slot (the appends' order depends on the threads; sorted, the sums over
    it have one order), and on one thread enter it in the active list if it has a candidate (in
    parallel, ``list_active`` does that after)."""
    stride = list_stride(scratch, state)
    n = ti.min(scratch.nbr_count[i], stride)
    base = i * stride
    for t in range(1, n):  # insertion sort: a few entries
        value = scratch.nbr_list[base + t]
        k = t - 1
        while k >= 0 and scratch.nbr_list[base + k] > value:
            scratch.nbr_list[base + k + 1] = scratch.nbr_list[base + k]
            k -= 1
        scratch.nbr_list[base + k + 1] = value
    if scratch.nbr_count[i] > stride:  # it walks the grid: the lists may grow (list_growth.py)
        bp.put(scratch, bp.OVERFLOW, 1)
    if scratch.nbr_count[i] > 0:  # visited by the pair stage until the next build
        if ti.static(not parallel):
            scratch.active[bp.claim_active(scratch)] = i
    else:  # never visited: no pair force until the next build
        no_pair_force(scratch, i)


@ti.func
def no_pair_force(scratch: ti.template(), i):
    """A particle the pair stage will not visit (no candidate): no pair force or couple."""
    scratch.particle_f[i] = ZERO3
    scratch.particle_couple[i] = ZERO3


@ti.func
def _active_chunk(state: ti.template(), scratch: ti.template(), k):
    """Chunk k of the slots for list_active (as many chunks as the grid's scan has)."""
    n, chunks = state.particle_x.shape[0], bp.get(scratch, bp.GRID_CHUNKS)
    return chunk_start(n, chunks, k), chunk_start(n, chunks, k + 1)


@ti.func
def chunk_start(n, chunks, k):
    """n k // chunks, the first of chunk k's slots, as k q + k r // chunks (n = q chunks + r): n k
    itself overflows an i32 from 2^31 / chunks particles on (a million at 2,048 chunks)."""
    q, r = n // chunks, n % chunks
    return k * q + (k * r) // chunks


@ti.func
def list_active(state: ti.template(), scratch: ti.template(), gate, parallel: ti.template()):
    """The active list of a parallel build (top-level loops; ``gate`` 0: none), ascending by slot
    (on one thread, finish_list appends to it).
    Every thread appending through one counter cost 20 ms for a million particles (the cache line
    passed between the cores at each append; 0.5 ms without the atomic), so each chunk of slots
    counts its active particles, one thread sums the counts (scan.sum_chunk_totals, in
    chunk_total, free after the grid's scan) and each chunk writes its slots from its offset."""
    if ti.static(parallel):
        _list_active(state, scratch, gate)


@ti.func
def _list_active(state: ti.template(), scratch: ti.template(), gate):
    chunks = bp.get(scratch, bp.GRID_CHUNKS) * gate
    for k in range(chunks):
        lo, hi = _active_chunk(state, scratch, k)
        total = 0
        for i in range(lo, hi):
            if scratch.nbr_count[i] > 0:
                total += 1
        scratch.chunk_total[k + 1] = total
    scan.sum_chunk_totals(scratch.chunk_total, chunks)
    for k in range(chunks):
        lo, hi = _active_chunk(state, scratch, k)
        t = scratch.chunk_total[k]
        for i in range(lo, hi):
            if scratch.nbr_count[i] > 0:
                scratch.active[t] = i
                t += 1
        if k == chunks - 1:
            bp.put(scratch, bp.ACTIVE, t)


@ti.func
def clear_flag(scratch: ti.template()):
    """After a build (or none): count it (BUILDS, for benchmarks) and lower the flag."""
    bp.put(scratch, bp.BUILDS, bp.get(scratch, bp.BUILDS) + bp.get(scratch, bp.REBUILD))
    bp.put(scratch, bp.REBUILD, 0)


@ti.func
def index_active_by_body(model: ti.template(), state: ti.template(), scratch: ti.template()):
    """After a build on one thread (the active list then ascends by slot, and a body's slots are
    contiguous): where each body's run of the active list starts, so that the one-thread stages
    walk bodies, passing over a sleeper at once, without testing every slot."""
    B = state.x.shape[0]
    n = num_active(scratch)
    t = 0
    for b in range(B):
        bp.set_body_int(scratch, b, bp.RUN_START, t)
        end = model.body_start[b] + model.body_count[b]
        while t < n and scratch.active[t] < end:
            t += 1
    bp.set_body_int(scratch, B, bp.RUN_START, n)


@ti.func
def list_stride(scratch: ti.template(), state: ti.template()):
    return scratch.nbr_list.shape[0] // state.particle_x.shape[0]
