"""What a settled pile costs with sleeping, against the same pile falling.

The benchmark's 125-sphere pile (rigid.bench.peers.scene) runs in chunks of 30 frames until
every body sleeps (at most ``max_seconds``); the cost per substep of the first second (falling)
is set against the cost once all sleep (the next ``settled_frames`` frames), and against the
same settled state with sleeping off (every body woken and kept awake: what a settled pile cost
before). Times are reported, never asserted.
"""
from __future__ import annotations

import time


def _chunk(sim, frames: int) -> float:
    import taichi as ti
    start = time.perf_counter()
    sim.advance_frames(frames)
    ti.sync()
    return (time.perf_counter() - start) / (frames * sim.substeps) * 1e6


def settled_cost(units, count: int = 125, max_seconds: float = 20.0, settled_frames: int = 60) -> dict:
    from rigid.engine.simulator import Simulator

    from .peers import scene

    config, bodies = scene(count)
    sim = Simulator(config, units, bodies=bodies)
    sim.advance_frames(1)
    sim.reset()
    falling = _chunk(sim, 60)
    while not sim.asleep().all() and sim.time < max_seconds:
        sim.advance_frames(30)
    slept_at = round(sim.time, 2)
    all_asleep = bool(sim.asleep().all())
    settled = _chunk(sim, settled_frames)
    sim.params.sleep = False  # a parameter change: every body wakes, and none sleeps again
    awake = _chunk(sim, settled_frames)
    return dict(bodies=count, falling_us_per_substep=round(falling, 1), all_asleep=all_asleep,
                all_asleep_at_s=slept_at, settled_us_per_substep=round(settled, 1),
                settled_sleep_off_us_per_substep=round(awake, 1),
                settled_over_falling=round(settled / falling, 3))


def markdown(r: dict) -> list[str]:
    return ["## Sleeping: a settled pile against a falling one", "",
            f"{r['bodies']} spheres (the peers' scene): falling (first second) {r['falling_us_per_substep']:,} µs a "
            f"substep; every body asleep at {r['all_asleep_at_s']} s" + ("" if r["all_asleep"] else " (not all: cut off)") +
            f"; then {r['settled_us_per_substep']:,} µs a substep = **{100 * r['settled_over_falling']:.0f} % of "
            f"falling**; the same settled pile with sleeping off: {r['settled_sleep_off_us_per_substep']:,} µs.", ""]
