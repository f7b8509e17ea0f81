"""Regenerate report/: report.md and report.pdf with their figures.

    python scripts/make_report.py            # ~1-2 minutes: simulations, validation, figures, PDF
    python scripts/make_report.py --quick    # shorter runs, smaller pictures (the tests use it)

Simulations run here (CPU, float32, fixed seeds: the same figures every time).
The validation table comes from scripts/validate.py and the benchmark table from
scripts/bench.py: their JSON in report/ is used when present (the benchmark is slow
and its timings are the machine's, not reproducible); --rerun runs both again. The
many-body benchmark (scripts/bench_many.py: bench_many.json, figures/many_scaling.png)
is only read, never run here (minutes).
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the repository

from rigid.report import figures as figures
from rigid.report import text as report_text
from rigid.report.document import Doc

SCENES = ("assignment", "thrown_sphere", "tumbling_t_handle", "bouncing_torus")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=str(ROOT / "report"), help="output folder (default report/)")
    p.add_argument("--quick", action="store_true", help="short simulations, for tests")
    p.add_argument("--rerun", action="store_true", help="re-run scripts/validate.py and scripts/bench.py")
    args = p.parse_args(argv)
    from rigid.runtime import init_taichi

    init_taichi("cpu", fp64=False)
    build(Path(args.out), quick=args.quick, rerun=args.rerun)
    return 0


def build(out: Path, quick: bool = False, rerun: bool = False) -> None:
    """Write ``out``/report.md, report.pdf and figures/ on Taichi as this process initialised it
    (``init_taichi("cpu", fp64=False)``, as ``main`` does). The TODO units are the repository's
    solved file (``default_units``: one module per process, so a process that has run its scenes
    already has the kernels compiled)."""
    (out / "figures").mkdir(parents=True, exist_ok=True)

    from rigid.config import SimConfig, load_scene
    from rigid.science.experiments import SimulatorCache, record
    from rigid.engine.units import default_units

    units = default_units()
    get_sim = SimulatorCache(units, fp64=False)
    configs = {name: SimConfig(**load_scene(ROOT / "assets/scenes" / f"{name}.toml")).validate()
               for name in SCENES}
    seconds = 3.0 if quick else 10.0

    runs = {}
    for name in ("assignment", "thrown_sphere", "tumbling_t_handle"):
        c = configs[name]
        scene = {k: getattr(c, k) for k in ("mesh", "scale", "particle_mass", "integrator")}
        runtime = {k: getattr(c, k) for k in get_sim_runtime_keys()}
        sim = get_sim(**scene, **runtime)
        runs[name] = record(sim, int(seconds * 60), sim.substeps)
        figures.energy_momentum(runs[name], f"{name}.toml", out / "figures" / f"energy_{name}.png")
    figures.side_view(runs["thrown_sphere"], configs["thrown_sphere"].floor, configs["thrown_sphere"].wall,
                      out / "figures" / "trajectory_thrown_sphere.png")
    flip = flip_figure(get_sim, out / "figures" / "flip.png", duration=6.0 if quick else 9.0)
    validation = load_or_run(out / "validation.json", ["scripts/validate.py", "--out", str(out)], rerun)
    if validation and "convergence" in validation:
        figures.convergence(validation["convergence"], out / "figures" / "convergence.png")
    bench = load_or_run(out / "bench.json", ["scripts/bench.py", "--out", str(out)], rerun, run_if_missing=False)
    still_frames, still_size = ((5, 20, 40), (320, 180)) if quick else ((10, 60, 150), (640, 360))
    stills = render_stills(units, out / "figures", still_frames, still_size)
    many_runs = many_scenes(units, out / "figures", quick)
    bench_many_json = out / "bench_many.json"  # scripts/bench_many.py writes it (minutes): read only
    bench_many = json.loads(bench_many_json.read_text()) if bench_many_json.exists() else None

    doc = Doc()
    report_text.write(doc, out, configs=configs, runs=runs, flip=flip, validation=validation,
                      bench=bench, stills=stills, many=many_runs, bench_many=bench_many)
    (out / "report.md").write_text(doc.markdown(out))
    doc.pdf(out / "report.pdf")
    print(f"wrote {out / 'report.md'} and {out / 'report.pdf'}")


def get_sim_runtime_keys():
    from rigid.engine.simulator import Simulator

    return sorted(Simulator.RUNTIME_KEYS - {"frames", "seed"})


def flip_figure(get_sim, path, duration: float) -> dict:
    """The T-handle's intermediate-axis flip, simulator vs scipy's solve_ivp."""
    from rigid.science import experiments
    from rigid.science import reference

    omega0 = experiments.FLIP_W0
    sim, traj = experiments.flip_run(get_sim, omega0=omega0, duration=duration)  # measured and drawn: one run
    result = experiments.flip_period(sim, traj, omega0)
    _w, _q, omega_ref = reference.torque_free_rotation(sim.model.inertia_body_np[0], omega0, traj["t"])
    figures.flip(traj["t"], experiments.body_omega(traj), traj["t"], omega_ref, result["period"],
                 result["reference_period"], path)
    return result


def load_or_run(path: Path, command: list[str], rerun: bool, run_if_missing: bool = True) -> dict | None:
    if (rerun or (run_if_missing and not path.exists())) and (ROOT / command[0]).exists():
        subprocess.run([sys.executable, *command], cwd=ROOT, check=True)
    return json.loads(path.read_text()) if path.exists() else None


def many_scenes(units, folder: Path, quick: bool) -> dict:
    """The pile and the dominoes (rigid.report.many): stills, energies; the pile's energy figure."""
    from rigid.report import many

    size = (320, 180) if quick else (640, 360)
    results = {name: many.simulate(run, units, size, folder / f"many_{name}.png")
               for name, run in many.runs(quick).items()}
    pile = results["pile"]
    figures.many_energy(pile["t"], pile["kinetic_energy"], pile["potential_energy"],
                        f"pile.toml: {pile['bodies']} bodies", folder / "energy_pile.png")
    return results


def render_stills(units, folder: Path, frames: tuple, size: tuple) -> list[Path]:
    """Frames ``frames`` of a recording of the thrown sphere at ``size``, drawn by the project's
    renderer (rigid/view/raster.py, offscreen: no display, no Vulkan); empty if recording fails.
    What ``--scene assets/scenes/thrown_sphere.toml --record`` writes (the same scene, camera
    and ``view.video.record``), made in this process with the report's ``units`` on the kernels
    it has compiled already: a process of its own started Taichi and built them again."""
    import contextlib
    import io

    import av
    import numpy as np
    from PIL import Image

    from rigid.bodies.placement import scene_bodies
    from rigid.config import SimConfig, load_scene
    from rigid.engine.simulator import Simulator
    from rigid.errors import UserError
    from rigid.view.camera import camera_spec
    from rigid.view.video import record

    video = folder / "thrown_sphere.mp4"
    scene = ROOT / "assets" / "scenes" / "thrown_sphere.toml"
    try:
        config = SimConfig(**{**load_scene(scene), "frames": max(frames) + 1, "resolution": size}).validate()
        sim = Simulator(config, units, bodies=scene_bodies(config))
        with contextlib.redirect_stderr(io.StringIO()):  # the progress bar
            result = record(sim, video, config.frames, config.resolution, progress=False,
                            camera=camera_spec(config.camera, f"scene file {scene}: [camera]"))
        failed = "" if result.exit_code == 0 else f"the recording stopped (exit code {result.exit_code})"
    except (UserError, OSError) as err:
        failed = str(err)
    if failed:
        print(f"note: no stills ({failed})", file=sys.stderr)
        return []
    paths = []
    with av.open(str(video)) as container:
        for i, frame in enumerate(container.decode(video=0)):
            if i in frames:
                path = folder / f"still_{i:03d}.png"
                Image.fromarray(np.asarray(frame.to_ndarray(format="rgb24"))).save(path)
                paths.append(path)
    video.unlink()
    return paths


if __name__ == "__main__":
    raise SystemExit(main())
