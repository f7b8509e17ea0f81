"""Speed per substep: the handout's loop, this engine, MuJoCo; start-up; memory; the crossover.

    python scripts/bench.py              # the full table (~1-2 minutes on 2 cores)
    python scripts/bench.py --quick      # a smoke test: small runs, no subprocesses (~12 s)

In one process, one after another, for each body: the handout-style loop
(scripts/bench_handout.py: one launch per substep from Python, parallel loops,
the same units and contact), this engine (rigid.Simulator: one launch per frame)
and MuJoCo (scripts/bench_mujoco.py) if installed. Bodies: the 42-vertex sphere
(assets/sphere.obj, scale 0.3), the 4096-vertex torus (assets/torus.obj, scale
0.5), both thrown into the box for 2 s; and a 0.5 m cube volume-sampled by
rigid.bodies.sampling (--particles volume --grid 100: 1,000,000 particles), timed in
flight and resting on the floor. Δt = 1e-3, 16 substeps per frame, CPU, float32.
Times: median over repeats of (wall time of whole frames) / substeps. Also:
the command line's own figure, whole processes, long minus short runs, with and
without --export (rigid.bench.command_line); start-up from command to first frame
(python rigid_body_dynamic.py --headless --frames 1) with an empty and a warm kernel cache, peak memory of a process
running the 1M body, and serial vs parallel path by particle count (the
crossover behind rigid.engine.schedule).
Writes report/bench.json and report/bench.md (--out DIR to change). Speeds are
reported, never asserted: the machine is shared and timings are noisy.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the repository

from rigid.bench import table as bench_table

SCENARIO = dict(position=(0.0, 0.0, 0.0), initial_velocity=(1.0, 0.0, 0.6),
                initial_angular_velocity=(1.0, 2.0, 0.5))
CUBE_HALF = 0.25  # the volume-sampled cube: assets/box.obj (side 1) at scale 0.5


def body_cases(quick: bool) -> list[dict]:
    """Bodies, scenarios and run lengths (frames per repeat, repeats)."""
    sphere = dict(name="sphere (42 vertices)", mesh="sphere.obj", scale=0.3, **SCENARIO)
    torus = dict(name="torus (4096 vertices)", mesh="torus.obj", scale=0.5, **SCENARIO)
    grid = 34 if quick else 100  # 34³ = 39,304 particles: still takes the parallel path
    cube = dict(mesh="box.obj", scale=0.5, particles="volume", grid=grid, box_half=CUBE_HALF)
    on_floor = (0.0, -1.0 + CUBE_HALF - 0.005, 0.0)  # resting, bottom layer 5 mm deep
    big = f"cube ({grid ** 3:,} particles)"
    frames, big_frames, repeats = (5, 2, 1) if quick else (120, 8, 5)
    return [dict(sphere, frames=frames, repeats=repeats), dict(torus, frames=frames, repeats=repeats),
            dict(cube, name=big + ", in flight", **SCENARIO, frames=big_frames, repeats=max(1, repeats - 2)),
            dict(cube, name=big + ", on the floor", position=on_floor, frames=big_frames,
                 repeats=max(1, repeats - 2))]


def time_frames(runner, frames: int, repeats: int, substeps: int, sync) -> float:
    """Median over repeats of the wall time per substep (µs), after one untimed frame."""
    runner.reset()
    runner.step_frame(substeps)  # compiles
    sync()
    times = []
    for _ in range(repeats):
        runner.reset()
        sync()
        start = time.perf_counter()
        for _ in range(frames):
            runner.step_frame(substeps)
        sync()
        times.append((time.perf_counter() - start) / (frames * substeps) * 1e6)
    return statistics.median(times)


class EngineRunner:
    def __init__(self, sim):
        self.sim = sim

    def reset(self):
        self.sim.reset()

    def step_frame(self, substeps):
        self.sim.step_frame(substeps)

    def position(self):
        return self.sim.snapshot()["x"]


def config_for(case):
    from rigid.config import ASSETS, SimConfig

    keys = ("scale", "position", "initial_velocity", "initial_angular_velocity", "particles", "grid")
    return SimConfig(mesh=str(ASSETS / case["mesh"]), **{k: case[k] for k in keys if k in case}).validate()


_BUILT = {}  # (mesh, scale, particles, grid) -> the three implementations, reused across scenarios


def implementations(case, config, units, ti, row) -> tuple:
    """(baseline, engine, MuJoCo or None) for the case's body, built once, set to the case's config."""
    from rigid.bench import handout as bench_handout
    from rigid.bench import mujoco as bench_mujoco
    from rigid.bodies.mesh import body_geometry
    from rigid.engine.simulator import Simulator

    key = tuple(case.get(k) for k in ("mesh", "scale", "particles", "grid"))
    if key not in _BUILT:
        geometry = body_geometry(config)
        r0 = geometry.particles - geometry.particles.mean(axis=0)
        baseline = bench_handout.HandoutLoop(r0, config.particle_mass, units, config)
        start = time.perf_counter()
        sim = Simulator(config, units, geometry)
        sim.step_frame()
        ti.sync()
        row["engine_build_and_first_frame_s"] = round(time.perf_counter() - start, 3)
        mj = None
        if bench_mujoco.available():
            if "box_half" in case:
                mj = bench_mujoco.MujocoBox(config, sim.model.mass, box_half=case["box_half"])
            else:
                mj = bench_mujoco.MujocoBox(config, sim.model.mass, geometry.vertices, geometry.faces)
        _BUILT[key] = (baseline, sim, mj)
    baseline, sim, mj = _BUILT[key]
    baseline.config = config
    sim.reconfigure(**{k: getattr(config, k) for k in ("position", "initial_velocity", "initial_angular_velocity")})
    if mj is not None:
        mj.config = config
    return baseline, sim, mj


def run_case(case, units, ti) -> dict:
    config = config_for(case)
    substeps, sync = config.substeps, ti.sync
    row = dict(body=case["name"], frames=case["frames"], repeats=case["repeats"], substeps_per_frame=substeps)
    baseline, sim, mj = implementations(case, config, units, ti, row)
    row["particles"] = sim.model.num_particles
    row["baseline_us"] = time_frames(baseline, case["frames"], case["repeats"], substeps, sync)
    row["baseline_final_x"] = baseline.position().round(4).tolist()
    row["engine_path"] = sim.schedule
    engine = EngineRunner(sim)
    row["engine_us"] = time_frames(engine, case["frames"], case["repeats"], substeps, sync)
    row["engine_final_x"] = engine.position().round(4).tolist()
    if mj is not None:
        row["mujoco_us"] = time_frames(mj, case["frames"], case["repeats"], substeps, lambda: None)
        row["mujoco_final_x"] = mj.position().round(4).tolist()
    row["load_average"] = round(os.getloadavg()[0], 2)
    print(bench_table.row_line(row), flush=True)
    return row


def crossover(units, ti, quick: bool) -> list[dict]:
    """Serial vs parallel path per substep for volume-sampled cubes of growing particle count."""
    from rigid.engine.simulator import Simulator

    grids = (20,) if quick else (16, 25, 40, 63, 80, 100)
    out = []
    for grid in grids:
        case = dict(mesh="box.obj", scale=0.5, particles="volume", grid=grid)
        # On the floor: its bottom layer of particles (half a cell inside the cube) on the floor
        # (a start below it is refused); in contact from the first substeps.
        on_floor = (0.0, -1.0 + CUBE_HALF * (1.0 - 1.0 / grid), 0.0)
        entry = {}
        for where, position in (("flight", SCENARIO["position"]), ("floor", on_floor)):
            # A new Simulator for each place (cheap: the kernels are compiled once).
            sim = Simulator(config_for(dict(case, **dict(SCENARIO, position=position))), units)
            entry["particles"] = sim.model.num_particles
            times = {"serial": [], "parallel": []}
            for _ in range(1 if quick else 5):  # alternate the paths, so that both see the same load
                for path in times:
                    sim.schedule = path
                    times[path].append(time_frames(EngineRunner(sim), 2 if quick else 6, 1, sim.substeps, ti.sync))
            for path, values in times.items():
                entry[f"{path}_{where}_us"] = statistics.median(values)
        entry["load_average"] = round(os.getloadavg()[0], 2)
        out.append(entry)
        print("crossover", json.dumps(entry), flush=True)
    return out


def startup(timeout: float = 300) -> dict:
    """Wall time of `rigid_body_dynamic.py --headless --frames 1`: empty kernel cache, then warm."""
    result = {}
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, TI_OFFLINE_CACHE_FILE_PATH=cache)
        for label in ("cold_cache_s", "warm_cache_s"):
            start = time.perf_counter()
            subprocess.run([sys.executable, str(ROOT / "rigid_body_dynamic.py"), "--headless", "--frames", "1"],
                           env=env, cwd=ROOT, check=True, capture_output=True, timeout=timeout)
            result[label] = round(time.perf_counter() - start, 2)
    return result


def peak_memory(grid: int) -> dict:
    """Peak RSS (MiB) of a process that builds a body and runs 4 frames: the sphere, then the cube."""
    out = {}
    for label, g in (("sphere", 0), ("cube", grid)):
        done = subprocess.run([sys.executable, "-m", "rigid.bench.speed", "--memory-child", str(g)], cwd=ROOT, check=True,
                              capture_output=True, text=True, timeout=600)
        child = json.loads(done.stdout.strip().splitlines()[-1])
        out[f"{label}_particles"] = child["particles"]
        out[f"{label}_peak_rss_mib"] = child["peak_rss_mib"]
    return out


def memory_child(grid: int) -> None:
    """Build the sphere (grid 0) or the cube volume-sampled at ``grid``, run 4 frames, print peak RSS."""
    from rigid.runtime import init_taichi
    from rigid.engine.simulator import Simulator
    from rigid.engine.units import load_units

    init_taichi("cpu", fp64=False)
    case = dict(mesh="sphere.obj", scale=0.3) if grid == 0 else \
        dict(mesh="box.obj", scale=0.5, particles="volume", grid=grid)
    sim = Simulator(config_for(dict(case, **SCENARIO)), load_units(ROOT / "rigid_body_dynamic.py"))
    for _ in range(4):
        sim.step_frame()
    sim.snapshot()
    peak_kib = next(int(line.split()[1]) for line in open("/proc/self/status") if line.startswith("VmHWM"))
    print(json.dumps({"peak_rss_mib": round(peak_kib / 1024, 1), "particles": sim.model.num_particles}))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="small runs, no subprocesses: a smoke test")
    p.add_argument("--out", default=str(ROOT / "report"), help="folder for bench.json and bench.md")
    p.add_argument("--memory-child", type=int, metavar="GRID", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.memory_child is not None:
        memory_child(args.memory_child)
        return 0
    import taichi as ti

    from rigid.bench import mujoco as bench_mujoco
    from rigid.runtime import init_taichi
    from rigid.engine.units import load_units

    init_taichi("cpu", fp64=False)
    units = load_units(ROOT / "rigid_body_dynamic.py")
    mujoco_version = bench_mujoco.available()
    result = dict(machine=machine(), quick=args.quick, taichi=ti.__version__, mujoco=mujoco_version,
                  scenario=dict(SCENARIO, dt=1e-3, substeps_per_frame=16, precision="float32"))
    if not mujoco_version:
        print("note: MuJoCo is not installed (pip install mujoco, or the extra '.[mujoco]'); "
              "its column is left empty", file=sys.stderr)
    print(bench_table.header_line(), flush=True)
    result["rows"] = [run_case(case, units, ti) for case in body_cases(args.quick)]
    result["crossover"] = crossover(units, ti, args.quick)
    if not args.quick:
        from rigid.bench import command_line

        result["command_line"] = command_line.measure(result["rows"])
        result["startup"] = startup()
        result["memory"] = peak_memory(100)
    result["table"] = bench_table.table(result["rows"])
    result["goals"] = bench_table.goals(result)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    bench_table.write(result, out / "bench.json", out / "bench.md")
    print(bench_table.markdown(result))
    return 0


def machine() -> str:
    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
               platform.processor() or "unknown CPU") if Path("/proc/cpuinfo").exists() else platform.processor()
    return f"{cpu}, {os.cpu_count()} cores, {platform.system()}, Python {platform.python_version()}"


if __name__ == "__main__":
    raise SystemExit(main())
