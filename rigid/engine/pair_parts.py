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
checked on a 125- and a 1,000-sphere pile for 1, 2, 4 and 7 parts); a run stays
bit-reproducible: a part's work is a fixed sequence whichever thread runs it, and like the
sweep it sums only touching pairs, so the lists' skin and rebuilds change no bit. Only the
pairs across a part's lower edge are evaluated twice; slots follow bodies, which a scene lays
out in space (a pile's lattice), so few pairs cross (on 1,000 spheres in contact, 2 parts:
+16 % work on one thread).

Taichi's CPU backend hands out a parallel loop's iterations in blocks of at least 512
(schedule.py), so a loop over a few parts would run on one thread: the parts loop runs over
``parts × SPREAD`` iterations and each part is the first iteration of its block. Bodies
asleep (sleep.py) need the waves of pair_stages.visit_all, which the parallel schedule keeps
for a substep that has a sleeper (``note_asleep``).
"""
import taichi as ti

from . import neighbours, pair_once, pair_stages, stages
from .pair_once import give, sweep_particle, touching
from .pair_stages import pair_between

SPREAD = 512  # iterations per part in the parts loop: one block of Taichi's CPU thread pool each
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
    """1 if a body is asleep now, else 0: found by one thread, kept in nbr_flags (neighbours.py)
    and read back, as a top-level loop hands its result to the next through memory."""
    slot = scratch.nbr_flags.shape[0] - 2
    ti.loop_config(serialize=True)
    for _ in range(1):
        scratch.nbr_flags[slot] = pair_once.any_asleep(state)
    return scratch.nbr_flags[slot]


@ti.func
def collect_from_below(model: ti.template(), state: ti.template(), scratch: ti.template(), lo, hi, k, kd, mu, stride):
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
            if n <= stride:
                base = i * stride
                for t in range(n):
                    j = scratch.nbr_list[base + t]
                    if j >= lo:  # sorted: the rest are the part's own or above
                        break
                    b = model.particle_body[j]
                    r_b = model.particle_radius[b]
                    fj, c, _e = pair_between(model, state, j, state.particle_x[j], r_b, state.x[b], state.v[b],
                                             state.omega[b], k, kd, mu, i, r_b + r_max)
                    if touching(fj):
                        give(state, scratch, i, fj, c)


@ti.func
def sweep_part(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), part, parts):
    """One part: collect_from_below, then the sweep's turns of its listed particles."""
    n = state.particle_x.shape[0]
    lo, hi = (n * part) // parts, (n * (part + 1)) // parts
    k, kd, mu = stages.contact_constants(world)
    stride = neighbours.list_stride(scratch, state)
    collect_from_below(model, state, scratch, lo, hi, k, kd, mu, stride)
    for i in range(lo, hi):
        if scratch.nbr_count[i] > 0:
            a = model.particle_body[i]
            body = (model.particle_radius[a], state.x[a], state.v[a], state.omega[a])
            sweep_particle(model, state, scratch, i, a, False, body, k, kd, mu, stride, False, hi)


@ti.func
def sweep_parts(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
                parts: ti.template(), gate):
    """Stage 3a at a kernel's top level: the parts side by side (``gate`` 0 or 1, a run-time value:
    whether to run at all)."""
    for t in range(parts * SPREAD * gate):
        if t % SPREAD == 0:
            sweep_part(model, state, world, scratch, t // SPREAD, parts)


@ti.func
def parallel_pairs(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
                   sleeping: ti.template(), parts: ti.template()):
    """Stage 3a of the parallel schedule on a CPU (at a kernel's top level): the sweep in parts,
    or with ``sleeping`` compiled in and a body asleep, the waves of pair_stages.visit_all."""
    asleep = 0
    if ti.static(sleeping):
        asleep = note_asleep(state, scratch)
        pair_stages.visit_all(model, state, world, scratch, sleeping, asleep)
    sweep_parts(model, state, world, scratch, parts, 1 - asleep)
