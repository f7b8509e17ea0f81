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
worker, a 1,024-iteration one split evenly. Measured again as CPU time over wall time (2 cores):
96 to 512 iterations kept one thread busy, 768 kept 1.45, 1,024 kept 1.96, whatever
``loop_config(block_dim=...)`` said: the loop is handed out about 512 iterations at a time. So a parallel substep's loops over a small scene's
bodies and blocks run on one thread after paying the wake-up, and threads of a kernel cannot
be made to wait for each other (a "team" schedule with barriers between stages deadlocked).

Bodies in contact, re-measured with this pipeline and its neighbour lists (piles of 42-vertex
spheres falling into the box, symplectic, sleeping off, 30 frames after 5, wall µs a substep on
the 2-vCPU machine, two runs each): 16,800 particles serial 1,093 / parallel 1,595; 29,400:
1,895-2,144 / 2,136-2,246; 42,000: 2,985-3,024 / 2,811-3,151; 84,000: 7,276-7,511 /
5,806-7,473. Re-measured with Taichi's workers pinned one to a core (threads.py: unpinned,
both often ran on one vCPU) and the parallel pair stage as the sweep in parts (pair_parts.py),
in contact at 1 s, µs a substep serial / parallel, one process each, medians of 3: the peers'
piles (0.42 kg spheres) 5,250 particles 131 / 642, 16,800 624 / 971, 29,400 1,224 / 1,374,
42,000 1,787 / 1,718; the handout's 1 kg particles (`--count N --scale 0.07`, spheres that
sink into one another, more pairs a particle) 16,800 1,223 / 1,902, 29,400 3,758 / 3,227,
42,000 6,653 / 5,426. A parallel substep pays a round trip through the thread pool for every
top-level loop, an empty one too (~30 µs): ~0.5 ms for its ~25 loops, ~0.3 ms since a substep
that does not rebuild the lists skips the rebuild's (split_substep.py; the peers' 125 pile 642 →
427 µs, 16,800 971 → 893, 29,400 1,374 → 1,254, serial 1,212; the 1 kg 29,400 3,281 against
3,651). So the break-even is ~30k particles: 2¹⁵. Bodies against the walls alone: ~1-3 ns a particle, break-even 2²⁰ (the earlier
paths' ``scripts/bench.py`` crossover, not re-measured). Both are assumed to fall as 1/threads
with more threads. A GPU always runs parallel (one GPU thread would run the whole scene).
"""
from __future__ import annotations

import os

import taichi as ti

# Particles from which two CPU threads beat one (see the module docstring).
PARALLEL_MIN_PARTICLES_ALONE = 1 << 20  # bodies that touch only the static colliders
PARALLEL_MIN_PARTICLES_PAIRS = 1 << 15  # bodies that collide with one another (2¹⁶ before the workers were pinned)
SCHEDULE_ENV = "RIGID_SCHEDULE"  # "serial" or "parallel" forces one (benchmarks, tests)


def check_schedule(name: str) -> str:
    """``name`` if it is a schedule's, else a ValueError naming both."""
    if name not in ("serial", "parallel"):
        raise ValueError(f"schedule = {name!r}: use 'serial' or 'parallel'")
    return name


def on_cpu() -> bool:
    """Whether Taichi runs on a CPU (after ti.init). The stages compiled for another device differ
    in a few places (pair_parts.parts_here, refresh.settle, motion.note_motion_spread,
    kernels.finish_frame), each through this one switch."""
    return ti.lang.impl.current_cfg().arch in (ti.x64, ti.arm64)


def choose_schedule(num_particles: int, pairs: bool, forced: str | None = None) -> str:
    """"serial" or "parallel" for a scene of ``num_particles`` on the current Taichi arch.
    ``forced`` (or the RIGID_SCHEDULE environment variable) overrides the choice."""
    forced = forced or os.environ.get(SCHEDULE_ENV) or None
    if forced is not None:
        return check_schedule(forced)
    if not on_cpu():
        return "parallel"
    threads = ti.lang.impl.current_cfg().cpu_max_num_threads
    if threads < 2:
        return "serial"
    base = PARALLEL_MIN_PARTICLES_PAIRS if pairs else PARALLEL_MIN_PARTICLES_ALONE
    return "parallel" if num_particles >= base * 2 // threads else "serial"
