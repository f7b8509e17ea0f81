"""The speed a user sees: whole ``rigid_body_dynamic.py --headless`` processes, long minus short.

For each case, processes of SHORT and of LONG frames run alternately, REPEATS times
each, with and without ``--export out.npz``; start-up, compilation, mesh reading
and the export's fixed costs cancel in the difference, so

    µs per substep = (median wall(LONG) − median wall(SHORT)) / ((LONG − SHORT) × substeps)

is what each further frame costs the user, host work and the export's rows
included. LONG is chosen so that the simulated part takes seconds (the engine's
figure × frames), well above the start-up's noise. The same bodies and scenario as
the engine's rows in rigid.bench.speed (thrown from the centre, Δt = 1e-3 s,
16 substeps per frame); the 27-sphere pile (``--count 27``) shows that the host's
per-frame cost does not grow with the number of bodies, its engine figure measured
here, in process, with ``Simulator.step_frame`` as speed.py does.
"""
from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
THROWN = ["--position", "0", "0", "0", "--v0", "1", "0", "0.6", "--w0", "1", "2", "0.5"]
SUBSTEPS = 16
REPEATS = 3

# (label, CLI arguments, short and long frame counts)
CASES = [("sphere (42 vertices)", ["--mesh", str(ROOT / "assets/sphere.obj"), "--scale", "0.3", *THROWN], 600, 200_600),
         ("torus (4096 vertices)", ["--mesh", str(ROOT / "assets/torus.obj"), "--scale", "0.5", *THROWN], 600, 24_600),
         ("27 spheres (--count 27)", ["--mesh", str(ROOT / "assets/sphere.obj"), "--scale", "0.15", "--count", "27",
                                      "--v0", "1", "0", "0.6"], 120, 1_320)]


# The 27-sphere case's command line as config keys, for its in-process engine figure.
MANY_CONFIG = dict(mesh=str(ROOT / "assets/sphere.obj"), scale=0.15, count=27, initial_velocity=(1.0, 0.0, 0.6))


def wall_time(args: list[str], frames: int, export: Path | None, timeout: float = 600) -> float:
    """Seconds from starting ``rigid_body_dynamic.py --headless --frames N ARGS`` to its exit."""
    command = [sys.executable, str(ROOT / "rigid_body_dynamic.py"), "--headless", "--frames", str(frames), *args]
    if export is not None:
        command += ["--export", str(export)]
    start = time.perf_counter()
    subprocess.run(command, cwd=ROOT, check=True, capture_output=True, timeout=timeout)
    return time.perf_counter() - start


def per_substep_us(args: list[str], short: int, long: int, export: Path | None) -> dict:
    """Median walls of SHORT and LONG runs (alternating) and the µs per further substep."""
    walls = {short: [], long: []}
    for _ in range(REPEATS):
        for frames in (short, long):
            walls[frames].append(wall_time(args, frames, export))
    medians = {frames: statistics.median(values) for frames, values in walls.items()}
    us = (medians[long] - medians[short]) / ((long - short) * SUBSTEPS) * 1e6
    return dict(us=round(us, 3), short_s=round(medians[short], 3), long_s=round(medians[long], 3))


def engine_us_many(config_keys: dict) -> float:
    """The engine's µs per substep for a case, in process (as rigid.bench.speed times bodies)."""
    import taichi as ti

    from rigid.bench.speed import EngineRunner, time_frames
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator
    from rigid.engine.units import load_units

    sim = Simulator(SimConfig(**config_keys).validate(), load_units(ROOT / "rigid_body_dynamic.py"))
    return time_frames(EngineRunner(sim), 120, REPEATS, SUBSTEPS, ti.sync)


def measure(engine_rows: list[dict]) -> list[dict]:
    """One row per case: the command line's µs per substep without and with --export, beside the
    engine's (``engine_rows`` from rigid.bench.speed, matched by body; measured here otherwise)."""
    out = []
    with tempfile.TemporaryDirectory() as folder:
        export = Path(folder) / "out.npz"
        for label, args, short, long in CASES:
            engine = next((r["engine_us"] for r in engine_rows if r["body"] == label), None)
            if engine is None:
                engine = engine_us_many(MANY_CONFIG)
            plain = per_substep_us(args, short, long, None)
            exported = per_substep_us(args, short, long, export)
            row = dict(body=label, frames_short=short, frames_long=long, engine_us=round(engine, 3),
                       cli_us=plain["us"], cli_export_us=exported["us"], walls=dict(plain=plain, export=exported),
                       load_average=round(os.getloadavg()[0], 2))
            print("command line", row, flush=True)
            out.append(row)
    return out
