"""The report's section on restitution and friction a scene sets: the bounce against e² and the
ramp against its closed form, every number read from report/materials.json
(``python scripts/validate_materials.py``, rigid.science.materials); nothing if it is absent."""
from __future__ import annotations

import json
from pathlib import Path


def write(doc, out: Path) -> None:
    path = out / "materials.json"
    if not path.exists():
        return
    m = json.loads(path.read_text())
    doc.heading("Restitution and friction you can set", 2)
    doc.para("A scene's `restitution` e turns into each contact's damper from the clamped damped "
             "oscillator (the damper never pulls, which raises e above exp(−πζ/√(1−ζ²))), with the mass "
             "the contact moves (M / n for n contacts in parallel) and a table of the integrator's own "
             "clamped oscillator (`rigid/engine/materials.py`). Five balls of e = 0.1 … 0.9, thrown at "
             "the floor without gravity, leave it at e times their speed, and pairs meeting head-on "
             "separate at e times their approach speed (explicit Euler, Δt = 0.1 ms, k = 1e5, 10 g "
             "particles). Dropped 0.2 m under gravity they rise to e² of the drop (the apex above the "
             "height of first touch): gravity keeps pressing on a contact while it lasts, which takes "
             "g t_c out of the rebound, so each contact with a static plane remembers its impact speed "
             "v0 and takes its damping from a table over e, ωΔt and the load β = g_n / (ω e v0) "
             "(`rigid/engine/damping_table.py`), stepped with the integrator's own clamped oscillator.")
    rise = {k: m[k]["apex_above_touch_ratio"] for k in ("dropped", "dropped_volume")}
    rows = [[e, m["thrown_vertex_euler"][i], m["thrown_volume_euler"][i], m["head_on_vertex"][i],
             m["head_on_volume"][i], rise["dropped"][i], rise["dropped_volume"][i], round(e * e, 4)]
            for i, e in enumerate(m["e"])]
    doc.table(["e", "thrown at the floor, exit/approach (vertex)", "(volume)", "head-on pairs, separation/"
               "approach (vertex)", "(volume)", "dropped 0.2 m, rise/drop (vertex)", "(volume)", "e²"], rows)
    r, s = m["ramp"], m["slide"]
    doc.para(f"Friction sticks on the planes (a tangential spring at each contact, slipping at μ f_n). A "
             f"box on a 30° `[[plane]]` with μ = 0.2 slides at {r['acceleration']} m/s², against "
             f"g (sin θ − μ cos θ) = {r['expected']} m/s²; with μ = 0.7 (tan θ < μ) it moves "
             f"{r['moved_mu07_2s']} m in 2 s. A block sliding on the floor with μ = 0.3 decelerates at "
             f"{s['deceleration']} m/s² against μ g = {s['expected']} m/s².")
