"""Partial rebuilds of the neighbour lists: only the bodies that moved have their lists made again.

The lists (neighbours.py) stay exact while no two particles that may touch have closed by more
than the skin since the build. When a few bodies move fast (the top layer of a 24,000-body pile
still landing at 1 s: 1,325 bodies past the skin each substep), that fails every substep, and
a full rebuild of 1,008,000 particles cost 123 ms a substep (90 of them the list search), against
30 for the forces. So when the motion test (motion.py) finds a pair that moved too far, the
bodies that moved most are *refreshed* instead: each keeps its own reference pose, and

  every pair is listed exactly when its particles' reference positions are within reach + skin

(a full build sets every reference to now; a refresh sets a body's to now). A particle of body
b lies within e⁰_b = |Δx_b| + ‖ΔR_b‖₂ ρ_b of its reference (motion.body_shift), so a pair can
have closed by at most e⁰_a + e⁰_b, and refreshing every body with e⁰ > half the allowed
motion leaves every pair within it. Refreshing the marked bodies: 1. their particles leave
their partners' lists (one thread: lists shared between bodies change); 2. their positions now
become their references (build_x; the placement that follows places the particles themselves,
so a particle's position never depends on when lists were refreshed); 3. each of their
particles finds its partners again, into its own list (refresh_search.py; side by side on a
CPU's threads in split_substep.py's launch, ~0.6 of the time on one: the 24,000-body pile's
motion test and refresh 19.3-19.8 → 14.9 ms a substep); 4. one thread enters them in their
partners' lists. Every list stays sorted by slot and symmetric, and holds every touching pair,
so every sum runs over the same terms in the same order as after a full build: the bits do not
change (tests/test_refresh.py, tests/test_skin.py).

A full build is done instead when a refresh would cost more than the substeps since the last
full build did on average, the build included (its refreshed particles and ROUND_COST against
the build's and the refreshes' since, counted in refreshed particles: BUILD_COST), once the
refreshes have cost half a build: a refresh's cost grows with the bodies past half the skin,
which grow as the build ages, so the lists are rebuilt in full once that is cheaper, as the
Verlet list's rebuild every few substeps is (on the 24,000-body pile, refresh and builds 23.9 →
21.8 ms a substep, a full build every 13 substeps instead of 21); in a quiet pile, where
refreshes come seldom and the average runs low, the refreshes go on (without that condition
pile.toml ran 11 % slower, 319 full builds in 300 frames instead of 218; with it 236). Also
when the refreshed bodies would exceed broadphase.MAX_REFRESHED of the particles (REFRESH_FRACTION,
which sizes the hash; 0: never refresh), when a list has overflowed since (its grid walk would
miss the refreshed particles: list_growth.py) or would overflow. Off a CPU the parallel
schedule always rebuilds in full. Where the refresh keeps its state: broadphase.py (REFRESHED_BODIES
... MOTION_TESTS; per body REFRESH_STATE, REFRESH_ORDER, MOVED).
"""
import taichi as ti

from . import broadphase as bp
from . import motion, neighbours, refresh_search, schedule
from .broadphase import MARKED, REFRESHED, body_state, marked, refreshed_body, searching
from .matvec import body_offset, matvec, norm

# Of the particles, refreshed since the last full build at most. On the 24,000-body pile at 1 s a
# refresh marks ~12 % of the bodies at a skin of a tenth of a diameter: 0.0625 never refreshed
# there (170 ns a particle-substep), 0.125 ran 57-63 ns, 0.25 62-68, 0.5 80 (the first search).
REFRESH_FRACTION = 0.25
# A full build's cost (broadphase.FULL_BUILD_COST) and a refresh's own (its passes over every body and
# particle), in refreshed particles per particle of the scene: on the 24,000-body pile a build
# took 168 ms, a refresh ~4 ms and 0.6 µs a refreshed particle (two threads).
BUILD_COST, ROUND_COST = 0.28, 0.007
PENDING = 4  # broadphase.REBUILD from a refresh's preparation to its search's end (then 0, or 1: a full build)

REFRESH_AT_LEAST = 16  # bodies: fewer, and a full rebuild is cheap (worth_refreshing)


def worth_refreshing(num_bodies: int) -> bool:
    """Whether a scene of ``num_bodies`` bodies (every world's) compiles the refresh: with a few
    bodies a full rebuild costs little more than a refresh, and the refresh's code is about a
    quarter of the engine's kernel to compile (report/bench_first_run.md). Either way the lists
    hold every touching pair in slot order: the bits are the same."""
    return num_bodies >= REFRESH_AT_LEAST


@ti.func
def start_build(state: ti.template(), scratch: ti.template()):
    """neighbours.start_build, and no body refreshed once a full build follows (top-level statements)."""
    neighbours.start_build(scratch)
    keep = 1 - bp.get(scratch, bp.REBUILD)
    for what in ti.static((bp.REFRESHED_BODIES, bp.REFRESHED_PARTICLES, bp.MOTION_TESTS)):
        bp.put(scratch, what, bp.get(scratch, what) * keep)
    build = ti.cast(bp.value(scratch, bp.FULL_BUILD_COST) * state.particle_x.shape[0], ti.i32)
    bp.put(scratch, bp.REFRESH_COST, keep * bp.get(scratch, bp.REFRESH_COST) + (1 - keep) * build)


@ti.func
def after_build(state: ti.template(), scratch: ti.template(), b):
    """A full build's end for body b: its pose kept, its references those of the build."""
    bp.keep_reference_pose(scratch, b, state.x[b], state.R[b])
    bp.set_body_int(scratch, b, bp.REFRESH_STATE, 0)


@ti.func
def settle(model: ti.template(), state: ti.template(), scratch: ti.template(), parallel: ti.template(),
           enabled: ti.template(), defer: ti.template()):
    """After close_pairs_moved (one thread): no rebuild if no pair moved too far, else a refresh
    if it can be done (``enabled``, on one thread or a CPU), else a full build. The refresh's
    search then runs here, or with ``defer`` is left PENDING for split_substep.py's launch, which
    runs ``search`` on both threads and then ``finish``."""
    flag = bp.get(scratch, bp.REBUILD)
    if ti.static(enabled):
        bp.put(scratch, bp.MOTION_TESTS, ti.min(bp.get(scratch, bp.MOTION_TESTS) + 1, 1 << 30))
    if flag == motion.MAYBE:
        flag = 0
    elif flag == motion.VIOLATED:
        flag = 1
        if ti.static(enabled and (not parallel or schedule.on_cpu())):
            if _prepare(model, state, scratch):
                flag = PENDING
    bp.put(scratch, bp.REBUILD, flag)
    if ti.static(enabled and not defer):
        if flag == PENDING:
            for t in range(searching(scratch)):
                search(model, state, scratch, t)
            finish(model, state, scratch, parallel)


@ti.func
def _prepare(model: ti.template(), state: ti.template(), scratch: ti.template()):
    """Mark every body with e⁰ > half the allowed motion and make its lists ready to be searched
    again (steps 1 and 2), unless a full build is due; 1 if so."""
    B, N = state.x.shape[0], state.particle_x.shape[0]
    half = 0.5 * bp.value(scratch, bp.ALLOWED)
    listed, particles = bp.get(scratch, bp.REFRESHED_BODIES), bp.get(scratch, bp.REFRESHED_PARTICLES)
    H = refresh_search.buckets(scratch, N)
    ok = ti.cast(bp.get(scratch, bp.OVERFLOW) == 0 and H > 0, ti.i32)  # no list overflowed
    cost = 0
    if ok:
        for b in range(B):
            dx, turn = motion.body_shift(scratch, state, b)
            moved = norm(dx) + turn
            bp.set_body_float(scratch, b, bp.MOVED, moved)
            if moved > half:
                cost += model.body_count[b]
                if body_state(scratch, b) == 0:
                    particles += model.body_count[b]
        cost += ti.cast(ROUND_COST * N, ti.i32)
        cycle = bp.get(scratch, bp.REFRESH_COST)  # the build's and the refreshes' since
        since = ti.max(bp.get(scratch, bp.MOTION_TESTS), 1)
        build = bp.value(scratch, bp.FULL_BUILD_COST) * N
        dear = ti.cast(cost, float) * since > cycle and cycle > 1.5 * build  # (a quiet pile's average runs low)
        ok = ti.cast(particles <= bp.value(scratch, bp.MAX_REFRESHED) * N and not dear, ti.i32)
        if ok:
            bp.put(scratch, bp.REFRESH_COST, ti.min(cycle + cost, 1 << 30))  # (no i32 overflow)
    if ok:
        if listed == 0:  # the first refresh since the full build
            refresh_search.empty_hash(scratch, H)
        for b in range(B):
            if bp.body_float(scratch, b, bp.MOVED) > half:
                if body_state(scratch, b) == 0:
                    bp.set_body_int(scratch, listed, bp.REFRESH_ORDER, b)
                    listed += 1
                bp.set_body_int(scratch, b, bp.REFRESH_STATE, body_state(scratch, b) | MARKED)
        bp.put(scratch, bp.REFRESHED_BODIES, listed)
        bp.put(scratch, bp.REFRESHED_PARTICLES, particles)
        bp.put(scratch, bp.BUCKETS, H)
        bp.put(scratch, bp.SEARCH_FULL, 0)
        _unlist_and_rehash(model, state, scratch, H)
    return ok


@ti.func
def _remove(scratch: ti.template(), j, i, stride):
    """Slot i out of slot j's list (the order of the rest kept); a list left empty: no pair force."""
    base, kept = j * stride, 0
    for t in range(scratch.nbr_count[j]):
        value = scratch.nbr_list[base + t]
        if value != i:
            scratch.nbr_list[base + kept] = value
            kept += 1
    scratch.nbr_count[j] = kept
    if kept == 0:
        neighbours.no_pair_force(scratch, j)


@ti.func
def _unlist_and_rehash(model: ti.template(), state: ti.template(), scratch: ti.template(), H):
    """Steps 1 and 2 for the marked bodies, with the hash of the refreshed particles' references (H
    buckets, refresh_search.py) kept up; their particles, to be searched, in the active list
    (which finish makes again)."""
    stride = neighbours.list_stride(scratch, state)
    listed = bp.get(scratch, bp.REFRESHED_BODIES)
    for k in range(listed):  # 1. out of their partners' lists (the marked ones' are emptied next)
        a = refreshed_body(scratch, k)
        if marked(scratch, a):
            for i in range(model.body_start[a], model.body_start[a] + model.body_count[a]):
                for t in range(scratch.nbr_count[i]):
                    j = scratch.nbr_list[i * stride + t]
                    if not marked(scratch, model.particle_body[j]):
                        _remove(scratch, j, i, stride)
    n = 0
    for k in range(listed):  # 2. their references now (particle_x is left to the placement, which
        a = refreshed_body(scratch, k)  # follows: the same code places a particle whatever the lists)
        if marked(scratch, a):
            if body_state(scratch, a) & REFRESHED != 0:  # hashed at its old references
                refresh_search.unhash_body(model, scratch, a, H)
            bp.keep_reference_pose(scratch, a, state.x[a], state.R[a])
            R, x = state.R[a], state.x[a]
            for i in range(model.body_start[a], model.body_start[a] + model.body_count[a]):
                scratch.build_x[i] = x + matvec(R, body_offset(model, i))
                scratch.nbr_count[i] = 0
                scratch.active[n] = i
                n += 1
            refresh_search.hash_body(model, scratch, a, H)
    bp.put(scratch, bp.SEARCHING, n)


@ti.func
def search(model: ti.template(), state: ti.template(), scratch: ti.template(), t):
    """3. The t-th marked particle's partners found again, into its own list only (so the marked
    particles may search side by side: split_substep.py)."""
    stride = neighbours.list_stride(scratch, state)
    H = bp.get(scratch, bp.BUCKETS)
    if not refresh_search.find_partners(model, state, scratch, scratch.active[t], stride, H):
        bp.put(scratch, bp.SEARCH_FULL, 1)


@ti.func
def finish(model: ti.template(), state: ti.template(), scratch: ti.template(), parallel: ti.template()):
    """After ``search`` (one thread): each marked particle entered in the lists of its partners
    not marked (a marked partner found it itself: the distance test is symmetric), and the
    active list made again; else (a list full) a full build."""
    if bp.get(scratch, bp.REBUILD) == PENDING:
        N = state.particle_x.shape[0]
        stride = neighbours.list_stride(scratch, state)
        ok = 1 - bp.get(scratch, bp.SEARCH_FULL)
        n = searching(scratch)
        for t in range(n * ok):
            i = scratch.active[t]
            for s in range(scratch.nbr_count[i]):
                j = scratch.nbr_list[i * stride + s]
                if not marked(scratch, model.particle_body[j]):
                    ok &= refresh_search.insert(scratch, j, i, stride)
        flag = 1
        if ok:
            flag = 0
            for t in range(n):
                if scratch.nbr_count[scratch.active[t]] == 0:
                    neighbours.no_pair_force(scratch, scratch.active[t])
            for k in range(bp.get(scratch, bp.REFRESHED_BODIES)):
                bp.set_body_int(scratch, refreshed_body(scratch, k), bp.REFRESH_STATE, REFRESHED)
            bp.put(scratch, bp.REFRESHES, bp.get(scratch, bp.REFRESHES) + 1)
            m = 0  # the active list again, ascending (on one thread: a parallel list_active's two empty
            for i in range(N):  # loops would cost every substep ~60 µs; this, 1-2 ms a refresh at 1M)
                if scratch.nbr_count[i] > 0:
                    scratch.active[m] = i
                    m += 1
            bp.put(scratch, bp.ACTIVE, m)
            if ti.static(not parallel):
                neighbours.index_active_by_body(model, state, scratch)
        bp.put(scratch, bp.REBUILD, flag)
