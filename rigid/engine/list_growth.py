"""Neighbour lists that grow where a pile is dense, with the run's bits unchanged.

Each particle's list holds K slots (neighbours.py). A particle with more candidates walks the
grid every substep instead, which is exact but costs ~1 µs a particle: 1,000 volume spheres
sunk into one another (4-5 % of 208,000 particles past 16 candidates) spent a third of their
pair stage there. So a run starts with K = 16 (neighbours.NEIGHBOURS_PER_PARTICLE: enough for
piles that hold their shape, where a longer stride only costs cache) and doubles K, up to
``MAX_NEIGHBOURS`` (and a memory cap), when a build overflows.

Growing between chunks would make the run depend on where the chunks end (an overflowed
particle sums its pairs in the grid's order, a listed one in slot order). So a chunk that
could still grow runs from a copy of the state: if one of its builds overflowed, the lists
grow, the state is put back, and the chunk runs again with a rebuild at its start. A run
whose lists never overflowed gives the same bits whatever K and whenever its lists were
rebuilt (every sum runs over the touching pairs in slot order), so the result is the run
that had the larger K from the start, however the frames are chunked (tests/test_list_growth.py).
The flag is broadphase.OVERFLOW (neighbours.finish_list raises it).
"""
from __future__ import annotations

import ctypes

import numpy as np
import taichi as ti

from . import broadphase, broadphase_host, pair_slip
from .arrays import ScratchArgs, StateArgs, _cpu_pointer, byte_size, clear, download, upload, zeros

MAX_NEIGHBOURS = 64  # list slots per particle at most
MAX_LIST_BYTES = 1 << 30  # and at most this much memory for the lists


class ListGrowth:
    def __init__(self, num_particles: int, pairs: bool):
        self.num_particles, self.pairs = num_particles, pairs
        self._copy = None  # the Snapshot of a Simulator's arrays, made at its first chunk

    def stride(self, scratch_arrays: dict) -> int:
        return scratch_arrays["nbr_list"].shape[0] // max(1, self.num_particles)

    def can_grow(self, scratch_arrays: dict) -> bool:
        k = self.stride(scratch_arrays)
        return self.pairs and k < MAX_NEIGHBOURS and 2 * k * self.num_particles * 4 <= MAX_LIST_BYTES

    def run(self, sim, run_chunk) -> None:
        """``run_chunk()`` once, or again after growing the lists if one of its builds overflowed."""
        while self.can_grow(sim._scratch_arrays):
            if self._copy is None:
                self._copy = Snapshot(self._kept(sim))
                arrays = sim._scratch_arrays
                self._overflowed = broadphase_host.cell(arrays, broadphase.OVERFLOW)
                self._rebuild = broadphase_host.cell(arrays, broadphase.REBUILD)
            self._overflowed.value = 0  # only this chunk's builds count
            self._copy.save()
            run_chunk()
            if not self._overflowed.value:
                return
            self._copy.restore()
            self._grow(sim)  # from the chunk's start: the pairs' springs are carried into the longer lists
            self._copy = None  # a copy of the new arrays at the next try
            self._rebuild.value = 1  # rebuild (with the longer lists) at the first placement
        run_chunk()

    # What a chunk changes and keeps: the bodies' state, the materials' springs on the planes and,
    # of the scratch arrays, the broadphase's counters and per-body tables and the materials' contact counts;
    # with materials, the lists and their pairs' springs too (the rebuild carries them: pair_slip.py).
    # The rest is rewritten by every substep, or by the rebuild that starts the chunk again, which
    # places every particle from its body's state (the same numbers a substep computes).
    _STATE = tuple(name for name in StateArgs.NAMES if name not in ("particle_x", "particle_v"))
    _SCRATCH = broadphase_host.KEPT + ("contacts",)
    _SPRINGS = ("nbr_count", "nbr_list")

    def _kept(self, sim) -> list:
        names = self._SCRATCH + (self._SPRINGS if sim.materials else ())
        return [getattr(sim.state, name) for name in self._STATE] + [sim._scratch_arrays[n] for n in names]

    def _grow(self, sim) -> None:
        arrays = sim._scratch_arrays
        if sim.materials:  # the pairs' springs (in state.plane_slip) laid out for the longer lists
            pair_slip.grown(sim, self.num_particles, self.stride(arrays))
        else:
            arrays["nbr_list"] = zeros(2 * self.stride(arrays) * self.num_particles, "i")
            clear(arrays["nbr_count"])
            sim.scratch = ScratchArgs()(**{name: arrays[name] for name in ScratchArgs.NAMES})
        sim._launches = None  # prepared for the old arrays


class Snapshot:
    """A copy of some arrays, taken and put back. On the CPU a byte copy from addresses found
    once: a chunk of the 27-sphere pile stepped frame by frame costs ~360 µs, and copying its
    13 arrays through download() took ~100 µs of that."""

    def __init__(self, arrays: list):
        self.arrays = arrays
        where = [(_cpu_pointer(a), byte_size(a)) for a in arrays]
        self.cpu = all(pointer is not None for pointer, _n in where)
        self.copies = [np.empty(n, np.uint8) for _p, n in where] if self.cpu else [None] * len(arrays)
        self.moves = [(c.ctypes.data, p, n) for c, (p, n) in zip(self.copies, where)] if self.cpu else []

    def save(self) -> None:
        if not self.cpu:
            self.copies = [download(a) for a in self.arrays]
            return
        ti.sync()
        for copy, pointer, n in self.moves:
            ctypes.memmove(copy, pointer, n)

    def restore(self) -> None:
        if not self.cpu:
            for array, values in zip(self.arrays, self.copies):
                upload(array, values)
            return
        ti.sync()
        for copy, pointer, n in self.moves:
            ctypes.memmove(pointer, copy, n)
