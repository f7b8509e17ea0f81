"""Stage 3b, the one force loop: every particle's force, and each block's share of F and τ.

For each particle i of block k (body b), in slot order:

    fᵢ = TODO 2 (m g)                     gravity_force
       + the static planes in reach       plane_terms.py: the handout's law, or the materials'
       + the pair force from other bodies scratch.particle_f (stage 3a: pair_stages.py et al.)
    F += TODO 3 (fᵢ)                      total_force_term
    τ += TODO 4 (pᵢ, x, R, r0ᵢ, fᵢ) + the pairs' couple (c − pᵢ) × fᵢ at the contact point c

then the forces that are not contact (forces.add_external: drag, the grab, springs), and the
block's (F, τ) stored for stage 4 (stages.body_wrench sums the blocks in order). A scene with
materials only changes the plane term and the counts of contacts (m_eff, materials.py); a new
contact law on the planes is one more ``*_planes`` function, not another loop.
"""
import taichi as ti

from . import forces, plane_terms
from .material_stages import body_contacts, is_static
from .materials import sticking_damping
from .matvec import ZERO3, matvec
from .stages import contact_constants, gravity, num_planes, planes_in_reach, wrench
from .state import DAMPING, DT, FRICTION, STIFFNESS

FAR = 1e30  # offset of a stand-in plane: behind it lie only coordinates below -1e30 (finite in f32)
NEAR_SLOTS = 3  # planes a block's loop tests with its slots unrolled (the box: floor, one x, one z wall)


@ti.func
def particle_loop(u: ti.template(), model: ti.template(), scratch: ti.template(), k, x, R, planes: ti.template(),
                  c: ti.template(), pairs: ti.template(), m, g):
    """Σ TODO 3 and TODO 4 over block k's particles, each one's force being TODO 2 + ``planes(c, ...)``
    + its pair force and couple (scratch, if ``pairs``); with materials (``c.contacts``), the
    block's pair contacts counted too."""
    F = ZERO3
    tau = ZERO3
    pair_contacts = 0
    start = model.block_start[k]
    for i in range(start, start + model.block_count[k]):
        r0 = ti.Vector([model.r0_x[i], model.r0_y[i], model.r0_z[i]])
        r = matvec(R, r0)
        p = x + r
        f = planes(c, i, p, r, u.gravity_force(m, g))
        couple = ZERO3
        if ti.static(pairs):
            f += scratch.particle_f[i]
            couple = scratch.particle_couple[i]
            if ti.static(hasattr(c, "contacts")):
                pair_contacts += scratch.contacts[i]
        F += u.total_force_term(f)
        tau += u.torque_term(p, x, R, r0, f) + couple
    return F, tau, pair_contacts


@ti.func
def _plain_loop(u: ti.template(), model: ti.template(), scratch: ti.template(), k, x, R, values: ti.template(),
                count: ti.template(), pairs: ti.template(), m, g):
    """particle_loop with the handout's law on ``count`` plane slots (``values``: PlainPlanes' fields but count)."""
    F, tau, _n = particle_loop(u, model, scratch, k, x, R, plane_terms.plain_planes,
                               ti.static(plane_terms.PlainPlanes(*values, count)), pairs, m, g)
    return F, tau


@ti.func
def _plain_share(u: ti.template(), model: ti.template(), state: ti.template(), world: ti.template(),
                 scratch: ti.template(), k, b, pairs: ti.template(), compact: ti.template()):
    """Block k's (F, τ) under the handout's law: the planes in reach put in three plain slots, in
    index order (the other slots hold a plane no particle is behind: its force is exactly zero),
    and the loop compiled for 0, 1 or 3 of them (``compact``: one loop over every plane)."""
    x, R, v, omega = state.x[b], state.R[b], state.v[b], state.omega[b]
    near = planes_in_reach(model, state, world, k)
    # Loaded once, so that LLVM vectorises the loop over the particles.
    m, g = model.particle_mass[b], gravity(world)
    stiffness, kd, mu = contact_constants(world)
    radius = model.particle_radius[b]
    plane0 = ti.Vector([0.0, 1.0, 0.0, -FAR])
    plane1 = ti.Vector([0.0, 1.0, 0.0, -FAR])
    plane2 = ti.Vector([0.0, 1.0, 0.0, -FAR])
    used = 0
    for j in range(num_planes(world)):
        if near & (1 << j):
            if used == 0:
                plane0 = world.planes[j]
            elif used == 1:
                plane1 = world.planes[j]
            elif used == 2:
                plane2 = world.planes[j]
            used += 1
    c = ti.static((world, v, omega, radius, stiffness, kd, mu, plane0, plane1, plane2))
    F = ZERO3
    tau = ZERO3
    if ti.static(compact):  # one loop for every case (kernels.compact_block_loops)
        F, tau = _plain_loop(u, model, scratch, k, x, R, c, -1, pairs, m, g)
    elif used == 0:
        F, tau = _plain_loop(u, model, scratch, k, x, R, c, 0, pairs, m, g)
    elif used == 1:  # e.g. resting on the floor
        F, tau = _plain_loop(u, model, scratch, k, x, R, c, 1, pairs, m, g)
    elif used <= NEAR_SLOTS:
        F, tau = _plain_loop(u, model, scratch, k, x, R, c, NEAR_SLOTS, pairs, m, g)
    else:
        F, tau = _plain_loop(u, model, scratch, k, x, R, c, -1, pairs, m, g)
    return F, tau


@ti.func
def _material_share(u: ti.template(), model: ti.template(), state: ti.template(), world: ti.template(),
                    scratch: ti.template(), k, b, pairs: ti.template(), step, touch_part: ti.template()):
    """Block k's (F, τ) with materials (``step``: the time this evaluation's force acts, Δt or RK4's
    weight of it; ``touch_part``: materials.plane_damping's first-step rule, the Euler schemes),
    and its plane and pair contacts stored for the next evaluation's m_eff. A static body: none."""
    F = ZERO3
    tau = ZERO3
    plane_contacts = 0
    pair_contacts = 0
    if not is_static(model, b):
        x, R, v, omega = state.x[b], state.R[b], state.v[b], state.omega[b]
        m, g = model.particle_mass[b], gravity(world)
        stiffness, dt = world.values[STIFFNESS], world.values[DT]
        m_eff = model.body_mass[b] / ti.max(body_contacts(model, state, scratch, b, 0), 1)
        c = ti.static(plane_terms.MaterialPlanes(
            state, world, v, omega, model.particle_radius[b], stiffness, dt, g, planes_in_reach(model, state, world, k),
            model.body_material[b], m_eff, sticking_damping(stiffness, m_eff, dt), world.values[DAMPING],
            world.values[FRICTION], step, touch_part, plane_contacts))
        F, tau, pair_contacts = particle_loop(u, model, scratch, k, x, R, plane_terms.material_planes, c, pairs, m, g)
    base = state.particle_x.shape[0]
    scratch.contacts[base + 2 * k] = plane_contacts
    scratch.contacts[base + 2 * k + 1] = pair_contacts
    return F, tau


@ti.func
def block_forces(u: ti.template(), model: ti.template(), state: ti.template(), world: ti.template(),
                 scratch: ti.template(), k, pairs: ti.template(), compact: ti.template(),
                 materials: ti.template(), step, touch_part: ti.template()):
    """Stage 3b for block k: its particles' forces and the block's share of F (TODO 3) and τ
    (TODO 4), summed in slot order, + the external forces, into scratch.block_wrench[k]."""
    b = model.block_body[k]
    F = ZERO3
    tau = ZERO3
    if ti.static(materials):
        F, tau = _material_share(u, model, state, world, scratch, k, b, pairs, step, touch_part)
    else:
        F, tau = _plain_share(u, model, state, world, scratch, k, b, pairs, compact)
    F, tau = forces.add_external(u, model, state, world, b, k, F, tau)
    scratch.block_wrench[k] = wrench(F, tau)
