"""The forward and backward passes, segment by segment, with checkpoints.

The run of ``frames`` frames is cut into segments of K frames (``checkpoint_frames``; by default
the whole run where its tape fits TAPE_BYTES, ``segment_frames``). The forward pass runs a
segment in one launch (``advance``) and keeps each segment's starting state (a checkpoint: one
step of state, on the host) and the rows; the backward pass walks the segments from the last: it
restores the segment's checkpoint, runs the segment forward again (the last one is still on the
tape), then runs its adjoint (Taichi's ``kernel.grad``: ``advance``'s, one launch a segment, or
for scenes of many particles the rows' and substeps' in reverse order, one launch a substep) and
carries the adjoint of the segment's first state into the previous one. Memory is one segment of state (rigid.diff.tape) whatever the horizon; the cost is
one more forward run of every segment but the last (none when the run is one segment).
"""
from __future__ import annotations

import time

import numpy as np

from ..errors import UserError
from ..runtime import compile_settings
from . import kernels as kernel_module
from .tape import Tape

TAPE_BYTES = 256 * 2**20  # the tape's budget (state, forces and their adjoints), which sets K
FRAMES_AT_LEAST = 64  # a tape holds at least this many frames (fewer where the budget says so)
SERIAL_PARTICLES = 512  # up to this many (padded) particles a substep's loops run on one thread
PLANES_AT_LEAST = 5  # the box's floor and four walls
BODIES_AT_LEAST = 2  # a lone body's tape serves two (a body's fields are ~350 bytes a step)
AD_STACK_SPARE = 32  # ad-stack entries the kernels are compiled with, beyond the planes' count
_TAPES: dict = {}
ADJOINT = dict(cfg_optimization=True)  # the adjoint kernels' settings beyond the pass's (below)


# The pass's kernels compile with these settings (rigid.runtime.compile_settings, around each
# kernel's launches: self.options, and ADJOINT around the adjoints' own):
#
# - ``cfg_optimization=True`` for the adjoint kernels only (ADJOINT): Taichi's store-to-load
#   forwarding and dead-store passes, which the engine goes without for its compile time, make the
#   fused adjoint about 3x faster for a few seconds more of its first compile. The forward kernels
#   go without them: compiled with them (Taichi 1.7.4, its default compile), a box resting on the
#   floor left its tape so that the stiffness gradient came out NaN (tests/test_gradients.py's
#   resting box, under RIGID_QUICK_COMPILE=0; the suite's quick compile runs no CFG pass).
# - ``ad_stack_size`` (AD_STACK_SPARE + the planes' count). A mutable local in a loop of a
#   reverse-mode kernel lives on an ad-stack; Taichi 1.7 sizes each to the most values it holds
#   (``ad_stack_size = 0``), but allocates its header as 4 bytes where the runtime uses 8, so a
#   full stack's top adjoint overhangs its allocation by 4 bytes into the neighbouring local:
#   silent, and dependent on what earlier kernels left on the native stack (``advance``'s adjoint
#   drifted after other kernels ran). With more entries than any local takes in one iteration
#   of a stage, no stack is ever full: the force sum over the planes takes the planes' count + 2
#   values, the other locals (the repository's TODO units included) at most 5.
# - ``force_scalarize_matrix=True``: matrices are split into scalars before reverse mode runs, not
#   after. Differentiated as matrices, TODO 7's ``R @ I0⁻¹ @ Rᵀ`` alone compiles for ~1.8 s (its
#   adjoint is one long block that Taichi's passes edit in quadratic time). Split, a ball's first
#   gradient compiles in ~8 s; whole, ~28 s (quick_compile: ~6 and ~9 s, and the split adjoint
#   runs ~3x slower without the CFG passes); the values agree to round-off.


def _power_of_two(n: int, least: int) -> int:
    return max(least, 1 << (max(n, 1) - 1).bit_length())


def step_bytes(bodies: int, particles: int, planes: int, materials: bool) -> int:
    """A tape's bytes a step: per body x, P, L, ω, F, τ, q and their adjoints, the count; per
    (particle, plane) the contact force and (materials) the sticking spring, with adjoints, the
    near flag and a slot of the pairs' list."""
    return bodies * (2 * 22 * 8 + 4) + 4 + particles * planes * (3 * 8 * 2 * (2 if materials else 1) + 1 + 4)


def segment_frames(frames: int, substeps: int, bodies: int, particles: int, planes: int, materials: bool) -> int:
    """K: the whole run, as a power of two of at least FRAMES_AT_LEAST frames (so that runs of
    other lengths share a tape), halved while the tape would pass TAPE_BYTES."""
    k = _power_of_two(frames, FRAMES_AT_LEAST)
    while k > 1 and (k * substeps + 1) * step_bytes(bodies, particles, planes, materials) > TAPE_BYTES:
        k //= 2
    return k


class Pass:
    """A scene's forward and backward passes. ``fused``: the backward runs ``advance``'s adjoint,
    one launch a segment, where the loops are serial (False: one launch a substep, as for scenes of
    many particles; the tests compare the two)."""

    def __init__(self, problem, units, frames: int, checkpoint_frames: int | None = None, fused: bool = True):
        self.problem, self.units, self.frames, self.fused = problem, units, frames, fused
        self.substeps = problem.substeps
        B, N = problem.num_bodies, problem.num_particles
        # Fields sized up (bodies, particles and frames to powers of two, at least the box's 5 planes:
        # the extra ones are stand-ins no particle touches) and kept per process, so that scenes of
        # one kind (law, scheme) and every call of a fit reuse one tape and its compiled kernels.
        P = max(len(problem.planes), PLANES_AT_LEAST)
        if checkpoint_frames is None:
            checkpoint_frames = segment_frames(frames, self.substeps, _power_of_two(B, BODIES_AT_LEAST),
                                               _power_of_two(N, 64), P, problem.materials)
        self.segment = max(1, min(checkpoint_frames, frames)) * self.substeps  # substeps per segment
        self.total = frames * self.substeps
        self.num_segments = -(-self.total // self.segment)
        steps = max(1, checkpoint_frames) * self.substeps + 1
        key = (id(units), problem.scheme, problem.materials, P, _power_of_two(B, BODIES_AT_LEAST),
               _power_of_two(N, 64), _power_of_two(frames + 1, 64), len(problem.table))
        # A tape of more steps serves shorter segments too (its kernels take a segment's length): a
        # run in segments takes one of its kind that the process holds, compiling nothing more.
        held = [s for k, s in _TAPES if k == key and s >= steps]
        if held:
            steps = min(held)
        else:
            tape = Tape(steps, key[4], key[5], P, key[6] - 1, len(problem.table), problem.materials)
            _TAPES[key, steps] = (tape, kernel_module.build(tape, units, problem.scheme, problem.materials, P,
                                                            key[5] <= SERIAL_PARTICLES))
        self.tape, self.k = _TAPES[key, steps]
        self.serial = key[5] <= SERIAL_PARTICLES
        self.options = dict(ad_stack_size=AD_STACK_SPARE + P, force_scalarize_matrix=True)  # the settings above
        self.tape.load(problem)
        self.checkpoints: list = []
        self.seconds = dict(rerun=0.0, adjoint=0.0)  # of the last backward

    def _length(self, g: int) -> int:
        return min(self.segment, self.total - g * self.segment)

    def _frame_at(self, g: int, s: int):
        """The frame whose row is step s of segment g, or None."""
        step = g * self.segment + s
        return step // self.substeps if step % self.substeps == 0 else None

    def _run_segment(self, g: int, write_rows: bool) -> None:
        k, p = self.k, self.problem
        B, N, dt = p.num_bodies, p.num_particles, p.dt
        k.clear(self._length(g), B, N, 0)
        if self.serial:
            if write_rows and g == 0:
                k.rows(0, 0, B)
            k.advance(0, self._length(g), N, B, dt, g * self.segment, self.substeps, int(write_rows))
        else:
            self._run_substeps(g, write_rows)
        if B > 1:
            self._check_apart(g)

    def _run_substeps(self, g: int, write_rows: bool) -> None:
        k, p = self.k, self.problem
        B, N, dt = p.num_bodies, p.num_particles, p.dt
        for s in range(self._length(g)):
            if write_rows and (s > 0 or g == 0) and self._frame_at(g, s) is not None:
                k.rows(s, self._frame_at(g, s), B)
            k.substep(s, N, B, dt)
        end = self._length(g)
        if write_rows:
            k.rows(end, self._frame_at(g, end), B)

    def _check_apart(self, g: int) -> None:
        """Refuse a run where two bodies come within reach of each other (their bounding spheres,
        particle radii included, overlap at some step): pair contact is not differentiated."""
        p = self.problem
        x = self.tape.x.to_numpy()[:self._length(g) + 1, :p.num_bodies]
        reach = p.reach + p.radius
        for a in range(p.num_bodies):
            for b in range(a + 1, p.num_bodies):
                gap = np.linalg.norm(x[:, a] - x[:, b], axis=1) - reach[a] - reach[b]
                if np.any(gap < 0):
                    frame = (g * self.segment + int(np.argmax(gap < 0))) // self.substeps
                    raise UserError(f"bodies {a} and {b} come within reach of each other near frame {frame}: "
                                    f"contact between bodies is not differentiated")

    def forward(self) -> dict:
        """Run the scene; returns the rows (as rigid.Simulator.advance, float64)."""
        with compile_settings(**self.options):
            self._forward()
        return self.rows()

    def _forward(self) -> None:
        t, k, p = self.tape, self.k, self.problem
        B, N = p.num_bodies, p.num_particles
        k.clear(0, B, N, 2)
        k.start(N, B)
        self.checkpoints = []
        for g in range(self.num_segments):
            if g > 0:
                t.save(self._length(g - 1), B, N)
                t.restore(0, B, N)
            if g < self.num_segments - 1:  # the backward re-runs every segment but the last
                t.save(0, B, N)
            self.checkpoints.append(t.checkpoint() if g < self.num_segments - 1 else None)
            self._run_segment(g, True)

    def rows(self) -> dict:
        return self.tape.rows(self.frames, self.problem.num_bodies)

    def backward(self, cotangents: dict) -> dict:
        """The adjoint of the last forward run for ∂L/∂rows = ``cotangents``: ∂L/∂ each parameter
        field (rigid.diff.tape.Tape.PARAMETERS), as float64 numpy."""
        t = self.tape
        self.seconds = dict(rerun=0.0, adjoint=0.0)
        with compile_settings(**self.options):
            if not t.clean:  # a backward stopped half-way: its adjoints may be anywhere
                for f in (t.fc, t.slip, *t.row_fields().values()):
                    f.grad.fill(0)
            t.clean = False
            t.clear_parameter_grads()
            t.seed(cotangents, self.frames, self.problem.num_bodies)
            self._adjoints()
            t.clean = True
        return t.parameter_grads()

    def _adjoints(self) -> None:
        """The segments' adjoints from the last (each re-run first but the last), then the start's."""
        t, k, p = self.tape, self.k, self.problem
        B, N, dt = p.num_bodies, p.num_particles, p.dt
        for g in reversed(range(self.num_segments)):
            start = time.perf_counter()
            if g < self.num_segments - 1:  # the last segment is still on the tape
                t.set_checkpoint(self.checkpoints[g])
                t.restore(0, B, N)
                self._run_segment(g, False)
            self.seconds["rerun"] += time.perf_counter() - start
            start = time.perf_counter()
            end = self._length(g)
            k.clear(end, B, N, 1)
            if g < self.num_segments - 1:
                t.set_checkpoint(self._carried)
                t.restore_grad(end, B, N)
            with compile_settings(**ADJOINT):
                if self.serial and self.fused:
                    k.advance.grad(0, end, N, B, dt, g * self.segment, self.substeps, 1)
                    if g == 0:
                        k.rows.grad(0, 0, B)
                else:
                    for s in range(end, -1, -1):
                        frame = self._frame_at(g, s)
                        if frame is not None and (s > 0 or g == 0):
                            k.rows.grad(s, frame, B)
                        if s > 0:
                            k.substep.grad(s - 1, N, B, dt)
            if g > 0:
                t.save_grad(0, B, N)
                self._carried = t.checkpoint()
            self.seconds["adjoint"] += time.perf_counter() - start
        with compile_settings(**ADJOINT):
            k.start.grad(N, B)
