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
"""
import taichi as ti

from . import pair_stages
from .arrays import ModelArgs, ScratchArgs, StateArgs, WorldArgs
from .state import DT


class SplitSubstep:
    """The kernels of a parallel substep in parts (``motion``, ``build``, ``place``, ``forces``)."""

    def __init__(self, motion, build, place, forces):
        self.motion, self.build, self.place, self.forces = motion, build, place, forces


def make(place_and_build, evaluate, refreshing: bool) -> SplitSubstep:
    """The parts from kernels.py's stages (``place_and_build``: placement and the gated rebuild
    after the motion test; ``evaluate``: the forces and the update; ``refreshing``: partial
    rebuilds of the lists, refresh.py), for one set of kernels."""
    M, S, W, C = ModelArgs(), StateArgs(), WorldArgs(), ScratchArgs()

    @ti.kernel
    def motion(model: M, state: S, scratch: C):
        pair_stages.note_motion(model, state, scratch, True, refreshing)

    @ti.kernel
    def build(model: M, state: S, scratch: C):
        place_and_build(model, state, scratch, True, 0)

    @ti.kernel
    def place(model: M, state: S, scratch: C):
        pair_stages.place_active(model, state, scratch)

    @ti.kernel
    def forces(model: M, state: S, world: W, scratch: C):
        evaluate(model, state, world, scratch, True, world.values[DT], 0, 1.0)

    return SplitSubstep(motion, build, place, forces)
