"""Partial rebuilds of the neighbour lists: only the bodies that moved have their lists made again.

The lists (neighbours.py) stay exact while no two particles that may touch have closed by more
than the skin since the build. When a few bodies move fast (the top layer of a 24,000-body pile
still landing at 1 s: 1,325 bodies past the skin each substep), that fails every substep, and
a full rebuild of 1,008,000 particles cost 123 ms a substep (90 of them the list search), against
30 for the forces. So when the motion test (motion.py) finds a pair that moved too far, the
bodies that moved most are *refreshed* instead: each keeps its own reference pose, and

  every pair is listed exactly when its particles' reference positions are within reach + skin

(a full build sets every reference to now; a refresh sets a body's to now). A particle of body
b lies within e⁰_b = |Δx_b| + ‖ΔR_b‖₂ ρ_b of its reference (motion._body_shift), so a pair can
have closed by at most e⁰_a + e⁰_b, and refreshing every body with e⁰ > half the allowed
motion leaves every pair within it. Refreshing body F: its particles leave their partners'
lists, its particles are placed and become their references, and their partners are found
again: the bodies not refreshed since the full build by the build's grid (which holds their
references, build_x), the refreshed ones (whose references the grid no longer holds) by
their reference bounding spheres, then their particles. Every list stays sorted by slot and
symmetric, and holds every touching pair, so every sum runs over the same terms in the same
order as after a full build: the bits do not change (tests/test_refresh.py).

A full build is done instead when the refreshed bodies would exceed ``grid_params[4]`` of the
particles (REFRESH_FRACTION; 0: never refresh), when a refresh would test more body pairs than
PAIR_BUDGET a particle, when a list has overflowed since (its grid walk would miss the refreshed
particles: list_growth.py) or would overflow. One thread refreshes (lists shared between
bodies change); off a CPU the parallel schedule always rebuilds in full.

nbr_flags (neighbours.py) holds, after the parts' slots: per body b, [4 + 3B + b] its state
(MARKED while refreshed now, REFRESHED since the last full build), the refreshed bodies
[4 + 4B + k], their number [4 + 5B], their particles [5 + 5B] and the refreshes so far [6 + 5B]
(benchmarks). A refreshed body's build_pose slot 16 holds its particles' largest distance
from its centre.
"""
import taichi as ti

from . import grid, motion, neighbours, stages
from .arrays import download

REFRESH_FRACTION = 0.25  # of the particles, refreshed since the last full build at most
PAIR_BUDGET = 16.0  # body pairs a refresh may test (its bodies × the refreshed ones), per particle of the scene
MARKED, REFRESHED = 1, 2  # a body's state bits
REACH = 16  # build_pose slot: a refreshed body's particles' largest distance from its centre


def flags_size(num_bodies: int) -> int:
    """Length of nbr_flags for ``num_bodies`` bodies in contact (neighbours.py and above)."""
    return 9 + 5 * num_bodies


def refreshes_so_far(sim) -> int:
    """How many substeps refreshed some lists in part (benchmarks: refreshes per substep)."""
    return int(download(sim._scratch_arrays["nbr_flags"])[6 + 5 * sim.num_bodies]) if sim.many else 0


@ti.func
def _at(state: ti.template(), what):
    """Index of the first of the refresh's slots in nbr_flags plus ``what`` (see above)."""
    return 4 + 3 * state.x.shape[0] + what


@ti.func
def body_state(state: ti.template(), scratch: ti.template(), b):
    return scratch.nbr_flags[_at(state, b)]


@ti.func
def start_build(state: ti.template(), scratch: ti.template()):
    """neighbours.start_build, and no body refreshed once a full build follows (top-level statements)."""
    neighbours.start_build(scratch)
    B = state.x.shape[0]
    keep = 1 - scratch.nbr_flags[0]
    scratch.nbr_flags[_at(state, 2 * B)] *= keep
    scratch.nbr_flags[_at(state, 2 * B + 1)] *= keep


@ti.func
def after_build(state: ti.template(), scratch: ti.template(), b):
    """A full build's end for body b: its pose kept, its references those of the build."""
    motion.keep_build_pose(scratch, state, b)
    scratch.nbr_flags[_at(state, b)] = 0


@ti.func
def settle(model: ti.template(), state: ti.template(), scratch: ti.template(), parallel: ti.template(),
           enabled: ti.template()):
    """After close_pairs_moved (one thread): no rebuild if no pair moved too far, else a refresh
    if it can be done (``enabled``, on one thread or a CPU), else a full build."""
    flag = scratch.nbr_flags[0]
    if flag == motion.MAYBE:
        flag = 0
    elif flag == motion.VIOLATED:
        flag = 1
        if ti.static(enabled and (not parallel or _on_cpu())):
            if _refresh(model, state, scratch, parallel):
                flag = 0
    scratch.nbr_flags[0] = flag


def _on_cpu() -> bool:
    return ti.lang.impl.current_cfg().arch in (ti.x64, ti.arm64)


@ti.func
def _refresh(model: ti.template(), state: ti.template(), scratch: ti.template(), parallel: ti.template()):
    """Refresh every body with e⁰ > half the allowed motion, unless a full build is due; 1 if done."""
    B, N = state.x.shape[0], state.particle_x.shape[0]
    half = 0.5 * scratch.grid_params[2]
    listed, particles = scratch.nbr_flags[_at(state, 2 * B)], scratch.nbr_flags[_at(state, 2 * B + 1)]
    ok = ti.cast(scratch.nbr_flags[scratch.nbr_flags.shape[0] - 1] == 0, ti.i32)  # no list overflowed
    marked = 0
    if ok:
        for b in range(B):
            dx, turn = motion._body_shift(scratch, state, b)
            moved = dx.norm() + turn
            scratch.build_pose[b][13] = moved  # the motion test is done with slot 13
            if moved > half:
                marked += 1
                if body_state(state, scratch, b) == 0:
                    particles += model.body_count[b]
        tested = ti.cast(marked, float) * ti.cast(listed + marked, float)
        ok = ti.cast(particles <= scratch.grid_params[4] * N and tested <= PAIR_BUDGET * N, ti.i32)
    if ok:
        for b in range(B):
            if scratch.build_pose[b][13] > half:
                if body_state(state, scratch, b) == 0:
                    scratch.nbr_flags[_at(state, B + listed)] = b
                    listed += 1
                scratch.nbr_flags[_at(state, b)] |= MARKED
        scratch.nbr_flags[_at(state, 2 * B)] = listed
        scratch.nbr_flags[_at(state, 2 * B + 1)] = particles
        ok = _refresh_marked(model, state, scratch)
    if ok:
        for k in range(listed):
            scratch.nbr_flags[_at(state, scratch.nbr_flags[_at(state, B + k)])] = REFRESHED
        scratch.nbr_flags[_at(state, 2 * B + 2)] += 1
        n = 0  # the active list again, ascending (on one thread: a parallel list_active's two empty
        for i in range(N):  # loops would cost every substep ~60 µs; this, 1-2 ms a refresh at 1M)
            if scratch.nbr_count[i] > 0:
                scratch.active[n] = i
                n += 1
        scratch.nbr_flags[2] = n
        if ti.static(not parallel):
            neighbours.index_active_by_body(model, state, scratch)
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
        _no_pairs(scratch, j)


@ti.func
def _no_pairs(scratch: ti.template(), i):
    """A particle the pair stage will not visit: no pair force or couple (as neighbours.finish_list)."""
    scratch.particle_f[i] = ti.Vector.zero(float, 3)
    scratch.particle_couple[i] = ti.Vector.zero(float, 3)


@ti.func
def _insert(scratch: ti.template(), i, j, stride):
    """Slot j into slot i's list, in slot order; 0 if the list is full (then a full build follows)."""
    n = scratch.nbr_count[i]
    fits = 0
    if n < stride:
        fits = 1
        base, k = i * stride, n - 1
        while k >= 0 and scratch.nbr_list[base + k] > j:
            scratch.nbr_list[base + k + 1] = scratch.nbr_list[base + k]
            k -= 1
        scratch.nbr_list[base + k + 1] = j
        scratch.nbr_count[i] = n + 1
    return fits


@ti.func
def _refresh_marked(model: ti.template(), state: ti.template(), scratch: ti.template()):
    """The marked bodies' lists made again (see the module's docstring); 0 if a list overflowed."""
    B = state.x.shape[0]
    stride = neighbours.list_stride(scratch, state)
    listed = scratch.nbr_flags[_at(state, 2 * B)]
    for k in range(listed):  # 1. out of their partners' lists (the marked ones' are emptied next)
        a = scratch.nbr_flags[_at(state, B + k)]
        if body_state(state, scratch, a) & MARKED != 0:
            for i in range(model.body_start[a], model.body_start[a] + model.body_count[a]):
                for t in range(scratch.nbr_count[i]):
                    j = scratch.nbr_list[i * stride + t]
                    if body_state(state, scratch, model.particle_body[j]) & MARKED == 0:
                        _remove(scratch, j, i, stride)
    for k in range(listed):  # 2. placed now, their references
        a = scratch.nbr_flags[_at(state, B + k)]
        if body_state(state, scratch, a) & MARKED != 0:
            motion.keep_build_pose(scratch, state, a)
            R, x, v, w = state.R[a], state.x[a], state.v[a], state.omega[a]
            reach = 0.0
            for i in range(model.body_start[a], model.body_start[a] + model.body_count[a]):
                stages.place_body_particle(model, state, i, R, x, v, w)
                scratch.build_x[i] = state.particle_x[i]
                scratch.nbr_count[i] = 0
                reach = ti.max(reach, (state.particle_x[i] - x).norm())
            scratch.build_pose[a][REACH] = reach * (1.0 + 1e-5)
    ok = 1
    for k in range(listed):  # 3. their partners found again
        a = scratch.nbr_flags[_at(state, B + k)]
        if body_state(state, scratch, a) & MARKED != 0:
            ok &= _find_partners(model, state, scratch, a, stride)
    if ok:
        for k in range(listed):
            a = scratch.nbr_flags[_at(state, B + k)]
            if body_state(state, scratch, a) & MARKED != 0:
                for i in range(model.body_start[a], model.body_start[a] + model.body_count[a]):
                    if scratch.nbr_count[i] == 0:
                        _no_pairs(scratch, i)
    return ok


@ti.func
def _find_partners(model: ti.template(), state: ti.template(), scratch: ti.template(), a, stride):
    """Marked body a's pairs (its particles at their new references): with the bodies not refreshed
    since the full build, from the build's grid (27 cells: no half shell, as only a's side
    looks); with the refreshed ones (each pair of two marked bodies from the lower index), by
    their reference spheres. 0 if a list was full."""
    B = state.x.shape[0]
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
                    if body_state(state, scratch, b) == 0:
                        d = scratch.sorted_x[slot] - p
                        reach = r_a + model.particle_radius[b] + skin
                        if d.dot(d) < reach * reach:
                            j = scratch.sorted_particle[slot]
                            ok &= _insert(scratch, i, j, stride) & _insert(scratch, j, i, stride)
                    slot += 1
    pose_a = scratch.build_pose[a]
    x_a = ti.Vector([pose_a[0], pose_a[1], pose_a[2]])
    for k in range(scratch.nbr_flags[_at(state, 2 * B)]):
        b = scratch.nbr_flags[_at(state, B + k)]
        if b != a and (body_state(state, scratch, b) & MARKED == 0 or b > a):
            pose_b = scratch.build_pose[b]
            d = ti.Vector([pose_b[0], pose_b[1], pose_b[2]]) - x_a
            r_b = model.particle_radius[b]
            reach = (pose_a[REACH] + pose_b[REACH] + r_a + r_b + skin) * (1.0 + 1e-5)
            if d.dot(d) < reach * reach:
                near = r_a + r_b + skin
                for i in range(model.body_start[a], model.body_start[a] + model.body_count[a]):
                    p = scratch.build_x[i]
                    for j in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
                        e = scratch.build_x[j] - p
                        if e.dot(e) < near * near:
                            ok &= _insert(scratch, i, j, stride) & _insert(scratch, j, i, stride)
    return ok
