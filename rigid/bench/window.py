"""Benchmark the window: simulating and drawing a frame, timed apart, in a real GGUI window.

    xvfb-run -a python scripts/bench_window.py                  # the sphere and the pile, 1280x720
    xvfb-run -a python scripts/bench_window.py --frames 60 --scenes pile --out /tmp/w.json

Per drawn frame, as the window loop (rigid/view/window.py) runs it, one simulated frame each:
- simulate: ``sim.advance_frames(1)`` (16 substeps and the frame's row)
- draw:     the scene into the picture (rigid/view/raster.py: the meshes' vertices read back,
            the contact shadows, the rasteriser's kernels on the CPU)
- panel:    the control panel's readouts and widgets (its energies are read 4 times a second)
- show:     GGUI's ``canvas.set_image`` and ``window.show`` (Vulkan; lavapipe without a GPU)
Medians over the frames (the first 5 are left out: compiling), in ms, and the frame rate they
allow: 1000 / (sum of the medians); the window caps it at 60. Writes JSON (default
report/bench_window.json). Wall-clock on this machine: quote medians of interleaved runs.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENES = {"sphere": "assignment.toml", "pile": "pile.toml", "dominoes": "dominoes.toml"}
WARM_UP = 5


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--frames", type=int, default=120)
    p.add_argument("--resolution", type=int, nargs=2, default=(1280, 720), metavar=("W", "H"))
    p.add_argument("--scenes", nargs="+", default=["sphere", "pile"], choices=sorted(SCENES))
    p.add_argument("--out", default=str(ROOT / "report" / "bench_window.json"))
    args = p.parse_args()
    import numpy as np

    from rigid.config import SimConfig, load_scene
    from rigid.engine.simulator import Simulator
    from rigid.runtime import init_taichi
    from rigid.view.panel import ControlPanel
    from rigid.view.render import SceneRenderer
    from rigid.view.vulkan import require_display, require_vulkan

    require_display()
    require_vulkan("the window benchmark")
    init_taichi("cpu")
    size = tuple(args.resolution)
    results = dict(resolution=list(size), frames=args.frames, scenes={})
    load_before = os.getloadavg()[0]
    for name in args.scenes:
        sim = Simulator(SimConfig(**load_scene(ROOT / "assets" / "scenes" / SCENES[name])).validate())
        renderer = SceneRenderer(sim, size, offscreen=False, title="bench", fps_limit=100000)
        panel = ControlPanel(sim)
        times = {"simulate": [], "draw": [], "panel": [], "show": []}
        try:
            for _ in range(args.frames + WARM_UP):
                t0 = time.perf_counter()
                sim.advance_frames(1)
                t1 = time.perf_counter()
                renderer.draw()
                t2 = time.perf_counter()
                panel.draw(renderer.window.get_gui(), 60.0, {"sim_ms": 1e3 * (t1 - t0), "draw_ms": 1e3 * (t2 - t1)})
                t3 = time.perf_counter()
                renderer.window.show()
                t4 = time.perf_counter()
                for key, seconds in zip(times, (t1 - t0, t2 - t1, t3 - t2, t4 - t3)):
                    times[key].append(seconds)
        finally:
            renderer.close()
        ms = {key: round(1e3 * float(np.median(v[WARM_UP:])), 2) for key, v in times.items()}
        total = sum(ms.values())
        results["scenes"][name] = dict(
            scene=f"assets/scenes/{SCENES[name]}", bodies=sim.num_bodies, particles=sim.num_particles,
            faces=sim.model.num_faces, substeps=sim.substeps, median_ms=ms, frame_ms=round(total, 2),
            fps=round(1e3 / total, 1), fps_drawing_only=round(1e3 / (total - ms["simulate"]), 1),
            real_time_factor=round(min(1.0, 1e3 / total / 60.0) * 60.0 * sim.substeps * sim.params.dt, 3))
        print(name, results["scenes"][name], flush=True)
    results["machine"] = dict(cpus=os.cpu_count(), platform=platform.platform(), python=platform.python_version(),
                              vulkan="GGUI on the machine's Vulkan (lavapipe: software, on the CPU, without a GPU)",
                              load_average_1min_before=load_before, load_average_1min_after=os.getloadavg()[0],
                              note="the machine is shared: a load average above 0 means other work ran too")
    Path(args.out).write_text(json.dumps(results, indent=2) + "\n")
    print(f"wrote {args.out}")
    return 0
