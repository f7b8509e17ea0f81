"""Stage 2 of the substep, the broadphase's one interface: which particles of different bodies
may touch. The pair stages see it only through these four:

    update          the motion test, then the lists kept, refreshed for the bodies that moved
                    (refresh.py) or built again from the grid (grid.py, neighbours.py)
    place_and_build the particles placed and, if the motion test asked, the full build
    each_candidate  a particle's candidates, from its list or the grid (candidates.py)
    sleepers        broadphase.see_sleeper and friends: which lists hold a sleeper

Its state is in named places (broadphase.py); the substep (substep.py) calls ``update`` once a
force evaluation, the parallel schedule on a CPU its parts (split_substep.py).
"""
import taichi as ti

from . import grid, motion, neighbours, pair_slip, pair_stages, refresh, schedule
from .candidates import each_candidate

__all__ = ["update", "note_motion", "place_and_build", "each_candidate"]


@ti.func
def update(plan: ti.template(), model: ti.template(), state: ti.template(), scratch: ti.template(),
           parallel: ti.template(), everything):
    """The motion test, then the placement and the rebuild if needed (``everything``: place every
    particle, not only the active ones; 0 or 1, may be a run-time value)."""
    note_motion(model, state, scratch, parallel, plan.refreshing, False)
    place_and_build(plan, model, state, scratch, parallel, everything)


@ti.func
def note_motion(model: ti.template(), state: ti.template(), scratch: ti.template(), parallel: ti.template(),
                refresh_lists: ti.template(), defer_search: ti.template()):
    """Stage 1a (bodies in contact): whether the neighbour lists must be rebuilt (motion.py):
    each body's motion on one thread on a CPU (a parallel kernel's top level would split its
    loops), as parallel loops off one (motion.note_motion_spread), then
    the pairs of bodies near enough to touch, in parallel with ``parallel``; then, if a pair
    moved too far, the bodies that moved refreshed (with ``refresh_lists``: refresh.py) or a
    full build asked for (``defer_search``: the refresh's search left to split_substep.py)."""
    if ti.static(parallel):
        if ti.static(schedule.on_cpu()):
            ti.loop_config(serialize=True)
            for _ in range(1):
                motion.note_motion(scratch, state)
        else:  # a GPU's one thread would take milliseconds over its bodies
            motion.note_motion_spread(scratch, state)
        for a in range(state.x.shape[0] * motion.motion_undecided(scratch)):
            motion.close_pairs_moved(model, state, scratch, a)
        ti.loop_config(serialize=True)
        for _ in range(1):
            refresh.settle(model, state, scratch, parallel, refresh_lists, defer_search)
    else:
        motion.note_motion(scratch, state)
        for a in range(state.x.shape[0] * motion.motion_undecided(scratch)):
            motion.close_pairs_moved(model, state, scratch, a)
        refresh.settle(model, state, scratch, parallel, refresh_lists, defer_search)


@ti.func
def place_and_build(plan: ti.template(), model: ti.template(), state: ti.template(), scratch: ti.template(),
                    parallel: ti.template(), everything):
    """place after the motion test, bodies in contact (every loop gated by the rebuild flag)."""
    by_body = ti.static(plan.sleeping and not parallel)  # the one-thread stages walk bodies (pair_once.py)
    pair_stages.place_for_pairs(model, state, scratch, by_body, everything)
    grid.clear_and_count(scratch, model, state, neighbours.rebuild_gate(scratch))
    if ti.static(parallel):
        grid.finish_parallel(scratch, model, state, neighbours.rebuild_gate(scratch))
    else:
        grid.finish_serial(scratch, model, state, neighbours.rebuild_gate(scratch))
    refresh.start_build(state, scratch)
    if ti.static(plan.materials):  # the pairs' sticking springs, to carry into the new lists
        for i in range(state.particle_x.shape[0] * neighbours.rebuild_gate(scratch)):
            pair_slip.keep(state, scratch, i)
    for i in range(state.particle_x.shape[0] * neighbours.rebuild_gate(scratch)):
        neighbours.clear_list(scratch, i)
    for i in range(state.particle_x.shape[0] * neighbours.rebuild_gate(scratch)):
        neighbours.build_list(model, state, scratch, i)
    for i in range(state.particle_x.shape[0] * neighbours.rebuild_gate(scratch)):
        neighbours.finish_list(state, scratch, i, parallel)
    if ti.static(plan.materials):
        for i in range(state.particle_x.shape[0] * neighbours.rebuild_gate(scratch)):
            pair_slip.carry(state, scratch, i)
    neighbours.list_active(state, scratch, neighbours.rebuild_gate(scratch), parallel)
    for b in range(state.x.shape[0] * neighbours.rebuild_gate(scratch)):
        refresh.after_build(state, scratch, b)
    if ti.static(by_body):
        if neighbours.rebuild_gate(scratch):
            neighbours.index_active_by_body(model, state, scratch)
    if ti.static(plan.materials):  # a particle left out of the new lists has no pair contacts
        for i in range(state.particle_x.shape[0] * neighbours.rebuild_gate(scratch)):
            if scratch.nbr_count[i] == 0:
                scratch.contacts[i] = 0
    neighbours.clear_flag(scratch)
