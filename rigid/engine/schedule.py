"""Serial or parallel: the one place that decides how a scene's substeps run.

Both schedules run the same stages with sums in the same fixed order (kernels.py); they
differ in who runs them:
- serial: one thread runs a whole chunk of frames in one launch. No thread wakes up, no
  host work per substep: the better choice on a CPU unless a substep has a lot of work.
- parallel: every stage of a substep is a parallel loop, one launch per substep. Waking
  the worker threads costs 15-70 µs per loop on this project's 2-vCPU machine, and a launch
  from Python ~0.1-0.5 ms, so a substep must carry far more work than that to gain.

Taichi 1.7's CPU thread pool also leaves small parallel loops to one thread: measured per
thread (/proc), a 64-iteration range-for (block_dim 1, ~30 ms an iteration) ran entirely on one
worker, a 1,024-iteration one split evenly. So a parallel substep's loops over a small scene's
bodies and blocks run on one thread after paying the wake-up, and threads of a kernel cannot
be made to wait for each other (a "team" schedule with barriers between stages deadlocked).

Work per particle and substep on the 2-vCPU machine: ~1-3 ns for a body against the walls,
100-250 ns for particles in contact with other bodies (the pair search). The thresholds are
the break-evens for two threads measured with the engine's earlier paths (``scripts/bench.py``'s
crossover, ``scripts/bench_many.py``), kept for this pipeline (not re-measured: its per-launch
and per-task costs are about the same), and assumed to fall as 1/threads with more. A GPU always runs parallel (one
GPU thread would run the whole scene).
"""
from __future__ import annotations

import os

import taichi as ti

# Particles from which two CPU threads beat one (see the module docstring).
PARALLEL_MIN_PARTICLES_ALONE = 1 << 20  # bodies that touch only the static colliders
PARALLEL_MIN_PARTICLES_PAIRS = 16384  # bodies that collide with one another
SCHEDULE_ENV = "RIGID_SCHEDULE"  # "serial" or "parallel" forces one (benchmarks, tests)


def choose_schedule(num_particles: int, pairs: bool, forced: str | None = None) -> str:
    """"serial" or "parallel" for a scene of ``num_particles`` on the current Taichi arch.
    ``forced`` (or the RIGID_SCHEDULE environment variable) overrides the choice."""
    forced = forced or os.environ.get(SCHEDULE_ENV) or None
    if forced is not None:
        if forced not in ("serial", "parallel"):
            raise ValueError(f"schedule = {forced!r}: use 'serial' or 'parallel'")
        return forced
    cfg = ti.lang.impl.current_cfg()
    if cfg.arch not in (ti.x64, ti.arm64):
        return "parallel"
    threads = cfg.cpu_max_num_threads
    if threads < 2:
        return "serial"
    base = PARALLEL_MIN_PARTICLES_PAIRS if pairs else PARALLEL_MIN_PARTICLES_ALONE
    return "parallel" if num_particles >= base * 2 // threads else "serial"
