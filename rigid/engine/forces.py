"""The external forces: the one place where a force that is not contact enters the substep.

``add_external`` adds them to a block's share of F and τ, after the block's particle loop
(force_loop.py), through the student's TODO 3 (F += f) and TODO 4 (τ += r × f),
so that P and L change exactly by what they impart, in every scene and schedule:

- ``particle_force``: a term on every particle, summed over the block's particles in a pass of
  its own, only for a body that has it (the contact loop stays as lean as without). Today:
      drag      f = −c vᵢ          c: the body's ``drag`` (model.body_material[b][3]), N s/m
- ``point_wrench``: forces at chosen points of a body, added with its first block's sums, so
  that every body's are computed from the same state, before any body is updated. Today:
      the grab  f = k (target − p) − c v_p at the held particle (grab.py: the window's mouse)
      springs   f = (k (|d| − l0) + c (v_b − v_a)·n) n between two bodies' points, or a body's
                and a world point (rigid.bodies.springs; rows in ``world.springs``)

A new force is one more term in ``particle_force`` or ``point_wrench`` (and its parameters in
the model or the world's values); no schedule, stage or kernel changes.
"""
import taichi as ti

from .grab import GRAB_C, GRAB_K, GRAB_SLOT, GRAB_TX
from .matvec import ZERO3, body_offset, cross, dot, matvec, norm

NUM_SPRINGS = 10  # the slot of WorldArgs.values holding how many rows of world.springs each world uses
DRAG = 3  # the component of model.body_material holding the body's drag coefficient


@ti.func
def particle_force(model: ti.template(), b, pv):
    """The external force on a particle of body b moving at ``pv`` (world, m/s): linear drag."""
    return -model.body_material[b][DRAG] * pv


@ti.func
def _end(state: ti.template(), body, point):
    """A spring's end: (world position, world velocity) of ``point`` on ``body`` (−1: the world,
    where ``point`` is already a world point, at rest)."""
    p = point
    v = ZERO3
    if body >= 0:
        r = matvec(state.R[body], point)
        p = state.x[body] + r
        v = state.v[body] + cross(state.omega[body], r)
    return p, v


@ti.func
def _spring_force(world: ti.template(), state: ti.template(), s):
    """Spring s: its two bodies, the ends' body-frame offsets and world positions, and the force on
    its first end (the second gets its opposite)."""
    row = world.springs[s]
    a, b = ti.cast(row[0], ti.i32), ti.cast(row[1], ti.i32)
    ra = ti.Vector([row[2], row[3], row[4]])
    rb = ti.Vector([row[5], row[6], row[7]])
    pa, va = _end(state, a, ra)
    pb, vb = _end(state, b, rb)
    d = pb - pa
    length = norm(d)
    f = ZERO3
    if length > 0:
        n = d / length
        f = (row[8] * (length - row[10]) + row[9] * dot(vb - va, n)) * n
    return a, b, ra, rb, pa, pb, f


@ti.func
def any_point_forces(world: ti.template()):
    """Whether a force at a point acts at all (a grab held, a spring): else none is summed."""
    return world.values[GRAB_SLOT] >= 0 or world.values[NUM_SPRINGS] > 0


@ti.func
def add_external(u: ti.template(), model: ti.template(), state: ti.template(), world: ti.template(), b, k, F, tau):
    """(F, τ) of block k of body b with the external forces added: its particles' (drag), and the
    body's forces at points if k is its first block."""
    F_out, tau_out = F, tau
    if model.body_material[b][DRAG] != 0.0:
        x, R, v, omega = state.x[b], state.R[b], state.v[b], state.omega[b]
        for i in range(model.block_start[k], model.block_start[k] + model.block_count[k]):
            r0 = body_offset(model, i)
            r = matvec(R, r0)
            f = particle_force(model, b, v + cross(omega, r))
            F_out += u.total_force_term(f)
            tau_out += u.torque_term(x + r, x, R, r0, f)
    if model.body_blocks[b][0] == k and any_point_forces(world):
        F_points, tau_points = point_wrench(u, model, state, world, b)
        F_out += F_points
        tau_out += tau_points
    return F_out, tau_out


@ti.func
def point_wrench(u: ti.template(), model: ti.template(), state: ti.template(), world: ti.template(), b):
    """F and τ (about x) that the forces at points put on body b, through TODO 3 and 4: the grab
    (row −1), then each spring with an end on b, in index order (the sums' order is fixed). Each
    row gives a point and a force; one call of the TODOs sums them all (their code is compiled once)."""
    F = ZERO3
    tau = ZERO3
    x, R = state.x[b], state.R[b]
    held = ti.cast(world.values[GRAB_SLOT], ti.i32)
    per_world = ti.cast(world.values[NUM_SPRINGS], ti.i32)  # world w's springs: rows w · S .. (w + 1) · S − 1
    first = model.body_world[b][1] * per_world
    for s in range(first - 1, first + per_world):
        acts = False
        p, r0, f = x, ZERO3, ZERO3
        if s < first:  # the grab: f = k (target − p) − c v_p at the held particle, if it is b's
            if held >= 0 and model.particle_body[held] == b:
                r0 = body_offset(model, held)
                r = matvec(R, r0)
                p = x + r
                target = ti.Vector([world.values[GRAB_TX], world.values[GRAB_TX + 1], world.values[GRAB_TX + 2]])
                f = world.values[GRAB_K] * (target - p) - world.values[GRAB_C] * (state.v[b] + cross(state.omega[b], r))
                acts = True
        elif ti.cast(world.springs[s][0], ti.i32) == b or ti.cast(world.springs[s][1], ti.i32) == b:
            a, _b, ra, rb, pa, pb, f_a = _spring_force(world, state, s)
            acts = True
            if a == b:
                p, r0, f = pa, ra, f_a
            else:
                p, r0, f = pb, rb, -f_a
        if acts:
            F += u.total_force_term(f)
            tau += u.torque_term(p, x, R, r0, f)
    return F, tau
