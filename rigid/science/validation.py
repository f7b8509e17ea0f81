"""Validate the physics against outside references and print the table for the report.

    python scripts/validate.py                 # ~1 minute on 2 CPU cores
    python scripts/validate.py --out report    # where validation.json / validation.md go (default report/)

Runs in float64 (plus one float32 subprocess for the float32 figures), every
number judged against rigid/reference.py (closed forms, scipy's solve_ivp at
rtol 1e-12, Landau's flip period). Per integrator (euler, symplectic, rk4):
the observed order of ω(t) and q(t) errors, the energy behaviour over 10 s,
the angular momentum drift and the flip period; then volume sampling's
accuracy against trimesh and its speed.

validation.json and validation.md are tracked, so they hold no run-to-run noise
(``committed_outputs``): timings go to validation_timings.json (not tracked), every
number is rounded to 5 significant digits (on one machine the runs are bit-identical;
another CPU, or a new summation order, changes the last digits), and a value below
1e-12 (float64 round-off, e.g. momentum errors) is written as 0 ("< 1e-12" in the table).
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the repository

import numpy as np


SCHEMES = ("euler", "symplectic", "rk4")
DIGITS = 5  # significant digits kept in the tracked outputs (the table shows at most 5)
ROUND_OFF = 1e-12  # magnitudes below this (float64 round-off) are written as 0
ORDER_DTS = {"euler": (1 / 250, 1 / 500, 1 / 1000), "symplectic": (1 / 250, 1 / 500, 1 / 1000),
             "rk4": (1 / 60, 1 / 120, 1 / 240)}


def integrator_runs(get) -> dict:
    """Every float64 measurement per scheme (rigid.science.experiments), with its reference."""
    from rigid.science import experiments as ex

    out = {}
    for scheme in SCHEMES:
        start = time.perf_counter()
        r = out[scheme] = {}
        r["accuracy"] = ex.accuracy(get, scheme, ORDER_DTS[scheme])
        r["rotational_energy"] = ex.rotational_energy_drift(get, scheme, (1e-3,))
        r["free_flight"] = ex.free_fall(get, scheme, rows=20, substeps=500)  # 10 s at 1e-3
        r["angular_momentum"] = ex.angular_momentum_drift(get, scheme)
        r["bounce_damped"] = _bounce_summary(ex.bounce_energy(get, scheme))
        r["bounce_undamped"] = _bounce_summary(ex.bounce_energy(get, scheme, damping=False))
        flip_dts = (1e-3, 2.5e-4, 1e-4) if scheme != "rk4" else (1 / 60, 1 / 240)
        r["flip"] = [_flip_summary(ex.flip(get, scheme, dt, ex.FLIP_W0, duration=7.0), dt) for dt in flip_dts]
        r["seconds"] = round(time.perf_counter() - start, 2)
        print(f"  {scheme}: {r['seconds']} s", file=sys.stderr)
    return out


def _bounce_summary(r: dict) -> dict:
    energy = np.asarray(r["energy"])
    rise = float(np.diff(energy).max())  # round-off of the energy itself counts as no rise
    return dict(relative_change=r["relative_change"], start=float(energy[0]), end=float(energy[-1]),
                max_rise_per_frame=rise if abs(rise) > ROUND_OFF * np.abs(energy).max() else 0.0)


def _flip_summary(r: dict, dt: float) -> dict:
    return dict(dt=dt, period=r["period"], reference=r["reference_period"],
                relative_error=r["period"] / r["reference_period"] - 1.0)


def float32_runs() -> dict:
    """The float32 figures, in a child process (one Taichi precision per process)."""
    proc = subprocess.run([sys.executable, "-m", "rigid.science.validation", "--float32-part"], capture_output=True, text=True,
                          timeout=600)
    if proc.returncode != 0:
        raise SystemExit(f"float32 part failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout)


def float32_part() -> None:
    from rigid.science import experiments as ex
    from rigid.runtime import init_taichi
    from rigid.engine.units import load_units

    init_taichi("cpu", fp64=False)
    get = ex.SimulatorCache(load_units(ROOT / "rigid_body_dynamic.py"), fp64=False)
    out = dict(angular_momentum=ex.angular_momentum_drift(get, "euler"),
               drop_volume=ex.symmetric_drop(get),
               bounce=_bounce_summary(ex.bounce_energy(get)))
    sim = get(position=(0.3, 0.2, -0.2))  # the 42-vertex sphere dropped: it lands on a vertex
    traj = ex.record(sim, 180, sim.substeps)
    out["drop_vertex"] = dict(max_horizontal_drift=float(np.abs(traj["x"][:, [0, 2]] - [0.3, -0.2]).max()),
                              max_spin=float(np.linalg.norm(traj["omega"], axis=1).max()))
    json.dump(out, sys.stdout)


def sampling_runs() -> dict:
    """Volume sampling: I0/M and centre of mass against trimesh's solids; time to a million particles."""
    import trimesh

    from rigid.bodies.mesh import load_mesh
    from rigid.bodies.sampling import sample_volume

    solids = {"brick": trimesh.creation.box(extents=(1.0, 0.5, 0.25)),
              "box 1 x 0.6 x 0.35": trimesh.creation.box(extents=(1.0, 0.6, 0.35)),
              "icosphere (642 v)": trimesh.creation.icosphere(subdivisions=3, radius=0.4),
              "torus (48 x 24)": trimesh.creation.torus(0.6, 0.2, major_sections=48, minor_sections=24),
              "cone": trimesh.creation.cone(radius=0.5, height=1.0, sections=64)}
    accuracy = []
    for name, mesh in solids.items():
        for grid in (32, 64):
            p = sample_volume(mesh.vertices, mesh.faces, grid)
            r = p - p.mean(axis=0)
            per_mass = (np.eye(3) * np.einsum("ij,ij->", r, r) - r.T @ r) / len(p)
            exact = mesh.moment_inertia / mesh.mass
            h = (mesh.bounds[1] - mesh.bounds[0]).max() / grid
            accuracy.append(dict(mesh=name, grid=grid, particles=len(p),
                                 inertia_error=float(np.linalg.norm(per_mass - exact) / np.linalg.norm(exact)),
                                 com_error_cells=float(np.linalg.norm(p.mean(axis=0) - mesh.center_mass) / h)))
    speed = []
    for name, grid in (("box.obj", 100), ("sphere.obj", 130), ("torus.obj", 200)):
        vertices, faces = load_mesh(ROOT / "assets" / name, 1.0)
        best = float("inf")
        for _ in range(3):
            start = time.perf_counter()
            n = len(sample_volume(vertices, faces, grid))
            best = min(best, time.perf_counter() - start)
        speed.append(dict(mesh=name, grid=grid, particles=n, seconds=round(best, 3)))
    return dict(accuracy=accuracy, speed=speed)


def summary_table(runs: dict) -> dict:
    header = ["integrator", "order ω", "order q", "ω error (smallest Δt)", "rot. KE drift 10 s",
              "free-flight ΔE 10 s (J/kg)", "‖ΔL‖/‖L‖ 10 s", "flip period error"]
    rows = []
    for scheme, r in runs.items():
        acc, flip = r["accuracy"], r["flip"]
        rows.append([scheme, " ".join(f"{p:.2f}" for p in acc["omega_orders"]),
                     " ".join(f"{p:.2f}" for p in acc["q_orders"]),
                     f"{acc['omega_errors'][-1]:.2e} (Δt {acc['dts'][-1]:.2g})",
                     _tiny(r['rotational_energy']['drifts'][0], "+.2e"),
                     f"{r['free_flight']['energy_change'] / r['free_flight']['mass']:+.3g}",
                     _tiny(r['angular_momentum']['L_drift'], ".1e"),
                     f"{flip[0]['relative_error']:+.1%} (Δt {flip[0]['dt']:.2g})"])
    return dict(header=header, rows=rows)


def markdown(result: dict) -> str:
    def table(header, rows):
        lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
        return "\n".join(lines + ["| " + " | ".join(map(str, row)) + " |" for row in rows])

    runs, f32, samp = result["integrators"], result["float32"], result["sampling"]
    out = ["# Physics validation (scripts/validate.py)", "",
           "Float64 unless marked; T-handle (vertex particles, m = 0.7 kg each) in free flight, "
           "ω0 = (0.4, 0.3, 3) rad/s; references from rigid/reference.py (scipy solve_ivp rtol 1e-12, "
           "closed forms). Orders are log2 of successive error ratios over three Δt "
           "(euler, symplectic: 1/250, 1/500, 1/1000 s; rk4: 1/60, 1/120, 1/240 s), errors the largest "
           "over t = 0.5 … 2 s. Energy: relative change of ½ L·ω torque-free (Δt = 1e-3); total energy of "
           "the free flight under gravity per kg. Flip period error at Δt = 1e-3 (rk4: 1/60) for "
           "ω0 = (0, 6, 1.5) rad/s.", "", table(**result["table"]), ""]
    rows = []
    for scheme, r in runs.items():
        d, u = r["bounce_damped"], r["bounce_undamped"]
        rows.append([scheme, f"{d['start']:.1f} → {d['end']:.1f}", _tiny(d['max_rise_per_frame'], ".3g", "≈ 0"),
                     f"{u['start']:.1f} → {u['end']:.1f}", _tiny(u['max_rise_per_frame'], ".3g", "≈ 0")])
    out += ["## Bouncing in the box, 10 s (sphere.obj, 42 particles, Δt = 1e-3)", "",
            table(["integrator", "E with damping+friction (J)", "max rise/frame (J)",
                   "E, no damping or friction (J)", "max rise/frame (J)"], rows), "",
            "Explicit Euler adds exactly ½ M |g|² Δt² per substep in free flight (0.032 J per frame "
            "here); undamped penalty springs under explicit Euler pump energy at every bounce.", ""]
    rows = [[scheme, f"{f['dt']:.3g}", f"{f['period']:.4f}", f"{f['reference']:.4f}", f"{f['relative_error']:+.2%}"]
            for scheme, r in runs.items() for f in r["flip"]]
    out += ["## The intermediate-axis flip (ω0 = (0, 6, 1.5) rad/s, T-handle)", "",
            table(["integrator", "Δt (s)", "period (s)", "Landau K(k) (s)", "error"], rows), "",
            "Near the separatrix the period depends on the orbit's energy logarithmically; explicit "
            "Euler's energy drift moves the orbit, so its period error shrinks only with Δt.", ""]
    out += ["## Float32 figures", "",
            table(["measurement", "value"], [
                ["‖ΔL‖/‖L‖ over 10 s (euler, gravity on)", f"{f32['angular_momentum']['L_drift']:.1e}"],
                ["max abs(‖q‖ − 1), ‖RᵀR − E‖₂ (10 s tumble)",
                 f"{f32['angular_momentum']['q_norm_error']:.1e}, {f32['angular_momentum']['orthonormality_error']:.1e}"],
                ["sphere.obj (42 vertices) dropped: max drift (m), max spin (rad/s)",
                 f"{f32['drop_vertex']['max_horizontal_drift']:.2g}, {f32['drop_vertex']['max_spin']:.2g}"],
                ["volume sphere (grid 10) dropped: max drift (m), max spin (rad/s)",
                 f"{f32['drop_volume']['max_horizontal_drift']:.2g}, {f32['drop_volume']['max_spin']:.2g}"],
                ["damped bounce: max energy rise per frame (J)", f"{f32['bounce']['max_rise_per_frame']:.4g}"]]), "",
            "The 42-vertex icosphere lands on its vertex at (0, −1, 0), an unstable balance that float32 "
            "round-off can tip over (physics): friction capped by viscous damping (the contact law, "
            "rigid/engine/contact.py) holds it within the millimetre above; the volume-sampled sphere rests "
            "on a flat layer of cells.", ""]
    rows = [[a["mesh"], a["grid"], a["particles"], f"{a['inertia_error']:.2%}", f"{a['com_error_cells']:.3f}"]
            for a in samp["accuracy"]]
    out += ["## Volume sampling against trimesh's solids", "",
            table(["mesh", "grid", "particles", "I0/M error", "centre of mass error (cells)"], rows), "",
            table(["mesh", "grid", "particles"], [[s["mesh"], s["grid"], s["particles"]] for s in samp["speed"]]), "",
            "Sampling times (best of 3) and the runs' durations are this machine's: they go to "
            "validation_timings.json, which is not tracked.", ""]
    return "\n".join(out)


def _tiny(x: float, spec: str, zero: str = f"< {ROUND_OFF:.0e}") -> str:
    """A number as ``spec``, or ``zero`` where it was rounded to 0 (below float64 round-off)."""
    return zero if x == 0 else format(x, spec)


def committed_outputs(result: dict) -> tuple[str, str, str]:
    """(validation.json, validation.md, validation_timings.json) texts for a run's result: every
    timing apart, every other number to DIGITS significant digits and 0 below ROUND_OFF, so two
    runs (or two machines) give the same tracked files."""
    timings: dict = {}

    def clean(value, path):
        if isinstance(value, dict):
            out = {}
            for key, item in value.items():
                if key == "seconds":
                    timings[path + key] = item
                else:
                    out[key] = clean(item, f"{path}{key}.")
            return out
        if isinstance(value, (list, tuple)):
            return [clean(item, f"{path}{i}.") for i, item in enumerate(value)]
        if isinstance(value, (float, np.floating)):
            return 0.0 if abs(value) < ROUND_OFF else float(f"{float(value):.{DIGITS}g}")
        return value

    stable = clean(result, "")
    stable["table"] = summary_table(stable["integrators"])
    stable["convergence"] = {s: dict(dts=r["accuracy"]["dts"], errors=r["accuracy"]["omega_errors"])
                             for s, r in stable["integrators"].items()}
    stable["precision"] = dict(significant_digits=DIGITS, zero_below=ROUND_OFF,
                               timings="validation_timings.json (not tracked)")
    return (json.dumps(stable, indent=1, default=float) + "\n", markdown(stable) + "\n",
            json.dumps(timings, indent=1) + "\n")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=str(ROOT / "report"), help="folder for validation.json and .md (default report/)")
    p.add_argument("--float32-part", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.float32_part:
        float32_part()
        return 0

    from rigid.science import experiments as ex
    from rigid.run.atomic import atomic_output
    from rigid.runtime import init_taichi
    from rigid.engine.units import load_units

    start = time.perf_counter()
    init_taichi("cpu", fp64=True)
    get = ex.SimulatorCache(load_units(ROOT / "rigid_body_dynamic.py"), fp64=True)
    print("float64 runs ...", file=sys.stderr)
    runs = integrator_runs(get)
    print("float32 runs ...", file=sys.stderr)
    f32 = float32_runs()
    print("volume sampling ...", file=sys.stderr)
    result = dict(integrators=runs, float32=f32, sampling=sampling_runs())
    result["seconds"] = round(time.perf_counter() - start, 1)
    texts = committed_outputs(result)
    print(texts[1])
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for name, content in zip(("validation.json", "validation.md", "validation_timings.json"), texts):
        with atomic_output(out / name) as tmp:
            tmp.write_text(content)
    print(f"wrote {out / 'validation.json'} and {out / 'validation.md'} ({result['seconds']} s; "
          f"timings in {out / 'validation_timings.json'})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
