"""Stage 3a on a CPU's threads: the one-thread sweep (pair_once.py) cut into parts by slot,
the parts run side by side.

The parallel schedule's visit (pair_stages.visit_all) lets every particle sum its whole list,
so each touching pair is evaluated twice, once from each side. Here the slots are cut into
``parts`` ranges [lo, hi); a thread runs a part as the sweep runs the whole, except that it
gives a pair's −f only to slots below hi (its own part's). A particle of the part then lacks
the terms of its partners below lo, which the sweep would have given it at their turns; the
part adds them first, before its sweep starts (``collect_from_below``), each computed as that
partner's turn computes it (pair_between from the lower slot, then pair_once.give). So each
particle receives the same terms in the same order as in the one-thread sweep:

  its partners below it, ascending (those below lo collected first, then the part's own at
  their turns), then its partners above it, from its list's end down (at its own turn).

With Taichi's fast math, LLVM may round an expression inlined at two places differently, so
the sums match the one-thread sweep's to round-off (bit for bit with ``fast_math=False``,
checked on a 125-sphere pile in contact for 1, 2, 4 and 7 parts); a run stays
bit-reproducible: a part's work is a fixed sequence whichever thread runs it, and like the
sweep it sums only touching pairs, so the lists' skin and rebuilds change no bit. Which pairs
cross an edge follows the number of parts (one per CPU thread), so runs on machines with
other thread counts agree to round-off, as the schedules themselves do (schedule.py). Only the
pairs across a part's lower edge are evaluated twice; slots follow bodies, which a scene lays
out in space (a pile's lattice), so few pairs cross (on 1,000 spheres in contact, 2 parts:
+16 % work on one thread).

Taichi's CPU backend hands out a parallel loop's iterations in blocks of at least 512
(schedule.py), so a loop over a few parts would run on one thread: the parts loop runs over
``parts × SPREAD`` iterations and each part is the first iteration of its block. With bodies
asleep (sleep.py), the moving bodies first mark the sleepers they touch as woken
(``wake_if_touched``, found from the sleepers' side), then the parts skip the pairs
of two resting sleepers as the sweep does; once one body in MANY_ASLEEP sleeps, the parallel
schedule runs the waves of pair_stages.visit_all instead, which pass over a resting sleeper
at once (``note_asleep``).
"""
import taichi as ti

from . import grid, neighbours, pair_once, pair_stages, sleep, stages
from .pair_once import give, sweep_particle, touching
from .pair_stages import pair_between

SPREAD = 512  # iterations per part in the parts loop: one block of Taichi's CPU thread pool each
MANY_ASLEEP = 4  # a body in this many asleep or more: the waves, which pass over resting sleepers at once
PARTS_PER_THREAD = 1  # one part a thread: each more part adds its lower edge's pairs twice (2 parts: +16 % work, 4: +53 %)


def parts_here() -> int:
    """How many parts the sweep is cut into in this process (after ti.init): PARTS_PER_THREAD for
    each of Taichi's CPU threads; 0 off a CPU (a GPU runs pair_stages.visit_all)."""
    cfg = ti.lang.impl.current_cfg()
    if cfg.arch not in (ti.x64, ti.arm64):
        return 0
    return max(1, cfg.cpu_max_num_threads) * PARTS_PER_THREAD



@ti.func
def note_asleep(state: ti.template(), scratch: ti.template()):
    """0 if no body is asleep now, 1 if a few are, 2 if one in MANY_ASLEEP or more: found by one
    thread, kept in nbr_flags (neighbours.py) and read back, as a top-level loop hands its result
    to the next through memory."""
    slot = scratch.nbr_flags.shape[0] - 2
    ti.loop_config(serialize=True)
    for _ in range(1):
        count = 0
        for b in range(state.x.shape[0]):
            if sleep.asleep(state, b):
                count += 1
        mode = 0
        if count > 0:
            mode = 1
        if count * MANY_ASLEEP >= state.x.shape[0]:
            mode = 2
        scratch.nbr_flags[slot] = mode
    return scratch.nbr_flags[slot]


@ti.func
def wake_if_touched(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), b):
    """Sleeping body b is marked woken if a particle of a moving awake body touches one of its own
    (sleep.py), found from b's side: its particles' lists hold exactly the particles that have
    them in theirs, so a few sleepers cost a few lists, not a pass over every awake particle's
    (that pass cost 6 ms a substep on 1,000 volume spheres). Before the parts, so that each part
    reads final resting flags."""
    if sleep.asleep(state, b):
        r_b = model.particle_radius[b]
        stride = neighbours.list_stride(scratch, state)
        for s in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
            p = state.particle_x[s]
            n = scratch.nbr_count[s]
            if n <= stride:
                for t in range(n):
                    j = scratch.nbr_list[s * stride + t]
                    if _wakes(model, state, world, scratch, p, r_b, j):
                        sleep.mark_woken(state, b)
            else:  # an overflowed list: the build's grid around its build position
                g = grid.cell_coords(scratch, scratch.build_x[s])
                for r in range(grid.ROWS_AROUND):
                    lo, hi = grid.around_range(scratch, g, r)
                    for slot in range(lo, hi):
                        if scratch.sorted_body[slot] != b and _wakes(model, state, world, scratch, p, r_b,
                                                                      scratch.sorted_particle[slot]):
                            sleep.mark_woken(state, b)


@ti.func
def _wakes(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), p, r, j):
    """Whether slot j, of a moving awake body, overlaps the sleeping particle at p (radius r)."""
    a = model.particle_body[j]
    return (not sleep.asleep(state, a) and pair_once.overlap(state, model, p, r, j)
            and sleep.moving(state, world, scratch, a))


@ti.func
def collect_from_below(model: ti.template(), state: ti.template(), scratch: ti.template(), lo, hi, k, kd, mu, stride,
                       sleeping: ti.template()):
    """Each listed particle of [lo, hi): its force and couple set to the sum, ascending, of its
    touching pairs with slots below lo, each as the lower slot's sweep turn computes and gives
    it. An overflowed particle sums every pair itself at its turn."""
    zero = ti.Vector.zero(float, 3)
    r_max = scratch.grid_params[3]
    for i in range(lo, hi):
        n = scratch.nbr_count[i]
        if n > 0:
            scratch.particle_f[i] = zero
            scratch.particle_couple[i] = zero
            i_rests = False
            if ti.static(sleeping):
                i_rests = sleep.resting(state, model.particle_body[i])
            if n <= stride:
                base = i * stride
                for t in range(n):
                    j = scratch.nbr_list[base + t]
                    if j >= lo:  # sorted: the rest are the part's own or above
                        break
                    if not pair_once.wanted(model, state, i_rests, j, sleeping):  # two resting sleepers
                        continue
                    b = model.particle_body[j]
                    r_b = model.particle_radius[b]
                    fj, c, _e = pair_between(model, state, j, state.particle_x[j], r_b, state.x[b], state.v[b],
                                             state.omega[b], k, kd, mu, i, r_b + r_max)
                    if touching(fj):
                        give(state, scratch, i, fj, c)


@ti.func
def sweep_part(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), part, parts,
               sleeping: ti.template()):
    """One part: collect_from_below, then the sweep's turns of its listed particles (with
    ``sleeping``, the pairs of two resting sleepers skipped, as pair_once's sweep does)."""
    n = state.particle_x.shape[0]
    lo, hi = (n * part) // parts, (n * (part + 1)) // parts
    k, kd, mu = stages.contact_constants(world)
    stride = neighbours.list_stride(scratch, state)
    collect_from_below(model, state, scratch, lo, hi, k, kd, mu, stride, sleeping)
    for i in range(lo, hi):
        if scratch.nbr_count[i] > 0:
            a = model.particle_body[i]
            a_rests = False
            if ti.static(sleeping):
                a_rests = sleep.resting(state, a)
            body = (model.particle_radius[a], state.x[a], state.v[a], state.omega[a])
            sweep_particle(model, state, scratch, i, a, a_rests, body, k, kd, mu, stride, sleeping, hi)


@ti.func
def sweep_parts(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
                parts: ti.template(), gate, sleeping: ti.template()):
    """Stage 3a at a kernel's top level: the parts side by side (``gate`` 0 or 1, a run-time value:
    whether to run at all)."""
    for t in range(parts * SPREAD * gate):
        if t % SPREAD == 0:
            sweep_part(model, state, world, scratch, t // SPREAD, parts, sleeping)


@ti.func
def parallel_pairs(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
                   sleeping: ti.template(), parts: ti.template()):
    """Stage 3a of the parallel schedule on a CPU (at a kernel's top level): the sweep in parts;
    with ``sleeping`` compiled in and a few bodies asleep, after the moving bodies marked the
    sleepers they touch (``wake_if_touched``); with many asleep, the waves of
    pair_stages.visit_all, which pass over a resting sleeper's particles at once."""
    if ti.static(sleeping):
        mode = note_asleep(state, scratch)
        few, many = ti.cast(mode == 1, ti.i32), ti.cast(mode == 2, ti.i32)
        for b in range(state.x.shape[0] * few):
            wake_if_touched(model, state, world, scratch, b)
        pair_stages.visit_all(model, state, world, scratch, sleeping, many)
        sweep_parts(model, state, world, scratch, parts, 1 - many, sleeping)
    else:
        sweep_parts(model, state, world, scratch, parts, 1, sleeping)
