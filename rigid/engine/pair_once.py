"""Stage 3a on one thread: each touching pair's force computed once and added to both particles.

The list of particle i holds j exactly when j's holds i (neighbours.py), so visiting every
list in full (pair_stages.pair_stage, the parallel schedule's way: each particle writes only
its own sum) computes each pair twice. On one thread the sweep below visits the active
particles in turn and, for each entry j > i, evaluates the pair once (pair_between: from the
lower slot, as the full visit does from either side) and adds fᵢ to i and −fᵢ to j. In the
serial build the active list is in ascending slot order, so each particle receives its
terms in its list's order, as in the full visit. The sums agree with the full visit's to
round-off (LLVM contracts the sweep's arithmetic into FMAs differently: measured on a dense
pile, 54 % of the particles' forces bit-equal, the largest difference 1.6e-7 of the largest
force); each schedule alone stays bit-reproducible (fixed order, one thread), as the serial
and parallel schedules already agreed only to round-off. The pair stage of a dense pile
(21,375 particles) falls from 1.74 to 1.36 ms a substep.

A particle whose list overflowed (more than K candidates: it keeps only its count) walks the
build's grid at its turn, as the full visit does, sums every pair itself, and gives −f to
the touching ones above it that have lists; a particle below it computes their pair at its
own turn and keeps it. So each pair is still added once to each side.

With sleeping bodies (sleep.py) a first pass lets each moving awake body mark the sleepers
its particles touch (``mark_woken``: the full visit's first wave, without the forces), and
every body that does not rest note the sleepers in its lists; the sweep then skips the pairs
of two resting sleepers only, and a resting sleeper's own sums are not read. It walks the
bodies in slot order (the active list's order) and passes over a resting sleeper that no
other body noted with one test: all its pairs are with resting sleepers. So a settled
125-sphere pile costs 24-29 µs a substep, not 150 (its 5,250 particles were each visited), and
an awake particle gets the same terms, in the same order, whether bodies sleep or not: a run
with sleeping on keeps the bits of one with it off until a first body falls asleep, and
after, wherever the sleepers are exactly at rest.
"""
from collections import namedtuple

import taichi as ti

from . import broadphase as bp
from . import candidates, neighbours, sleep, stages
from .matvec import ZERO3, cross, dot
from .pair_stages import pair_between


@ti.func
def any_asleep(state: ti.template()):
    """1 when some body is asleep, else 0 (one thread)."""
    found = 0
    for b in range(state.x.shape[0]):
        if sleep.asleep(state, b):
            found = 1
    return found


@ti.func
def overlap(state: ti.template(), model: ti.template(), p, r_a, j):
    p_j, r_b = state.particle_x[j], model.particle_radius[model.particle_body[j]]
    d = p_j - p
    dist2 = dot(d, d)
    reach = r_a + r_b
    return dist2 < reach * reach and dist2 > 0


SleeperNote = namedtuple("SleeperNote", "model state scratch p r_a waker")


@ti.func
def _note_sleeper(c: ti.template(), j):
    """_note_sleepers' visitor: a sleeping body of candidate j is seen (the sweep visits it), and a
    ``waker`` (a moving body) marks it woken if j overlaps the particle at p."""
    b = c.model.particle_body[j]
    if sleep.asleep(c.state, b):
        bp.see_sleeper(c.scratch, b)
        if c.waker and overlap(c.state, c.model, c.p, c.r_a, j):
            sleep.mark_woken(c.state, b)


@ti.func
def _note_sleepers(model: ti.template(), state: ti.template(), scratch: ti.template(), i, a, waker):
    """Particle i of body a, which does not rest: every sleeping body among its candidates is seen
    (the sweep visits it), and a ``waker`` (a moving body) marks those it overlaps as woken."""
    p, r_a = state.particle_x[i], model.particle_radius[a]
    candidates.each_candidate(model, state, scratch, i, a, _note_sleeper,
                              ti.static(SleeperNote(model, state, scratch, p, r_a, waker)))


@ti.func
def mark_woken(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template()):
    """Before the sweep, with a body asleep: each awake body's particles see the sleeping bodies in
    their lists, and a moving one's mark those they overlap as woken; then the particles of the
    bodies woken now see theirs. A resting sleeper that no body seen here touches has only
    pairs with resting sleepers, all skipped: the sweep passes over it at the cost of one test,
    so a settled pile costs next to nothing. Walks bodies (their runs of the active list,
    neighbours.index_active_by_body), not the whole list, for that reason."""
    for turn in range(2):  # the awake bodies, then those woken just now (one call: the walk inlined once)
        for b in range(state.x.shape[0]):
            asleep = sleep.asleep(state, b)
            if (turn == 0 and not asleep) or (turn == 1 and asleep and not sleep.resting(state, b)):
                waker = 0
                if turn == 0:
                    waker = sleep.moving(state, world, scratch, b)
                first, end = bp.body_active_range(scratch, b)
                for t in range(first, end):
                    _note_sleepers(model, state, scratch, scratch.active[t], b, waker)


@ti.func
def _visited(state: ti.template(), scratch: ti.template(), b, sleeping: ti.template()):
    """Whether the sweep visits body b: it does not rest, or a body that does not saw it."""
    visit = True
    if ti.static(sleeping):
        visit = not sleep.resting(state, b) or bp.seen_sleeper(scratch, b)
    return visit


@ti.func
def wanted(model: ti.template(), state: ti.template(), a_rests, j, sleeping: ti.template()):
    """Whether a pair with slot j is evaluated when the other side's body rests (``a_rests``,
    sleep.resting, read once a particle): not two resting sleepers (j's body read only then)."""
    keep = True
    if ti.static(sleeping):
        if a_rests:
            keep = not sleep.resting(state, model.particle_body[j])
    return keep


@ti.func
def touching(f):
    """A pair's force is exactly zero when apart (then its couple is zero too)."""
    return f[0] != 0 or f[1] != 0 or f[2] != 0


@ti.func
def gives_to(model: ti.template(), state: ti.template(), scratch: ti.template(), j, part):
    """Whether a sweep's turn gives a pair's −f to slot j: always on one thread (``part`` −1), else
    only within the turn's part (pair_parts.py: another part collects it)."""
    return part < 0 or bp.part_of(scratch, model.particle_body[j]) == part


@ti.func
def give(state: ti.template(), scratch: ti.template(), j, fi, c):
    """Particle j's side of a pair whose force on the other side is fi, at the contact point c."""
    fj = -fi
    scratch.particle_f[j] += fj
    scratch.particle_couple[j] += cross(c - state.particle_x[j], fj)


@ti.func
def sweep(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
          sleeping: ti.template()):
    """Every active particle's pair force and couple, each pair evaluated once (on one thread;
    with ``sleeping`` compiled in, after mark_woken if a body is asleep: then body by body, the
    bodies _visited, over their runs of the active list, which keeps its order)."""
    k, kd, mu = stages.contact_constants(world)  # read once: the loops' stores may alias them for LLVM
    stride = neighbours.list_stride(scratch, state)
    if ti.static(sleeping):
        for b in range(state.x.shape[0]):
            if _visited(state, scratch, b, sleeping):
                first, end = bp.body_active_range(scratch, b)
                for t in range(first, end):
                    scratch.particle_f[scratch.active[t]] = ZERO3
                    scratch.particle_couple[scratch.active[t]] = ZERO3
        for b in range(state.x.shape[0]):
            if _visited(state, scratch, b, sleeping):
                a_rests = sleep.resting(state, b)
                bp.unsee_sleeper(scratch, b)  # all zero again after every sweep
                body = (model.particle_radius[b], state.x[b], state.v[b], state.omega[b])  # read once a body
                first, end = bp.body_active_range(scratch, b)
                for t in range(first, end):
                    sweep_particle(model, state, scratch, scratch.active[t], b, a_rests, body, k, kd, mu, stride,
                                   sleeping, -1)
    else:
        for t in range(neighbours.num_active(scratch)):
            i = scratch.active[t]
            scratch.particle_f[i] = ZERO3
            scratch.particle_couple[i] = ZERO3
        for t in range(neighbours.num_active(scratch)):
            i = scratch.active[t]
            a = model.particle_body[i]
            body = (model.particle_radius[a], state.x[a], state.v[a], state.omega[a])
            sweep_particle(model, state, scratch, i, a, False, body, k, kd, mu, stride, sleeping, -1)


SweepTurn = namedtuple("SweepTurn", "model state scratch i p r_a x_a v_a w_a a_rests k kd mu reach_max stride "
                                     "sleeping part listed f couple")


@ti.func
def _sweep_pair(c: ti.template(), j):
    """sweep_particle's visitor: the pair with candidate j evaluated at i's turn if j is above i
    (the lower slots gave theirs in their turns) or i's list overflowed (then i sums every pair
    itself); its −f given to j if j is above i and has a list (an overflowed j sums it itself)."""
    if (j > c.i or not c.listed) and wanted(c.model, c.state, c.a_rests, j, c.sleeping):
        fp, contact, _e = pair_between(c.model, c.state, c.i, c.p, c.r_a, c.x_a, c.v_a, c.w_a, c.k, c.kd, c.mu, j,
                                       c.reach_max)
        if touching(fp):
            c.f += fp
            c.couple += cross(contact - c.p, fp)
            if j > c.i and c.scratch.nbr_count[j] <= c.stride and gives_to(c.model, c.state, c.scratch, j, c.part):
                give(c.state, c.scratch, j, fp, contact)


@ti.func
def sweep_particle(model: ti.template(), state: ti.template(), scratch: ti.template(), i, a, a_rests, body: ti.template(),
                   k, kd, mu, stride, sleeping: ti.template(), part):
    """The sweep's turn of active particle i (of body a, resting or not; ``body``: its (radius, x,
    v, ω)): its pairs with higher slots evaluated and given (``part`` >= 0: only to the particles
    of that part, pair_parts.py), added, in slot order, to what the lower slots gave it; so a
    particle's terms come in its list's order, as in the full visit (pair_stages.pair_forces)."""
    p = state.particle_x[i]
    r_a, x_a, v_a, w_a = body
    listed = scratch.nbr_count[i] <= stride
    f = ZERO3  # an overflowed particle: lower slots gave it nothing
    couple = ZERO3
    if listed:
        f = scratch.particle_f[i]  # the pairs with lower slots, given in their turns
        couple = scratch.particle_couple[i]
    reach_max = r_a + bp.largest_radius(scratch)
    candidates.each_candidate(model, state, scratch, i, a, _sweep_pair,
                              ti.static(SweepTurn(model, state, scratch, i, p, r_a, x_a, v_a, w_a, a_rests, k, kd, mu,
                                                  reach_max, stride, sleeping, part, listed, f, couple)),
                              candidates.ABOVE)
    scratch.particle_f[i] = f
    scratch.particle_couple[i] = couple
