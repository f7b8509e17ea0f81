"""Before/after speed of two checkouts of this project, interleaved (a shared machine is noisy).

    python scripts/bench_versions.py OLD_TREE NEW_TREE [--rounds 3] [--only sphere,pile125]
    (the logic: this module)

Each round runs every workload once in each tree, in a fresh process of that tree's code (warm
kernel cache: compile time is the cold-start benchmark's business, scripts/bench_build.py), and
prints the medians of µs a substep and their ratio new / old. Workloads: the assignment's sphere
alone (42 particles), the bouncing torus (4,096 vertices, a lone big mesh), and the peers' piles
of 125 and 1,000 icospheres (rigid.bench.peers, sleeping off) in contact.
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

WORKER = r'''
import json, sys, time
import rigid
from rigid.engine.units import default_units
import taichi as ti
rigid.init("cpu")
units = default_units()
name = sys.argv[1]
if name.startswith("pile"):
    from rigid.bench.peers import scene, run_engine
    config, bodies = scene(int(name[4:]))
    seconds = 2.0 if int(name[4:]) <= 125 else 0.5
    print(json.dumps(run_engine(units, config, bodies, seconds, sleep=False)["us_per_substep"]))
else:
    from rigid.config import SimConfig, load_scene
    from rigid.engine.simulator import Simulator
    scene_file = {"sphere": "assignment", "torus": "bouncing_torus"}[name]
    sim = Simulator(SimConfig(**load_scene(f"assets/scenes/{scene_file}.toml")).validate(), units)
    sim.advance_frames(1)
    sim.reset()
    frames = 300
    start = time.perf_counter()
    sim.advance_frames(frames)
    ti.sync()
    print(json.dumps((time.perf_counter() - start) / (frames * sim.substeps) * 1e6))
'''
WORKLOADS = ("sphere", "torus", "pile125", "pile1000")


def measure(tree: Path, name: str) -> float:
    proc = subprocess.run([sys.executable, "-c", WORKER, name], cwd=tree, capture_output=True, text=True,
                          env={**__import__("os").environ, "PYTHONPATH": str(tree)}, timeout=1800)
    if proc.returncode != 0:
        raise SystemExit(f"{tree} {name} failed: {proc.stderr[-2000:]}")
    return float(json.loads(proc.stdout.strip().splitlines()[-1]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old", type=Path)
    parser.add_argument("new", type=Path)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--only", default=",".join(WORKLOADS))
    args = parser.parse_args()
    names = [n for n in args.only.split(",") if n]
    unknown = sorted(set(names) - set(WORKLOADS))
    if unknown:
        raise SystemExit(f"--only {unknown[0]}: not a workload; use some of {', '.join(WORKLOADS)}")
    times = {(tree, n): [] for tree in ("old", "new") for n in names}
    for r in range(args.rounds):
        for n in names:
            for label, tree in (("old", args.old), ("new", args.new)):
                times[(label, n)].append(measure(tree.resolve(), n))
                print(f"round {r + 1} {n} {label}: {times[(label, n)][-1]:.2f} µs a substep", flush=True)
    print("\n| workload | old µs/substep | new µs/substep | new / old |\n|---|---|---|---|")
    for n in names:
        old, new = statistics.median(times[("old", n)]), statistics.median(times[("new", n)])
        print(f"| {n} | {old:.2f} | {new:.2f} | {new / old:.3f} |")


if __name__ == "__main__":
    main()
