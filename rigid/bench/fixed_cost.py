"""A small scene's fixed cost per substep: what a substep costs beyond its particles.

Piles of 2 to 27 of the peers' icospheres (rigid.bench.peers.scene, scale 0.15, 42 particles a
body, sleeping off so that every body is integrated) run their first 2 s in chunks of frames, as
the command line runs them; the cost per substep against the particle count is fitted by a
line, whose intercept is the fixed cost (the motion test, the launch's share, the body loops)
and whose slope the cost per particle. Times are reported, never asserted.
"""
from __future__ import annotations

import statistics
import time

import numpy as np

COUNTS = (2, 4, 8, 16, 27)
SECONDS = 2.0


def fixed_cost(units, quick: bool = False) -> dict:
    import taichi as ti

    from rigid.engine.simulator import Simulator

    from .peers import scene

    counts, repeats = ((2, 4), 1) if quick else (COUNTS, 5)
    frames = 6 if quick else round(SECONDS * 60)
    rows = []
    for count in counts:
        config, bodies = scene(count, scale=0.15)
        sim = Simulator(config.replace(sleep=False), units, bodies=bodies)
        sim.advance_frames(1)  # compile (or load) the kernels
        times = []
        for _ in range(repeats):
            sim.reset()
            start = time.perf_counter()
            sim.advance_frames(frames)
            ti.sync()
            times.append((time.perf_counter() - start) / (frames * sim.substeps) * 1e6)
        rows.append(dict(bodies=count, particles=sim.num_particles, schedule=sim.schedule,
                         us_per_substep=round(statistics.median(times), 2)))
    n = np.array([r["particles"] for r in rows], float)
    us = np.array([r["us_per_substep"] for r in rows], float)
    slope, intercept = np.polyfit(n, us, 1)
    return dict(seconds=frames / 60, repeats=repeats, rows=rows, fixed_us_per_substep=round(float(intercept), 2),
                ns_per_particle=round(float(slope) * 1e3, 2))


def markdown(r: dict) -> list[str]:
    lines = ["## A small scene's fixed cost per substep", "",
             f"Piles of the peers' icospheres (42 particles a body, sleeping off), their first {r['seconds']:g} s in "
             f"chunks of frames as the command line runs them, median of {r['repeats']}; a line fitted to µs a "
             f"substep against particles: **{r['fixed_us_per_substep']} µs fixed** + {r['ns_per_particle']} ns a "
             "particle (rigid/bench/fixed_cost.py)" + _load(r) + ".", "",
             "| bodies | particles | schedule | µs/substep |", "|---|---|---|---|"]
    lines += [f"| {x['bodies']} | {x['particles']:,} | {x['schedule']} | {x['us_per_substep']} |" for x in r["rows"]]
    return lines + [""]


def _load(r: dict) -> str:
    """The load where this part ran alone (``--only fixed``), apart from the whole run's."""
    load = (r.get("machine") or {}).get("loadavg_1_5_15")
    return f"; run alone, load average {load} at its start" if load else ""
