"""How long a Simulator takes to build and run its first frame, in one process (#19).

Every Simulator of a process shares the engine's kernels (rigid.engine.kernels), so only
the first pays for compiling them (or for loading them from Taichi's disk cache); later
ones, of other scenes and sizes, only allocate their arrays. Measured here, in a child
process per run so that "first" is really first: the assignment's sphere, then the torus,
a 27-body pile and the sphere again, each built and stepped one frame. Times are wall
seconds of whole steps; reported, never asserted (the machine is shared).
"""
from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENES = (("assignment sphere", {}),
          ("torus (4096 vertices)", dict(mesh="torus.obj", scale=0.5, position=(0.0, 0.0, 0.0))),
          ("27 spheres", dict(count=27, scale=0.15, position=(0.0, -0.8, 0.0), integrator="symplectic",
                              particle_mass=0.01, velocity_damping_stiffness=12.0)),
          ("assignment sphere again", {}))


def child() -> None:
    """Runs in the child: prints one JSON line per scene."""
    import rigid

    rigid.init("cpu")
    for name, keys in SCENES:
        began = time.perf_counter()
        sim = rigid.Simulator(rigid.scene(**keys))
        built = time.perf_counter()
        sim.step_frame()
        sim.snapshot()
        done = time.perf_counter()
        print(json.dumps(dict(scene=name, build_s=round(built - began, 4), first_frame_s=round(done - built, 4),
                              total_s=round(done - began, 4))), flush=True)


def run(out: Path, repeats: int = 3) -> dict:
    """``repeats`` child processes (warm disk cache after the first); medians per scene."""
    import statistics

    runs = []
    for _ in range(repeats):
        proc = subprocess.run([sys.executable, "-c", "from rigid.bench.build import child; child()"],
                              cwd=ROOT, capture_output=True, text=True, timeout=900)
        if proc.returncode:
            raise RuntimeError(proc.stderr[-2000:])
        runs.append([json.loads(line) for line in proc.stdout.splitlines() if line.startswith("{")])
    rows = []
    for i, (name, _keys) in enumerate(SCENES):
        rows.append(dict(scene=name, **{key: statistics.median(r[i][key] for r in runs)
                                        for key in ("build_s", "first_frame_s", "total_s")}))
    result = dict(repeats=repeats, rows=rows, runs=runs)
    out.mkdir(parents=True, exist_ok=True)
    (out / "bench_build.json").write_text(json.dumps(result, indent=1) + "\n")
    lines = ["# Build and first frame, one process (scripts/bench_build.py)", "",
             f"Medians of {repeats} processes (the first may compile into an empty disk cache), wall seconds.", "",
             "| scene, in build order | build | first frame | total |", "|---|---|---|---|"]
    lines += [f"| {r['scene']} | {r['build_s']:.3f} | {r['first_frame_s']:.3f} | {r['total_s']:.3f} |" for r in rows]
    (out / "bench_build.md").write_text("\n".join(lines) + "\n")
    return result
