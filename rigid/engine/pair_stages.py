"""The stages of a substep that exist only when bodies collide (stages.py lists them all):
1b ``place_for_pairs`` (the
particles the pair stage reads), 3a ``pair_stage`` (each particle's force and couple from the
other bodies' particles in its neighbour list, neighbours.py; the law is contact.py's, each
pair evaluated by ``pair_between``), ``pair_forces``, and ``pair_energy``, the same pairs'
energies alone for the frame's contact energy. On one thread pair_once.py's sweep replaces 3a."""
from collections import namedtuple

import taichi as ti

from . import broadphase as bp
from . import candidates, neighbours, sleep, stages
from .contact import lower_slot_first, pair_contact, pair_contact_energy
from .matvec import ZERO3, cross, dot


@ti.func
def place_for_pairs(model: ti.template(), state: ti.template(), scratch: ti.template(), by_body: ti.template(),
                    everything):
    """Stage 1b (bodies in contact): every particle of the bodies awake placed if the lists are
    rebuilt now or ``everything`` (a frame's end; 0 or 1, may be a run-time value), else only
    their active ones (the pair stage reads no other): from the active list, or with ``by_body``
    (one thread, bodies that sleep) body by body over their runs of it
    (neighbours.index_active_by_body), a sleeper passed over at once. A sleeper's particles stay
    where stages.set_at_rest placed them when it fell asleep, never placed again by this code:
    LLVM's contractions round x + R r0 differently at the two places by an ulp, so re-placed by a
    full rebuild they moved, and runs rebuilt at other times parted (pile.toml from frame 90:
    tests/test_skin.py)."""
    gate = neighbours.rebuild_gate(scratch)
    if everything:
        gate = 1
    for i in range(state.particle_x.shape[0] * gate):
        if not sleep.asleep(state, model.particle_body[i]):
            stages.place_particle(model, state, i)
    if ti.static(by_body):
        for b in range(state.x.shape[0] * (1 - gate)):
            if not sleep.asleep(state, b):
                R, x, v, w = state.R[b], state.x[b], state.v[b], state.omega[b]
                first, end = bp.body_active_range(scratch, b)
                for t in range(first, end):
                    stages.place_body_particle(model, state, scratch.active[t], R, x, v, w)
    else:
        place_active(model, state, scratch, 1 - gate)


@ti.func
def place_active(model: ti.template(), state: ti.template(), scratch: ti.template(), gate=1):
    """The active particles of the bodies awake placed, in a top-level loop (``gate`` 0: none)."""
    for t in range(neighbours.num_active(scratch) * gate):
        i = scratch.active[t]
        if not sleep.asleep(state, model.particle_body[i]):
            stages.place_particle(model, state, i)


@ti.func
def pair_between(model: ti.template(), state: ti.template(), i, p, r_a, x_a, v_a, w_a, k, kd, mu, j, reach_max):
    """(force fᵢ on slot i (at p) from slot j, the contact point c, half the pair's energy), zeros when
    the spheres are apart (most candidates: then body b is not loaded, nor its radius where j lies
    beyond ``reach_max`` = r_a + the largest particle radius, broadphase.largest_radius: a chain
    of two dependent loads less for a list entry, ~7 % of the pair stage on a pile). The law is
    evaluated from the lower slot's side whichever side asks, in one call: so the force j gets
    from i is exactly −fᵢ (the same operations on the same numbers; the law written from each
    side rounds differently under LLVM's contractions: measured, 0 of 13,353 touching pairs
    of a dense pile differ, against about half before)."""
    f = ZERO3
    c = ZERO3
    e = 0.0
    p_j, b, r_b, near = _near(model, state, p, r_a, j, reach_max)
    if near:
        x_b, v_b, w_b = state.x[b], state.v[b], state.omega[b]
        lo_p, lo_r, lo_x, lo_v, lo_w, hi_p, hi_r, hi_x, hi_v, hi_w, sign = lower_slot_first(
            i, j, p, r_a, x_a, v_a, w_a, p_j, r_b, x_b, v_b, w_b)
        f_lo, c, e = pair_contact(lo_p, hi_p, lo_r, hi_r, lo_x, lo_v, lo_w, hi_x, hi_v, hi_w, k, kd, kd, mu)
        f = sign * f_lo
    return f, c, e


@ti.func
def _near(model: ti.template(), state: ti.template(), p, r_a, j, reach_max):
    """(p_j, j's body b, its radius r_b, whether the spheres at p (radius r_a) and p_j overlap):
    b and r_b are loaded only where j lies within ``reach_max`` (zeros beyond)."""
    p_j = state.particle_x[j]
    d = p_j - p
    dist2 = dot(d, d)
    b = 0
    r_b = 0.0
    near = False
    if dist2 < reach_max * reach_max:
        b = model.particle_body[j]
        r_b = model.particle_radius[b]
        reach = r_a + r_b
        near = dist2 < reach * reach
    return p_j, b, r_b, near


@ti.func
def pair_energy_between(model: ti.template(), state: ti.template(), i, p, r_a, j, reach_max, k):
    """Half the spring energy ½ k δ² of the pair (i at p, j), zero when apart: pair_between's
    energy, from the lower slot's side as there (contact.pair_contact_energy), without the forces (the
    frame's contact energy needs only this)."""
    e = 0.0
    p_j, _b, r_b, near = _near(model, state, p, r_a, j, reach_max)
    if near:
        if j < i:
            e = pair_contact_energy(p_j, p, r_b, r_a, k)
        else:
            e = pair_contact_energy(p, p_j, r_a, r_b, k)
    return e


EnergySum = namedtuple("EnergySum", "model state i p r_a reach_max k energy")


@ti.func
def _add_energy(c: ti.template(), j):
    """pair_energy's visitor: candidate j's half pair energy, added where the pair touches."""
    e = pair_energy_between(c.model, c.state, c.i, c.p, c.r_a, j, c.reach_max, c.k)
    if e > 0:
        c.energy += e


@ti.func
def pair_energy(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), i):
    """Σ over slot i's candidates of half each touching pair's ½ k δ², in slot order: the energies
    of the pairs pair_forces sums (the frame's contact energy, stages.block_contact_energy)."""
    a = model.particle_body[i]
    p, r_a = state.particle_x[i], model.particle_radius[a]
    k, _kd, _mu = stages.contact_constants(world)
    reach_max = r_a + bp.largest_radius(scratch)
    energy = 0.0
    candidates.each_candidate(model, state, scratch, i, a, _add_energy,
                              ti.static(EnergySum(model, state, i, p, r_a, reach_max, k, energy)))
    return energy


PairSums = namedtuple("PairSums", "model state i p r_a x_a v_a w_a k kd mu reach_max waker wake f couple")


@ti.func
def _add_pair(c: ti.template(), j):
    """pair_forces' visitor: candidate j's force and couple about pᵢ added to the sums when the
    pair touches (the sums take only these, so which other candidates a list holds, its skin,
    when it was built, changes no bit of them; zeros added or not would round the sums
    differently); with ``wake``, a moving body (``waker``) marks the sleeping body of j it
    touches as woken."""
    f, contact, e = pair_between(c.model, c.state, c.i, c.p, c.r_a, c.x_a, c.v_a, c.w_a, c.k, c.kd, c.mu, j,
                                 c.reach_max)
    if ti.static(c.wake):
        b = c.model.particle_body[j]
        if c.waker and e > 0 and sleep.asleep(c.state, b):
            sleep.mark_woken(c.state, b)
    if e > 0 or f[0] != 0 or f[1] != 0 or f[2] != 0:
        c.f += f
        c.couple += cross(contact - c.p, f)


@ti.func
def pair_forces(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), i,
                wake: ti.template(), waking=0):
    """Σ over slot i's candidates (other bodies' particles, candidates.py) of (force, couple about
    pᵢ), in slot order (their energies: pair_energy). With ``wake`` (compiled in) and ``waking``
    (now), a moving body marks the sleeping bodies it touches as woken (sleep.py)."""
    a = model.particle_body[i]
    p, r_a = state.particle_x[i], model.particle_radius[a]
    k, kd, mu = stages.contact_constants(world)
    x_a, v_a, w_a = state.x[a], state.v[a], state.omega[a]
    reach_max = r_a + bp.largest_radius(scratch)
    f = ZERO3
    couple = ZERO3
    waker = 0
    if ti.static(wake):
        waker = sleep.moving(state, world, scratch, a) * waking
    candidates.each_candidate(model, state, scratch, i, a, _add_pair,
                              ti.static(PairSums(model, state, i, p, r_a, x_a, v_a, w_a, k, kd, mu, reach_max,
                                                 waker, wake, f, couple)))
    return f, couple


@ti.func
def pair_stage(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), i,
               wake: ti.template(), waking=1):
    """Stage 3a (bodies in contact): slot i's force and couple from other bodies' particles
    (``wake`` and ``waking``: and the sleepers it wakes, sleep.py)."""
    fp, cp = pair_forces(model, state, world, scratch, i, wake, waking)
    scratch.particle_f[i] = fp
    scratch.particle_couple[i] = cp


@ti.func
def pair_wave(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), wave,
              gate=1):
    """Stage 3a with sleeping bodies, pass ``wave``: 0, the awake bodies' particles (a moving body
    marks the sleepers it touches, sleep.py); 1, the sleepers woken in pass 0 (``gate`` 0: none)."""
    for t in range(neighbours.num_active(scratch) * gate):  # each writes its own slot: any order
        i = scratch.active[t]
        b = model.particle_body[i]
        if sleep.asleep(state, b) == (wave == 1) and (wave == 0 or not sleep.resting(state, b)):
            pair_stage(model, state, world, scratch, i, True, 1 - wave)


@ti.func
def visit_all(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
              sleeping: ti.template(), gate=1):
    """Stage 3a in parallel (at a kernel's top level): each active particle sums its whole list,
    writing its own slot (any order); with ``sleeping``, in two waves, each a top-level loop
    (``gate`` 0 or 1, a run-time value: whether to run at all)."""
    if ti.static(not sleeping):
        for t in range(neighbours.num_active(scratch) * gate):
            pair_stage(model, state, world, scratch, scratch.active[t], False)
    else:
        for wave in ti.static(range(2)):
            pair_wave(model, state, world, scratch, wave, gate)
