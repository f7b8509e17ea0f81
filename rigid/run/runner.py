"""The frame loop shared by headless runs and recordings.

``run_frames`` steps the simulator (in chunks of frames when nothing is drawn),
keeps the trajectory for the export, stops at the first frame that blows up, and
turns Ctrl-C into a clean stop: whatever happens, the frames simulated so far are saved.
"""
from __future__ import annotations

import contextlib
import signal
import threading
import time
from dataclasses import dataclass

from .compile_guard import ctrl_c_stops_at_once
from .diagnostics import Trajectory, first_blow_up, stability_hint
from .escape import first_escape
from .exports import write_exports
from .progress import FrameBar, TimeLeft


def energy_bound(mass: float, gravity, kinetic0: float) -> float:
    """How far the total energy may rise above its start before we call it a blow-up.

    The body has no energy source: only the integrator's error adds energy (a small
    fraction of this bound in the scenes of assets/scenes). An unstable contact spring adds it
    exponentially; we stop once it has gained the energy of lifting the body by 1 m
    or half its initial kinetic energy, whichever is larger.
    """
    import numpy as np

    return mass * float(np.linalg.norm(gravity)) * 1.0 + 0.5 * kinetic0 + 1e-6


class StopRun(Exception):
    """Raised by an ``on_frame`` callback to end the run normally (e.g. the window was closed)."""


@dataclass
class RunResult:
    frames: int  # frames simulated after the initial state
    status: str  # "done", "interrupted" or "blew-up"
    message: str = ""
    last_row: dict | None = None  # the last good frame's row (what a summary reports)

    @property
    def exit_code(self) -> int:
        return {"done": 0, "interrupted": 130, "blew-up": 3}[self.status]


def run_frames(sim, frames: int | None, export_path=None, on_frame=None) -> RunResult:
    """Simulate ``frames`` frames (None: until ``on_frame`` raises StopRun); ``on_frame(sim, i)``
    runs after each (e.g. draw and encode). If it returns True, the state was changed by hand
    (a reset, a kick, a new gravity) and the blow-up check measures energy from there on.

    Without ``on_frame`` the frames run in chunks, one launch each (``Simulator.advance_frames``):
    the host reads a chunk's rows at once and checks them for a blow-up, so a frame costs the
    host nothing. A chunk is sized to take ~CHUNK_SECONDS, so Ctrl-C (honoured between chunks,
    with every frame simulated so far kept) is never kept waiting. Chunking never changes the
    numbers: a chunk runs the same substeps, in the same order, as frame-by-frame calls."""
    cfg = sim.config
    m = sim.model  # mass (B,), inertia_body (B, 3, 3); the NPZ of one body drops the body axis
    trajectory = Trajectory(m.body_mass_np, m.inertia_body_np, cfg.dt, sim.substeps, cfg.fp64)
    with ctrl_c_stops_at_once():  # until the first frame is done, Ctrl-C ends the run at once (compile_guard)
        start = sim.current_block()
    trajectory.append_block(start)
    e0, bound = _baseline(sim, start)
    result = RunResult(0, "done")
    last = row_of(start, 0)
    chunk = _ChunkSize(sim.rows.capacity if on_frame is None else 1)
    eta = TimeLeft(frames) if on_frame is None and frames is not None else None
    bar = FrameBar(frames, "simulating") if eta is not None else None  # after the first chunk (compiling)
    try:
        with _sigint_between_chunks(on_frame is None) as interrupted:
            if on_frame is not None:
                with ctrl_c_stops_at_once():  # drawing's kernels compile in frame 0
                    if on_frame(sim, 0):
                        e0, bound = _baseline(sim, sim.current_block())
            while frames is None or result.frames < frames:
                if interrupted():
                    raise KeyboardInterrupt
                size = chunk.next(None if frames is None else frames - result.frames)
                began = time.perf_counter()
                with ctrl_c_stops_at_once() if result.frames == 0 else contextlib.nullcontext():
                    block = sim.advance_frames(size)  # the first compiles the substep's kernels
                chunk.took(time.perf_counter() - began)
                if eta is not None:  # one line on stderr once the run looks long: its time left
                    eta.chunk_done(result.frames + size, size, time.perf_counter() - began)
                    bar.update(result.frames + size)
                bad = first_blow_up(block, e0, bound)
                escape = first_escape(block, cfg, last)  # a body through a wall: its energy does not show it
                if escape is not None and (bad is None or escape[0] <= bad[0]):
                    bad = escape
                if bad is not None:
                    index, problem = bad[:2]
                    if export_path:
                        trajectory.append_block(block, index)
                    first = result.frames + index + 1
                    last = row_of(block, index - 1) if index else last
                    result = RunResult(first - 1, "blew-up",
                                       f"blow-up at t = {block['t'][index]:.4g} s (frame {first}): {problem}; "
                                       f"{bad[2] if len(bad) > 2 else stability_hint(cfg)}")
                    break
                if export_path:  # rows are kept only for an export: a window left open stays in constant memory
                    trajectory.append_block(block)
                result.frames += size
                last = row_of(block, size - 1)
                if on_frame is not None and on_frame(sim, result.frames):
                    e0, bound = _baseline(sim, sim.current_block())
    except StopRun:
        pass
    except KeyboardInterrupt:
        result = RunResult(result.frames, "interrupted", f"interrupted after {result.frames} frames")
    finally:
        if bar is not None:
            bar.close()
    if export_path:  # one path or a list (--export given several times); the suffix picks the format
        write_exports(export_path, trajectory, sim)
    result.last_row = last
    return result


def row_of(block: dict, index: int) -> dict:
    """Row ``index`` of a block, as ``Simulator.snapshot`` gives it."""
    row = {key: value[index] for key, value in block.items()}
    row["t"] = float(row["t"])
    return row


CHUNK_SECONDS = 0.05


class _ChunkSize:
    """Frames per launch: doubles from 1 while a launch takes under CHUNK_SECONDS, halves above
    it, never over the row buffer's capacity (so long, heavy frames run one per launch)."""

    def __init__(self, capacity: int):
        self.capacity, self.size = capacity, 1

    def next(self, remaining: int | None) -> int:
        return self.size if remaining is None else min(self.size, remaining)

    def took(self, seconds: float) -> None:
        if seconds < CHUNK_SECONDS / 2:
            self.size = min(self.capacity, self.size * 2)
        elif seconds > 2 * CHUNK_SECONDS:
            self.size = max(1, self.size // 2)


@contextlib.contextmanager
def _sigint_between_chunks(active: bool):
    """While a headless run is chunked, the first Ctrl-C is noted and acted on between chunks
    (a KeyboardInterrupt raised inside a launch would lose the chunk's rows); a second one
    interrupts at once. Yields ``interrupted()``."""
    if not active or threading.current_thread() is not threading.main_thread():
        yield lambda: False
        return
    seen = []

    def note(signum, frame):
        seen.append(signum)
        signal.signal(signal.SIGINT, previous)  # the next Ctrl-C is a plain KeyboardInterrupt

    previous = signal.signal(signal.SIGINT, note)
    try:
        yield lambda: bool(seen)
    finally:
        signal.signal(signal.SIGINT, previous)


def _baseline(sim, block: dict) -> tuple[float, float]:
    return baseline(block, sim.model.mass, sim.params.gravity)


def baseline(block: dict, mass: float, gravity) -> tuple[float, float]:
    """Initial energy and blow-up bound, measured from a block of one row (the current state) of
    bodies of total ``mass`` (rigid.sweeps.batch: one world's)."""
    kinetic = float(block["kinetic_energy"][0])
    return kinetic + float(block["potential_energy"][0]), energy_bound(mass, gravity, kinetic)
