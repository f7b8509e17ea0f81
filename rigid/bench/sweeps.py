"""Benchmark ``python -m rigid sweep``: a sweep of many runs against single command-line runs, and
Ray's local cluster against the local pool (scripts/bench_sweep.py; report/bench_sweep.json).

- single: ``python -m rigid --scene SCENE --headless --frames F`` in a fresh process (Taichi's
  start, the kernels from the disk cache, the run), median of ``--repeats``
- pool:   ``python -m rigid sweep SCENE --vary ... --frames F --workers W`` of ``--runs`` runs
  (friction_stiffness x initial_velocity.x), a fresh output folder each time
- ray:    the same sweep with ``--ray local`` (starting and stopping the local cluster included)
- per run: the median of index.csv's wall_seconds in the pool's sweeps (a Simulator built and run
  in a warm worker; a worker's first run, which starts Taichi, included)
- worlds: the same number of runs varying only the throw (initial_velocity.x x
  initial_angular_velocity.y), which the sweep runs as worlds of one Simulator per worker
  (rigid.sweeps.batch)
- worlds_scaling: in one warm process, ``Simulator(scene, worlds=W).advance(F)`` for W = 1 and
  ``--worlds`` (seconds, median of ``--repeats``)

Every command runs once untimed first (the kernel cache, the file cache). The benchmark's
processes compile with the default optimisations (RIGID_QUICK_COMPILE unset), as users run.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "assets" / "scenes" / "thrown_sphere.toml"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--runs", type=int, default=64, help="runs in the sweep (a square: N x N values)")
    p.add_argument("--frames", type=int, default=60)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--workers", type=int, default=len(os.sched_getaffinity(0)))
    p.add_argument("--no-ray", action="store_true", help="skip the Ray measurement")
    p.add_argument("--worlds", type=int, default=1000, help="worlds stepped together in worlds_scaling")
    p.add_argument("--out", default=str(ROOT / "report" / "bench_sweep.json"))
    args = p.parse_args(argv)
    side = math.isqrt(args.runs)
    if side * side != args.runs:
        p.error("--runs must be a square (the sweep varies two keys with N values each)")
    env = {k: v for k, v in os.environ.items() if k != "RIGID_QUICK_COMPILE"}
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [env.get("PYTHONPATH")])])
    vary = ["--vary", f"friction_stiffness=0.05:0.4:{side}", "--vary", f"initial_velocity.x=1:4:{side}"]
    single = [sys.executable, "-m", "rigid", "--scene", str(SCENE), "--headless", "--frames", str(args.frames)]
    ray_ok = not args.no_ray and _has_ray()
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        def sweep(tag: str, i: int, *extra: str, varies=vary) -> list[str]:
            return [sys.executable, "-m", "rigid", "sweep", str(SCENE), *varies, "--frames", str(args.frames),
                    "--out", str(Path(tmp) / f"{tag}{i}"), "--workers", str(args.workers), *extra]

        throws = ["--vary", f"initial_velocity.x=1:4:{side}", "--vary", f"initial_angular_velocity.y=0:4:{side}"]
        results = dict(single=_timed(lambda i: single, args.repeats, env),
                       pool=_timed(lambda i: sweep("pool", i), args.repeats, env),
                       worlds=_timed(lambda i: sweep("worlds", i, varies=throws), args.repeats, env))
        per_run = [float(r["wall_seconds"]) for i in range(1, args.repeats + 1)
                   for r in csv.DictReader((Path(tmp) / f"pool{i}" / "index.csv").read_text().splitlines())]
        if ray_ok:
            results["ray"] = _timed(lambda i: sweep("ray", i, "--ray", "local"), args.repeats, env)
    out = dict(scene=str(SCENE.relative_to(ROOT)), frames=args.frames, runs=args.runs, workers=args.workers,
               repeats=args.repeats, **{f"{k}_s": v for k, v in results.items()},
               per_run_median_s=round(statistics.median(per_run), 3))
    out["worlds_scaling"] = _worlds_scaling(args.worlds, args.frames, args.repeats, env)
    one = out["single_s"]["median"]
    out["worlds_sweep_over_eight_singles"] = round(out["worlds_s"]["median"] / (8 * one), 3)
    out["eight_singles_s"] = round(8 * one, 2)
    out["sweep_over_eight_singles"] = round(out["pool_s"]["median"] / (8 * one), 3)
    if ray_ok:
        out["ray_overhead_s"] = round(out["ray_s"]["median"] - out["pool_s"]["median"], 2)
    out["machine"] = dict(cpus=os.cpu_count(), platform=platform.platform(), python=platform.python_version(),
                          load_average_1min_before=load_before, load_average_1min_after=os.getloadavg()[0],
                          ray=_ray_version() if ray_ok else None)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(out, indent=2) + "\n")
    print(markdown(out))
    print(f"wrote {args.out}")
    return 0


def _timed(command, repeats: int, env: dict) -> dict:
    """Wall seconds of ``command(i)`` for i = 1..repeats after an untimed i = 0: median and all."""
    times = []
    for i in range(repeats + 1):
        began = time.perf_counter()
        proc = subprocess.run(command(i), cwd=ROOT, env=env, capture_output=True, text=True)
        if proc.returncode != 0:
            raise SystemExit(f"bench_sweep: {' '.join(command(i))} failed:\n{proc.stderr[-2000:]}")
        if i:
            times.append(round(time.perf_counter() - began, 2))
    return dict(median=statistics.median(times), all=times)


_SCALING = """
import statistics, sys, time
import rigid
from rigid.engine.simulator import Simulator
rigid.init("cpu")
scene = rigid.load_scene(sys.argv[1])
frames, repeats, out = int(sys.argv[3]), int(sys.argv[4]), {}
for worlds in (1, int(sys.argv[2])):
    Simulator(scene, worlds=worlds).advance(2)  # compiled and warm
    times = []
    for _ in range(repeats):
        sim = Simulator(scene, worlds=worlds)
        began = time.perf_counter()
        sim.advance(frames)
        times.append(time.perf_counter() - began)
    out[worlds] = statistics.median(times)
print(out[1], out[int(sys.argv[2])])
"""


def _worlds_scaling(worlds: int, frames: int, repeats: int, env: dict) -> dict:
    """Seconds for ``frames`` frames of one world and of ``worlds`` (a fresh process, warm kernels)."""
    proc = subprocess.run([sys.executable, "-c", _SCALING, str(SCENE), str(worlds), str(frames), str(repeats)],
                          cwd=ROOT, env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"bench_sweep: worlds scaling failed:\n{proc.stderr[-2000:]}")
    one, many = (float(v) for v in proc.stdout.split()[-2:])
    return dict(worlds=worlds, one_world_s=round(one, 4), many_worlds_s=round(many, 4), ratio=round(many / one, 2))


def _has_ray() -> bool:
    return subprocess.run([sys.executable, "-c", "import ray"], capture_output=True).returncode == 0


def _ray_version() -> str:
    return subprocess.run([sys.executable, "-c", "import ray; print(ray.__version__)"], capture_output=True,
                          text=True).stdout.strip()


def markdown(d: dict) -> str:
    """report/bench_sweep.json as a table (the docs' hook and the script's output)."""
    rows = [("one command-line run (`--headless`)", d["single_s"]["median"]),
            ("8 command-line runs (8 x the median)", d["eight_singles_s"]),
            (f"a sweep of {d['runs']} runs, local pool ({d['workers']} workers)", d["pool_s"]["median"])]
    if "worlds_s" in d:
        rows.append((f"a sweep of {d['runs']} throws, run as worlds ({d['workers']} workers)", d["worlds_s"]["median"]))
    if "ray_s" in d:
        rows.append((f"the same sweep, `--ray local` ({d['workers']} CPUs)", d["ray_s"]["median"]))
    lines = [f"`{d['scene']}`, {d['frames']} frames a run; wall seconds, medians of {d['repeats']}.", "",
             "| what | seconds |", "|---|---|", *(f"| {what} | {s} |" for what, s in rows), "",
             f"The sweep costs {d['sweep_over_eight_singles']:.2f} x eight single runs "
             f"({d['runs']} single runs would cost {d['runs'] / 8:.0f} x as much); a run inside a warm worker "
             f"takes {d['per_run_median_s']} s (median)."]
    if "worlds_scaling" in d:
        w = d["worlds_scaling"]
        lines.append(f"The sweep of throws, as worlds, costs {d['worlds_sweep_over_eight_singles']:.2f} x eight single "
                     f"runs. In one process, {w['worlds']} worlds of the scene take {w['many_worlds_s']} s for "
                     f"{d['frames']} frames, {w['ratio']} x one world's {w['one_world_s']} s.")
    if "ray_overhead_s" in d:
        lines.append(f"Ray's local cluster adds {d['ray_overhead_s']} s to the sweep (its start and stop included).")
    return "\n".join(lines) + "\n"
