"""What a scene with restitution, friction, [[plane]] or [[static]] adds to the substep
(substep.py compiles it in only then, so that a scene without them runs the handout's law bit
for bit as before):

- each contact's damper comes from the two sides' restitution and the mass it moves
  (materials.py: c = 2 ζ' √(k m_eff), m_eff = M / n with n the body's contacts: with the planes
  counted before the forces (``count_plane_block``), with other bodies as the last pair stage
  predicted them (``pair_stage``); summed per body by ``sum_counts``, in ``scratch.contacts``);
- the pair stage with those dampers and friction that sticks (``pair_stage``: each pair's
  tangential spring kept per list entry, pair_slip.py); the planes' law with sticking friction
  is plane_terms.material_planes, in the one force loop (force_loop.py);
- a static body (``model.body_material[b][2]`` = 1) gets no forces and is not integrated (substep.py);
  the pair stage acts on the moving side only, with the static side's mass infinite; a convex
  static touched at its faces (= 2, static_faces.py) is left out of it (its faces are planes).
Every sum keeps fixed orders (slots, blocks), so runs stay bit-reproducible.
"""
from collections import namedtuple

import taichi as ti

from . import candidates, neighbours, pair_slip, sleep
from .contact import lower_slot_first, pair_contact, pair_contact_sticking
from .materials import normal_damping, pair_mu, pair_restitution, sticking_damping
from .matvec import ZERO3, cross, dot, matvec
from .stages import num_planes, planes_in_reach
from .state import DAMPING, DT, FRICTION, MATERIAL_TABLE, MATERIALS, STIFFNESS
from .static_faces import faced, on_face


@ti.func
def is_static(model: ti.template(), b):
    return model.body_material[b][2] > 0.5


@ti.func
def body_contacts(model: ti.template(), state: ti.template(), scratch: ti.template(), b, kind):
    """Body b's contacts of the last evaluation (kind 0: planes, 1: pairs) in scratch.contacts."""
    base = state.particle_x.shape[0] + 2 * model.block_start.shape[0]
    return scratch.contacts[base + 2 * b + kind]


@ti.func
def _pair_mass(model: ti.template(), a, b):
    """The mass a contact between bodies a and b moves (symmetric in a, b, bit for bit)."""
    M_a, M_b = model.body_mass[a], model.body_mass[b]
    m = M_a * M_b / (M_a + M_b)
    if is_static(model, a):
        m = M_b
    if is_static(model, b):
        m = M_a
    return m


@ti.func
def _pair_count(model: ti.template(), state: ti.template(), scratch: ti.template(), a, b):
    """Contacts sharing the pair's load: the larger pair count of its moving sides (at least 1)."""
    n_a = 0 if is_static(model, a) else body_contacts(model, state, scratch, a, 1)
    n_b = 0 if is_static(model, b) else body_contacts(model, state, scratch, b, 1)
    return ti.max(ti.max(n_a, n_b), 1)


@ti.func
def _material_pair(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
                   i, a, p, r_a, x_a, v_a, w_a, j, entry, step):
    """Slot j (another body's particle) on slot i at p (body a): (force, couple, 1 if it touches now
    or will after this substep at their closing speed, else 0, 1 if it touches now). ``entry``: the pair's place in i's
    list, where its sticking spring is kept (pair_slip.py), or −1 (i walks the grid). The law is
    evaluated from the lower slot's side whichever side asks, so that both sides' forces are
    exactly opposite and both copies of the spring evolve alike (pair_stages.pair_between)."""
    f = ZERO3
    couple = ZERO3
    touching = 0
    inside = 0
    b = model.particle_body[j]
    q, r_b = state.particle_x[j], model.particle_radius[b]
    d = q - p
    reach = r_a + r_b
    k, dt = world.values[STIFFNESS], world.values[DT]
    slip = ZERO3
    if dot(d, d) < reach * reach:
        m_eff = _pair_mass(model, a, b) / _pair_count(model, state, scratch, a, b)
        ma, mb = model.body_material[a], model.body_material[b]
        c = normal_damping(pair_restitution(ma[1], mb[1]), k, m_eff, dt, 0.0, 1.0, world.values,
                           MATERIALS + MATERIAL_TABLE, world.values[DAMPING])
        mu = pair_mu(ma[0], mb[0], world.values[FRICTION])
        ct = sticking_damping(k, m_eff, dt)
        x_b, v_b, w_b = state.x[b], state.v[b], state.omega[b]
        lo_p, lo_r, lo_x, lo_v, lo_w, hi_p, hi_r, hi_x, hi_v, hi_w, sign = lower_slot_first(
            i, j, p, r_a, x_a, v_a, w_a, q, r_b, x_b, v_b, w_b)
        f_lo = ZERO3
        point = ZERO3
        # Both sides keep the spring, or neither: j's list may have overflowed (it walks the grid).
        if entry >= 0 and scratch.nbr_count[j] <= neighbours.list_stride(scratch, state):
            f_lo, point, slip = pair_contact_sticking(lo_p, hi_p, lo_r, hi_r, lo_x, lo_v, lo_w, hi_x, hi_v, hi_w,
                                                      k, c, ct, mu, pair_slip.spring(state, scratch, entry), step)
        else:  # no entry: friction viscous below μ f_n (contact.friction)
            f_lo, point, _e = pair_contact(lo_p, hi_p, lo_r, hi_r, lo_x, lo_v, lo_w, hi_x, hi_v, hi_w, k, c, ct, mu)
        f = sign * f_lo
        couple = cross(point - p, f)
        touching = 1
        inside = 1
    elif dot(d, d) < 4.0 * reach * reach:  # about to touch? (for the next count)
        dist = ti.sqrt(dot(d, d))
        closing = dot((v_a + cross(w_a, p - x_a)) - (state.v[b] + cross(state.omega[b], q - state.x[b])), d) / dist
        if dist - reach < closing * dt:
            touching = 1
    if entry >= 0:
        pair_slip.set_spring(state, scratch, entry, slip)  # zero once apart
    return f, couple, touching, inside


MaterialSums = namedtuple("MaterialSums",
                          "model state world scratch i a p r_a x_a v_a w_a step wave waker f couple touching sleepers")


@ti.func
def _add_material_pair(c: ti.template(), j, entry):
    """pair_stage's visitor: candidate j's force, couple and contact count added to the sums (none
    from a static mesh touched at its faces: the planes' term is its contact, static_faces.py).
    With sleeping (``wave`` 0 or 1, else −1), wave 0: a moving body (``waker``) marks the sleeping
    body of j it touches as woken, and ``sleepers`` counts the candidates of sleeping bodies;
    wave 1 (a woken body): the spring's copy of a resting sleeper's particle j written too."""
    b = c.model.particle_body[j]
    if not faced(c.model, b):
        fp, cp, hit, inside = _material_pair(c.model, c.state, c.world, c.scratch, c.i, c.a, c.p, c.r_a, c.x_a,
                                             c.v_a, c.w_a, j, entry, c.step)
        c.f += fp
        c.couple += cp
        c.touching += hit
        if c.wave == 0:
            if sleep.asleep(c.state, b):
                c.sleepers += 1
                if c.waker and inside:
                    sleep.mark_woken(c.state, b)
        elif c.wave == 1:
            if sleep.resting(c.state, b):
                pair_slip.copy_to(c.state, c.scratch, c.i, j, entry)


@ti.func
def pair_stage(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), i, step,
               wave=-1):
    """Stage 3a with materials: slot i's force and couple from its candidates (the other bodies'
    particles near it, candidates.py), their springs stretched over ``step``, and how
    many of them touch it or will after this substep at their closing speed (the next force
    evaluation's count: a count of those touching only would be 0 on a contact's first substep
    and over-damp it, 19 % low at e = 0.1 for volume balls head-on; counting them anew before
    the forces would take a second neighbour search, 75 % more time in a pile). ``wave``: with
    sleeping, pair_wave's, a run-time value (wave 0 also notes whether i has sleepers among its
    candidates); −1 without sleeping."""
    a = model.particle_body[i]
    f = ZERO3
    couple = ZERO3
    touching = 0
    sleepers = 0
    if not is_static(model, a):
        p, r_a = state.particle_x[i], model.particle_radius[a]
        x_a, v_a, w_a = state.x[a], state.v[a], state.omega[a]
        waker = 0
        if wave == 0:
            waker = sleep.moving(state, world, scratch, a)
        candidates.each_candidate(model, state, scratch, i, a, _add_material_pair,
                                  ti.static(MaterialSums(model, state, world, scratch, i, a, p, r_a, x_a, v_a, w_a,
                                                         step, wave, waker, f, couple, touching, sleepers)),
                                  entries=True, one_call=True)
    scratch.particle_f[i] = f
    scratch.particle_couple[i] = couple
    scratch.contacts[i] = touching
    if wave == 0:
        pair_slip.note_sleepers(state, scratch, i, sleepers)


CopySprings = namedtuple("CopySprings", "model state scratch i")


@ti.func
def _copy_spring(c: ti.template(), j, entry):
    """copy_springs' visitor: the pair's spring written to j's copy if j's body rests."""
    if sleep.resting(c.state, c.model.particle_body[j]):
        pair_slip.copy_to(c.state, c.scratch, c.i, j, entry)


@ti.func
def pair_wave(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
              wave, step):
    """Stage 3a with materials and sleeping bodies, pass ``wave`` (0 or 1: a loop at a parallel
    kernel's top level, or a run-time value on one thread, where one copy serves both; each writes its
    own slot, its own list's springs and, wave 1, the sleepers' copies of its own pairs: any
    order). Wave 0: the awake bodies' particles, a moving body marking the sleepers it touches
    (sleep.py). Wave 1: the particles of the sleepers woken in wave 0 (their pairs with an awake
    body's particle evaluated as that side did, on the same copy of the spring: equal and
    opposite); and each awake particle that has sleepers among its candidates writes its new
    springs into the copies of the pairs' resting sides, which skip the pair stage (pair_slip.py):
    so both copies of every pair stay the same, whoever wakes when."""
    for t in range(neighbours.num_active(scratch)):
        i = scratch.active[t]
        b = model.particle_body[i]
        asleep = sleep.asleep(state, b)
        if (wave == 0 and not asleep) or (wave == 1 and asleep and not sleep.resting(state, b)):
            pair_stage(model, state, world, scratch, i, step, wave)  # one call: the law inlined once
        elif wave == 1 and not asleep and pair_slip.near_sleepers(state, scratch, i):
            candidates.each_candidate(model, state, scratch, i, b, _copy_spring,
                                      ti.static(CopySprings(model, state, scratch, i)), entries=True)


@ti.func
def count_contacts(model: ti.template(), state: ti.template(), scratch: ti.template(), b):
    """Body b's contacts (planes, pairs) of this evaluation, for the next one's m_eff."""
    first, count = model.body_blocks[b][0], model.body_blocks[b][1]
    planes, pairs = 0, 0
    N, K = state.particle_x.shape[0], model.block_start.shape[0]
    for k in range(first, first + count):
        planes += scratch.contacts[N + 2 * k]
        pairs += scratch.contacts[N + 2 * k + 1]
    scratch.contacts[N + 2 * K + 2 * b] = planes
    scratch.contacts[N + 2 * K + 2 * b + 1] = pairs


@ti.func
def count_plane_block(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(), k):
    """Block k's particles touching the planes now (before the forces, so that a contact's first
    substep already knows how many share the load: a lagged count of 0 would damp a flat landing
    on n particles n/√n times too hard for that substep)."""
    b = model.block_body[k]
    count = 0
    if not is_static(model, b):
        near = planes_in_reach(model, state, world, k)
        if near:
            x, R, radius = state.x[b], state.R[b], model.particle_radius[b]
            start = model.block_start[k]
            for i in range(start, start + model.block_count[k]):
                p = x + matvec(R, ti.Vector([model.r0_x[i], model.r0_y[i], model.r0_z[i]]))
                for j in range(num_planes(world)):
                    if near & (1 << j):
                        plane = world.planes[j]
                        if plane[3] + radius - dot(ti.Vector([plane[0], plane[1], plane[2]]), p) > 0:
                            count += on_face(world, j, p)
    pairs = 0  # and the block's pair contacts (as the last pair stage predicted them; 0 without pairs)
    for i in range(model.block_start[k], model.block_start[k] + model.block_count[k]):
        pairs += scratch.contacts[i]
    scratch.contacts[state.particle_x.shape[0] + 2 * k] = count
    scratch.contacts[state.particle_x.shape[0] + 2 * k + 1] = pairs


@ti.func
def sum_counts(model: ti.template(), state: ti.template(), scratch: ti.template(), b):
    """Body b's plane and pair contacts now: the sums of its blocks' (count_plane_block)."""
    count_contacts(model, state, scratch, b)
