"""The substep, read top to bottom: what every schedule runs, for one body or many.

    place          1.  pᵢ = x + R r0ᵢ, vᵢ = v + ω × R r0ᵢ               stages.place_particles
                   2.  the neighbour lists kept, refreshed or rebuilt   find_pairs.update (the
                       as the particles moved (bodies in contact)       broadphase's interface)
    step           3a. each particle's pair force and couple           pair_stages / pair_once / pair_parts
                   3b. fᵢ = TODO 2 + planes + pairs; F, τ (TODO 3, 4)   force_loop.block_forces
                       + drag, the grab, springs                       forces.add_external
                   4.  each body: F, τ summed; x, P, q, L (TODO 5-7)    schemes.py

A ``Plan`` holds what is chosen once, at compile time: the TODO units ``u``, the scheme, whether
bodies collide (``pairs``), materials, sleeping, the CPU's parts and list refreshes. The kernels
(kernels.py) call ``place`` and ``step``: the serial schedule in one loop on one thread, the
parallel one with each stage's loops at a kernel's top level (Taichi runs each such loop in
parallel, in order), so every stage is written once for both.
"""
from collections import namedtuple

import taichi as ti

from . import (find_pairs, force_loop, material_stages, neighbours, pair_once, pair_parts, pair_stages, schemes, sleep,
               stages)
from .state import DT

Plan = namedtuple("Plan", "u update rk4 pairs materials sleeping parts refreshing compact")


def make_plan(units, scheme: str, pairs: bool, materials: bool, compact: bool, refreshing: bool = True) -> Plan:
    """The compile-time choices for ``units`` and ``scheme``. Bodies may sleep (sleep.py) only without
    RK4; lists be refreshed in part (refresh.py) only without materials (whose contacts keep
    per-contact memory: static friction's springs, the counts of m_eff) and where ``refreshing``
    (refresh.worth_refreshing: scenes of many bodies)."""
    rk4 = scheme == "rk4"
    update = schemes.symplectic_update if scheme == "symplectic" else schemes.euler_update
    return Plan(units, update, rk4, pairs, materials, sleeping=pairs and not rk4,
                parts=pair_parts.parts_here(), refreshing=refreshing and not materials, compact=compact)


@ti.func
def place(plan: ti.template(), model: ti.template(), state: ti.template(), scratch: ti.template(),
          parallel: ti.template(), everything):
    """Stages 1-2: the particles placed (bodies in contact: the active ones, unless ``everything``
    (0 or 1, may be a run-time value) or a rebuild), the lists rebuilt if needed."""
    if ti.static(plan.pairs):
        find_pairs.update(plan, model, state, scratch, parallel, everything)
    else:
        stages.place_particles(model, state)


@ti.func
def step(plan: ti.template(), model: ti.template(), state: ti.template(), world: ti.template(),
         scratch: ti.template(), parallel: ti.template(), dt, stage, weight):
    """Stages 3-4 on the placed particles: one force evaluation, then every body's update (RK4:
    its ``stage``, whose force acts for ``weight`` of Δt)."""
    if ti.static(plan.materials):  # each body's contacts now (planes, pairs), for its contacts' m_eff
        for k in range(model.block_start.shape[0]):
            material_stages.count_plane_block(model, state, world, scratch, k)
        for b in range(state.x.shape[0]):
            material_stages.sum_counts(model, state, scratch, b)
    if ti.static(plan.pairs):
        pair_forces(plan, model, state, world, scratch, parallel, weight * world.values[DT])
    for k in range(model.block_start.shape[0]):
        if not ti.static(plan.sleeping) or not sleep.resting(state, model.block_body[k]):
            force_loop.block_forces(plan.u, model, state, world, scratch, k, plan.pairs, plan.compact, plan.materials,
                                    weight * world.values[DT], not plan.rk4)
    for b in range(state.x.shape[0]):
        if ti.static(plan.rk4):
            rk4_stage(plan, model, state, scratch, b, dt, stage)
        else:
            update_body(plan, model, state, scratch, world, b, dt)


@ti.func
def pair_forces(plan: ti.template(), model: ti.template(), state: ti.template(), world: ti.template(),
                scratch: ti.template(), parallel: ti.template(), step):
    """Stage 3a, each particle's force and couple from the other bodies', by the schedule's way of
    walking the pairs (the same law, contact.py, and candidates, candidates.py); with materials,
    the pairs' sticking springs stretch over ``step`` (pair_slip.py)."""
    if ti.static(plan.materials and plan.sleeping and parallel):  # in two waves (sleep.py)
        for wave in ti.static(range(2)):
            material_stages.pair_wave(model, state, world, scratch, wave, step)
    elif ti.static(plan.materials and plan.sleeping):  # the same, the wave a run-time value
        for wave in range(2):
            material_stages.pair_wave(model, state, world, scratch, wave, step)
    elif ti.static(plan.materials):
        for t in range(neighbours.num_active(scratch)):  # each writes its own slot: any order
            material_stages.pair_stage(model, state, world, scratch, scratch.active[t], step)
    elif ti.static(parallel and plan.parts):  # a CPU: the sweep in parts (pair_parts.py)
        pair_parts.parallel_pairs(model, state, world, scratch, plan.sleeping, plan.parts)
    elif ti.static(parallel):  # each particle's full list (its own slot: any order)
        pair_stages.visit_all(model, state, world, scratch, plan.sleeping)
    else:  # on one thread, each pair once (pair_once.py)
        if ti.static(plan.sleeping):
            if pair_once.any_asleep(state):
                pair_once.mark_woken(model, state, world, scratch)
        pair_once.sweep(model, state, world, scratch, plan.sleeping)


@ti.func
def update_body(plan: ti.template(), model: ti.template(), state: ti.template(), scratch: ti.template(),
                world: ti.template(), b, dt):
    """Stage 4 for body b: its wrench and the scheme's update (a static body: its contacts only; a
    resting sleeper: nothing, sleep.py)."""
    if ti.static(plan.materials):
        material_stages.count_contacts(model, state, scratch, b)  # a sleeper's: as it fell asleep
    if not ti.static(plan.materials) or not material_stages.is_static(model, b):  # (a static body never sleeps)
        if ti.static(plan.sleeping):
            sleeping_update(plan, model, state, scratch, world, b, dt)
        else:
            F, tau = stages.body_wrench(model, scratch, b)
            plan.update(plan.u, model, state, b, dt, F, tau)


@ti.func
def sleeping_update(plan: ti.template(), model: ti.template(), state: ti.template(), scratch: ti.template(),
                    world: ti.template(), b, dt):
    """Body b's update with sleeping bodies: none while it rests; else the scheme's, and set at
    rest if it falls asleep now (sleep.py)."""
    if not sleep.resting(state, b):
        sleep.begin_update(state, b)
        F, tau = stages.body_wrench(model, scratch, b)
        plan.update(plan.u, model, state, b, dt, F, tau)
        if sleep.end_update(state, world, scratch, b):  # at rest from now on
            stages.set_at_rest(model, state, b)


@ti.func
def rk4_stage(plan: ti.template(), model: ti.template(), state: ti.template(), scratch: ti.template(), b, dt, stage):
    F, tau = stages.body_wrench(model, scratch, b)
    if ti.static(plan.materials):
        material_stages.count_contacts(model, state, scratch, b)
    if not ti.static(plan.materials) or not material_stages.is_static(model, b):
        schemes.rk4_stage(plan.u, model, state, scratch, b, dt, F, tau, stage)


@ti.func
def rk4_finish(plan: ti.template(), model: ti.template(), state: ti.template(), scratch: ti.template(), b, dt):
    if not ti.static(plan.materials) or not material_stages.is_static(model, b):
        schemes.rk4_finish(plan.u, model, state, scratch, b, dt)
