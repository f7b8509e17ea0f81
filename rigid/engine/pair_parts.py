"""Stage 3a on a CPU's threads: the one-thread sweep (pair_once.py) run in parts side by side,
the bodies cut into the parts by where they are, weighted by their work (part_cut.py).

The parallel schedule's visit (pair_stages.visit_all) lets every particle sum its whole list,
so each touching pair is evaluated twice, once from each side. Here each part runs the sweep
over its own bodies' particles, ascending by slot, as the sweep runs over all of them, except
that it gives a pair's −f only to its own part's particles. A particle then lacks the terms of
its partners below it in other parts, which the sweep would have given it at their turns: at
its turn it first collects them (``collect_from_other_parts``), each computed as that partner's
turn computes it (pair_between from the lower slot, then pair_once.give). So a particle's sum
is

  its partners below it in its part (given at their turns), then those below it in other
  parts (collected, ascending), then its partners above it (from its list's end down).

Only the pairs across the cut are evaluated twice. Each part's work is a fixed sequence
whichever thread runs it, and the cut is a fixed function of the state (part_cut.py), so a run
stays bit-reproducible; like the sweep it sums only touching pairs, so the lists' skin and
rebuilds change no bit. The sums agree with the one-thread sweep's to round-off: another order
of the same terms, and LLVM's fast math may round an expression inlined at two places
differently. Which pairs cross follows the number of parts (one per CPU thread), so runs on
machines with other thread counts agree to round-off, as the schedules themselves do
(schedule.py). (The parts were slot ranges before the cut: slots follow the lattice the scene
laid out, which a pile forgets, and on 1,000 volume spheres in contact 54 % of the list
entries crossed it; see part_cut.py.)

Taichi's CPU backend hands out a parallel loop's iterations in blocks of at least 512
(schedule.py), so a loop over a few parts would run on one thread: the parts loop runs over
``parts × SPREAD`` iterations and each part is the first iteration of its block. With bodies
asleep (sleep.py), the moving bodies first mark the sleepers they touch as woken
(``wake_if_touched``, found from the sleepers' side), then the parts skip the pairs
of two resting sleepers as the sweep does; once one body in MANY_ASLEEP sleeps, the parallel
schedule runs the waves of pair_stages.visit_all instead, which pass over a resting sleeper
at once (``prepare``).
"""
from collections import namedtuple

import taichi as ti

from . import broadphase as bp
from . import candidates, neighbours, pair_once, pair_stages, part_cut, schedule, sleep, stages
from .matvec import ZERO3
from .pair_once import give, sweep_particle, touching
from .pair_stages import pair_between

SPREAD = 512  # iterations per part in the parts loop: one block of Taichi's CPU thread pool each
MANY_ASLEEP = 4  # a body in this many asleep or more: the waves, which pass over resting sleepers at once
PARTS_PER_THREAD = 1  # one part a thread: each more cut adds the pairs across it twice


def parts_here() -> int:
    """How many parts the sweep is cut into in this process (after ti.init): PARTS_PER_THREAD for
    each of Taichi's CPU threads; 0 off a CPU (a GPU runs pair_stages.visit_all)."""
    if not schedule.on_cpu():
        return 0
    return max(1, ti.lang.impl.current_cfg().cpu_max_num_threads) * PARTS_PER_THREAD


@ti.func
def prepare(model: ti.template(), state: ti.template(), scratch: ti.template(), parts: ti.template(),
            sleeping: ti.template()):
    """On one thread, before the parts: with ``sleeping``, the mode (0 if no body is asleep now, 1
    if a few are, 2 if one in MANY_ASLEEP or more), kept in broadphase.SLEEP_MODE and read back,
    as a top-level loop hands its result to the next through memory; unless the mode is 2 (no
    parts), the bodies cut into parts (part_cut.py)."""
    ti.loop_config(serialize=True)
    for _ in range(1):
        mode = 0
        if ti.static(sleeping):
            count = 0
            for b in range(state.x.shape[0]):
                if sleep.asleep(state, b):
                    count += 1
            if count > 0:
                mode = 1
            if count * MANY_ASLEEP >= state.x.shape[0]:
                mode = 2
        bp.put(scratch, bp.SLEEP_MODE, mode)
        if mode != 2:
            part_cut.cut_bodies(model, state, scratch, parts)
    return bp.get(scratch, bp.SLEEP_MODE)


WakeCheck = namedtuple("WakeCheck", "model state world scratch body p r")


@ti.func
def _wake_if(c: ti.template(), j):
    """wake_if_touched's visitor: the sleeping body is marked woken if candidate j, of a moving awake
    body, overlaps its particle at p (radius r)."""
    a = c.model.particle_body[j]
    if (not sleep.asleep(c.state, a) and pair_once.overlap(c.state, c.model, c.p, c.r, j)
            and sleep.moving(c.state, c.world, c.scratch, a)):
        sleep.mark_woken(c.state, c.body)


@ti.func
def wake_if_touched(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), b):
    """Sleeping body b is marked woken if a particle of a moving awake body touches one of its own
    (sleep.py), found from b's side: its particles' candidates are exactly the particles that
    have them among theirs, so a few sleepers cost a few lists, not a pass over every awake
    particle's (that pass cost 6 ms a substep on 1,000 volume spheres). Before the parts, so
    that each part reads final resting flags."""
    if sleep.asleep(state, b):
        r_b = model.particle_radius[b]
        for s in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
            p = state.particle_x[s]
            candidates.each_candidate(model, state, scratch, s, b, _wake_if,
                                      ti.static(WakeCheck(model, state, world, scratch, b, p, r_b)))


Collect = namedtuple("Collect", "model state scratch i part i_rests k kd mu r_max sleeping")


@ti.func
def _collect(c: ti.template(), j):
    """collect_from_other_parts' visitor: a partner j below i in another part gives its term as its
    own sweep turn computes it (from j's side: pair_between evaluates from the lower slot)."""
    if j < c.i:
        b = c.model.particle_body[j]
        if bp.part_of(c.scratch, b) != c.part and pair_once.wanted(c.model, c.state, c.i_rests, j,
                                                                                  c.sleeping):
            r_b = c.model.particle_radius[b]
            fj, contact, _e = pair_between(c.model, c.state, j, c.state.particle_x[j], r_b, c.state.x[b], c.state.v[b],
                                           c.state.omega[b], c.k, c.kd, c.mu, c.i, r_b + c.r_max)
            if touching(fj):
                give(c.state, c.scratch, c.i, fj, contact)


@ti.func
def collect_from_other_parts(model: ti.template(), state: ti.template(), scratch: ti.template(), i, part, i_rests,
                             k, kd, mu, r_max, sleeping: ti.template()):
    """Listed particle i of ``part``, at its turn: the terms of its touching partners below it in
    other parts, ascending, each as that partner's sweep turn computes and gives it (an
    overflowed particle sums every pair itself at its turn)."""
    candidates.each_candidate(model, state, scratch, i, model.particle_body[i], _collect,
                              ti.static(Collect(model, state, scratch, i, part, i_rests, k, kd, mu, r_max, sleeping)),
                              candidates.BELOW)


@ti.func
def sweep_part(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), part,
               sleeping: ti.template()):
    """One part (its bodies after part_cut.cut_bodies, ascending): its sums zeroed, then at each
    listed particle's turn its terms from the other parts below it collected and its sweep turn
    run (with ``sleeping``, the pairs of two resting sleepers skipped, as pair_once's sweep does)."""
    k, kd, mu = stages.contact_constants(world)
    stride = neighbours.list_stride(scratch, state)
    r_max = bp.largest_radius(scratch)
    for b in range(state.x.shape[0]):
        if bp.part_of(scratch, b) == part:
            for i in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
                if scratch.nbr_count[i] > 0:
                    scratch.particle_f[i] = ZERO3
                    scratch.particle_couple[i] = ZERO3
    for b in range(state.x.shape[0]):
        if bp.part_of(scratch, b) == part:
            a_rests = False
            if ti.static(sleeping):
                a_rests = sleep.resting(state, b)
            body = (model.particle_radius[b], state.x[b], state.v[b], state.omega[b])
            touches = 0
            for i in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
                n = scratch.nbr_count[i]
                if n > 0:
                    if n <= stride:
                        collect_from_other_parts(model, state, scratch, i, part, a_rests, k, kd, mu, r_max, sleeping)
                    sweep_particle(model, state, scratch, i, b, a_rests, body, k, kd, mu, stride, sleeping, part)
                    if touching(scratch.particle_f[i]):  # final: no later turn gives to i
                        touches += 1
            bp.set_body_int(scratch, b, bp.TOUCHES, touches)  # the next cut's weight


@ti.func
def sweep_parts(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
                parts: ti.template(), gate, sleeping: ti.template()):
    """Stage 3a at a kernel's top level: the parts side by side (``gate`` 0 or 1, a run-time value:
    whether to run at all), after part_cut.cut_bodies."""
    for t in range(parts * SPREAD * gate):
        if t % SPREAD == 0:
            sweep_part(model, state, world, scratch, t // SPREAD, sleeping)


@ti.func
def parallel_pairs(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
                   sleeping: ti.template(), parts: ti.template()):
    """Stage 3a of the parallel schedule on a CPU (at a kernel's top level): the bodies cut into
    parts and the sweep run in them; with ``sleeping`` compiled in and a few bodies asleep, after
    the moving bodies marked the sleepers they touch (``wake_if_touched``); with many asleep, the
    waves of pair_stages.visit_all, which pass over a resting sleeper's particles at once."""
    mode = prepare(model, state, scratch, parts, sleeping)
    if ti.static(sleeping):
        few, many = ti.cast(mode == 1, ti.i32), ti.cast(mode == 2, ti.i32)
        for b in range(state.x.shape[0] * few):
            wake_if_touched(model, state, world, scratch, b)
        pair_stages.visit_all(model, state, world, scratch, sleeping, many)
        sweep_parts(model, state, world, scratch, parts, 1 - many, sleeping)
    else:
        sweep_parts(model, state, world, scratch, parts, 1, sleeping)
