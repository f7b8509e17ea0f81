"""Benchmark --record: simulation, rendering (the Taichi rasteriser, offscreen) and encoding, apart and together.

    python scripts/bench_record.py                       # 600 frames, 1280x720, the bouncing torus
    python scripts/bench_record.py --frames 120 --resolution 640 360 --out /tmp/b.json

Phases, all on the scene assets/scenes/bouncing_torus.toml (assets/torus.obj, 4096 vertices):
- simulate: ``sim.step_frame()`` alone
- render:   draw (rigid/view/raster.py, Taichi kernels on the CPU; no Vulkan) + read back as RGBA
            bytes + text overlay (stepping not timed);
            the first KEEP frames are copied aside (into memory paged in before the timer)
- encode:   the MP4 writer (H.264) alone, fed the kept frames forwards and backwards
            (ping-pong: real frame-to-frame motion without holding 600 frames in memory)
- record:   ``rigid.view.video.record`` end to end (simulate, render, encode, progress bar off)
- cli:      the whole command line in a fresh process, Taichi start-up and kernel compile included
Writes JSON (default report/bench_record.json). Numbers are wall-clock seconds on this machine.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the repository

import numpy as np


SCENE = ROOT / "assets" / "scenes" / "bouncing_torus.toml"
KEEP = 120


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--frames", type=int, default=600)
    p.add_argument("--resolution", type=int, nargs=2, default=(1280, 720), metavar=("W", "H"))
    p.add_argument("--out", default=str(ROOT / "report" / "bench_record.json"))
    p.add_argument("--no-cli", action="store_true", help="skip the fresh-process run")
    args = p.parse_args()
    frames, size = args.frames, tuple(args.resolution)
    load_before = os.getloadavg()[0]

    from rigid.config import SimConfig, load_scene
    from rigid.view.encoders import Mp4Writer
    from rigid.view.imaging import TextOverlay
    from rigid.view.render import SceneRenderer
    from rigid.runtime import init_taichi
    from rigid.engine.simulator import Simulator
    from rigid.engine.units import load_units
    from rigid.view.video import record

    init_taichi("cpu")
    config = SimConfig(**load_scene(SCENE)).validate()
    sim = Simulator(config, load_units(ROOT / "rigid_body_dynamic.py"))
    sim.step_frame()  # compile outside the timers
    results = dict(frames=frames, resolution=list(size), scene=str(SCENE.relative_to(ROOT)),
                   particles=sim.model.num_particles, faces=sim.model.num_faces, substeps=sim.substeps)

    sim.reset()
    t0 = time.perf_counter()
    for _ in range(frames):
        sim.step_frame()
    results["simulate"] = _phase(time.perf_counter() - t0, frames)

    renderer = SceneRenderer(sim, size, offscreen=True)
    overlay = TextOverlay(size[1])
    renderer.draw()
    renderer.read_rgba()  # the rasteriser compiles its kernels on the first frame
    sim.reset()
    keep = min(KEEP, frames)
    kept = np.ones((keep, size[1], size[0], 4), np.uint8)  # written now: no page faults in the timer
    render_time = 0.0
    for i in range(frames):
        sim.step_frame()
        t0 = time.perf_counter()
        renderer.draw()
        frame = renderer.read_rgba()
        overlay.draw(frame, f"t = {sim.time:6.3f} s")
        render_time += time.perf_counter() - t0
        if i < keep:
            kept[i] = frame
    renderer.close()
    results["render"] = _phase(render_time, frames)

    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        writer = Mp4Writer(Path(tmp) / "encode.mp4", size)
        period = max(1, 2 * keep - 2)
        for i in range(frames):
            j = i % period
            writer.write(kept[j if j < keep else period - j])
        writer.close()
        results["encode"] = _phase(time.perf_counter() - t0, frames)
        results["mp4_bytes"] = (Path(tmp) / "encode.mp4").stat().st_size
        del kept

        sim.reset()
        t0 = time.perf_counter()
        record(sim, Path(tmp) / "record.mp4", frames, size, progress=False)
        results["record"] = _phase(time.perf_counter() - t0, frames)

        if not args.no_cli:
            cmd = [sys.executable, str(ROOT / "rigid_body_dynamic.py"), "--scene", str(SCENE),
                   "--record", str(Path(tmp) / "cli.mp4"), "--frames", str(frames),
                   "--resolution", *map(str, size)]
            t0 = time.perf_counter()
            proc = subprocess.run(cmd, capture_output=True, text=True)
            results["cli"] = _phase(time.perf_counter() - t0, frames)
            results["cli"]["returncode"] = proc.returncode
            results["cli"]["command"] = "python rigid_body_dynamic.py --scene assets/scenes/bouncing_torus.toml " \
                                        f"--record out.mp4 --frames {frames} --resolution {size[0]} {size[1]}"
    results["machine"] = dict(cpus=os.cpu_count(), platform=platform.platform(), python=platform.python_version(),
                              renderer="rigid/view/raster.py (Taichi kernels on the CPU; no Vulkan, no GPU)",
                              load_average_1min_before=load_before, load_average_1min_after=os.getloadavg()[0],
                              note="the machine is shared: a load average above 0 means other work ran too")
    results["goal"] = "600 frames at 1280x720 of a ~4000-vertex mesh in <= 20 s wall on 2 cores"
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(results, indent=2) + "\n")
    for key in ("simulate", "render", "encode", "record", "cli"):
        if key in results:
            r = results[key]
            print(f"{key:9s} {r['seconds']:7.2f} s  {r['fps']:8.1f} frames/s")
    print(f"wrote {out}")
    return 0


def _phase(seconds: float, frames: int) -> dict:
    return dict(seconds=round(seconds, 3), fps=round(frames / seconds, 1),
                ms_per_frame=round(1e3 * seconds / frames, 2))


if __name__ == "__main__":
    raise SystemExit(main())
