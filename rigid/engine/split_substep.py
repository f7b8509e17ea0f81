"""The parallel substep on a CPU in three or four launches, so that a substep that does not
rebuild the neighbour lists does not pay for the rebuild's loops.

Every top-level loop of a parallel kernel is a round trip through Taichi's thread pool, and a
loop of no iterations costs one too: measured on this project's 2-vCPU machine, 20 empty
loops in one kernel took 570-850 µs (28-43 µs each), 20 loops of 2,048 iterations 510-530 µs.
The one-kernel substep (kernels.py ``substep``) gates the rebuild's dozen loops by the flag
the motion test raises (``n * gate`` iterations), so every substep paid for them. Here the host
launches the motion test, reads the flag through its address (arrays.IntCell, ~1 µs on the
CPU), then either the placement and rebuild or the placement of the active particles alone,
then the forces and the update: the same loops in the same order as the one kernel runs them
(so the same bits), less the empty ones, for two more launches (~20 µs each). RK4 (four force
evaluations a substep) and the GPU (where reading the flag waits for the device) keep the one
kernel.

A substep that refreshes some bodies' lists (refresh.py) leaves their search PENDING after the
motion test; the host then launches ``refresh``: the marked particles search side by side on
both threads (each into its own list), then one thread enters the other sides and makes the
active list again (the 24,000-body pile: ~42 µs a refreshed body with all of it on one thread,
~27 so; the search loop alone 1.7x faster on two threads than on one).
"""
import taichi as ti

from ..runtime import CSE_OFF, SettingsKernel
from . import broadphase, find_pairs, pair_stages, refresh, substep
from .arrays import ModelArgs, ScratchArgs, StateArgs, WorldArgs
from .state import DT


class SplitSubstep:
    """The kernels of a parallel substep in parts (``motion``, ``refresh`` or None, ``build``,
    ``place``, ``forces``)."""

    def __init__(self, motion, refresh, build, place, forces):
        self.motion, self.refresh, self.build, self.place, self.forces = motion, refresh, build, place, forces


def make(plan) -> SplitSubstep:
    """The parts of substep.py's stages (find_pairs' ``note_motion`` and ``place_and_build``: the
    motion test, then placement and the gated rebuild; substep's ``step``: the forces and the update) for one ``plan`` (substep.Plan; with
    ``refreshing``, partial rebuilds of the lists, refresh.py)."""
    refreshing = plan.refreshing
    M, S, W, C = ModelArgs(), StateArgs(), WorldArgs(), ScratchArgs()

    @ti.kernel
    def motion(model: M, state: S, scratch: C):
        find_pairs.note_motion(model, state, scratch, True, refreshing, True)

    @ti.kernel
    def refresh_lists(model: M, state: S, scratch: C):
        for t in range(broadphase.searching(scratch)):
            refresh.search(model, state, scratch, t)
        ti.loop_config(serialize=True)
        for _ in range(1):
            refresh.finish(model, state, scratch, True)

    @ti.kernel
    def build(model: M, state: S, scratch: C):
        find_pairs.place_and_build(plan, model, state, scratch, True, 0)

    @ti.kernel
    def place(model: M, state: S, scratch: C):
        pair_stages.place_active(model, state, scratch)

    @ti.kernel
    def forces(model: M, state: S, world: W, scratch: C):
        substep.step(plan, model, state, world, scratch, True, world.values[DT], 0, 1.0)

    # The forces and the update, the largest of the parts, compile as the serial schedule's frame
    # does (rigid.runtime.CSE_OFF: half a many-body scene's first compile on this schedule, and
    # no measurable speed); the others keep Taichi's loop-invariant caching, which they run faster
    # with (report/bench_versions.md).
    return SplitSubstep(motion, refresh_lists if refreshing else None, build, place, SettingsKernel(forces, CSE_OFF))
