"""Measure restitution and friction (rigid.engine.materials) against closed forms, for the report.

    python scripts/validate_materials.py     # ~1 minute: report/materials.json and materials.md

- bounce: five balls (sphere.obj, scale 0.15, 10 g vertex particles, k = 1e5, Δt = 1e-4, explicit
  Euler) of e = 0.1 ... 0.9: (a) thrown at the floor without gravity: exit / approach speed, the
  definition of e; (b) dropped 0.2 m under gravity (vertex and volume particles): the apex
  above the height of first touch over the drop to it, against e² (gravity pulls during the
  contact; the plane contacts' damping allows for it, rigid.engine.materials step 3);
- ramp: boxes on a 30° plane with μ = 0.2 (acceleration against g (sin θ − μ cos θ)) and 0.7
  (how far it moves in 2 s), and a block sliding on a floor plane (deceleration against μ g).
Float32 on the CPU, like the rest of the report; every number is rounded to 4 digits.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

ES = (0.1, 0.3, 0.5, 0.7, 0.9)
G = 9.8


def _sim(**keys):
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    return Simulator(SimConfig(**keys).validate())


def _balls(y: float = -0.6, **keys):
    bodies = tuple(dict(position=(-0.8 + 0.4 * i, y, 0.0), restitution=e) for i, e in enumerate(ES))
    return _sim(scale=0.15, bodies=bodies, restitution=0.0, friction=0.0, collision_stiffness=1e5,
                particle_mass=0.01, dt=1e-4, **keys)


def thrown(particles: str = "vertex", integrator: str = "euler") -> list:
    sim = _balls(y=-0.75, gravity=(0, 0, 0), initial_velocity=(0, -2.0, 0), particles=particles, grid=8,
                 integrator=integrator)
    sim.advance_frames(15)
    return (sim.snapshot()["v"][:, 1] / 2.0).tolist()


def head_on(particles: str) -> list:
    """Five pairs of balls (one e each) meeting at 2 m/s without gravity: separation / approach."""
    bodies = []
    for i, e in enumerate(ES):
        z = -0.8 + 0.4 * i
        bodies += [dict(position=(-0.3, 0.0, z), initial_velocity=(1.0, 0, 0), restitution=e),
                   dict(position=(0.3, 0.0, z), initial_velocity=(-1.0, 0, 0), restitution=e)]
    sim = _sim(scale=0.15, particles=particles, grid=6, bodies=tuple(bodies), friction=0.0, walls=False,
               gravity=(0, 0, 0), collision_stiffness=1e5, particle_mass=0.01, dt=1e-4)
    sim.advance_frames(30)
    v = sim.snapshot()["v"][:, 0]
    return ((v[1::2] - v[0::2]) / 2.0).tolist()


def dropped(particles: str = "vertex") -> dict:
    """Bounce heights over the drop to first contact: the apex above the touch height (y − touch +
    v² / 2g at the first substep without contact force; the table's column) and, as before, v² / 2g
    alone (height_ratio: it misses that the ball may still be inside, coasting out, then)."""
    sim = _balls(particles=particles, grid=8)
    s0 = sim.snapshot()
    y0 = s0["x"][:, 1]
    p, body = sim.particle_positions(), sim.particle_bodies()
    low = np.array([p[body == b][:, 1].min() for b in range(len(ES))])
    touch = -1.0 + (y0 - low) + sim.model.radius_np  # the centre's height when the ball touches
    sim.advance_frames(10)
    dt = sim.params.dt
    prev = sim.snapshot()
    leave = np.full((len(ES), 2), np.nan)  # (height, speed) at the first free substep after the bounce
    touched = np.zeros(len(ES), bool)
    for _ in range(4000):
        sim.step_frame(substeps=1)
        s = sim.snapshot()
        y, v = s["x"][:, 1], s["v"][:, 1]
        touched |= y < touch
        free = touched & np.isnan(leave[:, 0]) & (v > 0) & (np.abs((v - prev["v"][:, 1]) / dt + G) < 1e-2 * G)
        leave[free] = np.stack([prev["x"][:, 1], prev["v"][:, 1]], axis=1)[free]
        prev = s
        if not np.isnan(leave[:, 0]).any():
            break
    rise = leave[:, 1] ** 2 / (2 * G)
    ratio = rise / (y0 - touch)
    return dict(height_ratio=ratio.tolist(), e_squared=[e * e for e in ES],
                apex_above_touch_ratio=((leave[:, 0] + rise - touch) / (y0 - touch)).tolist())


def ramp() -> dict:
    theta = math.radians(30)
    n = np.array([-math.sin(theta), math.cos(theta), 0.0])
    down = np.array([-math.cos(theta), -math.sin(theta), 0.0])
    q = (math.cos(theta / 2), 0.0, 0.0, math.sin(theta / 2))
    r = 0.005
    bodies = tuple(dict(position=tuple(np.array([0.0, 0.0, z]) + (0.1 + r + 1e-4) * n), orientation=q, friction=mu)
                   for z, mu in ((-0.3, 0.2), (0.3, 0.7)))
    sim = _sim(mesh=str(Path(__file__).resolve().parents[2] / "assets" / "box.obj"), scale=0.2, bodies=bodies,
               particle_radius=r, restitution=0.3, walls=False, collision_stiffness=1e5, particle_mass=0.1, dt=2e-4,
               planes=(dict(point=(0.0, 0.0, 0.0), normal=tuple(n)),))
    sim.advance_frames(12)
    a = sim.snapshot()
    sim.advance_frames(60)
    b = sim.snapshot()
    accel = float((b["v"][0] - a["v"][0]) @ down / (b["t"] - a["t"]))
    sim.advance_frames(60)
    moved = float(np.linalg.norm(sim.snapshot()["x"][1] - a["x"][1]))
    return dict(acceleration=accel, expected=G * (math.sin(theta) - 0.2 * math.cos(theta)), moved_mu07_2s=moved)


def slide(mu: float = 0.3) -> dict:
    sim = _sim(mesh=str(Path(__file__).resolve().parents[2] / "assets" / "box.obj"), scale=0.2, position=(0, -0.9, 0),
               initial_velocity=(3.0, 0, 0), friction=mu, restitution=0.3, collision_stiffness=1e5, particle_mass=0.1,
               dt=2e-4, walls=False, planes=(dict(point=(0, -1.0, 0), normal=(0, 1, 0)),))
    sim.advance_frames(20)
    a = sim.snapshot()
    sim.advance_frames(30)
    b = sim.snapshot()
    return dict(deceleration=float((a["v"][0][0] - b["v"][0][0]) / (b["t"] - a["t"])), expected=mu * G)


def measure() -> dict:
    r4 = lambda x: float(f"{x:.4g}")  # noqa: E731
    out = dict(e=list(ES), thrown_vertex_euler=thrown(), thrown_volume_rk4=thrown("volume", "rk4"),
               thrown_volume_euler=thrown("volume", "euler"), head_on_vertex=head_on("vertex"),
               head_on_volume=head_on("volume"), dropped=dropped(), dropped_volume=dropped("volume"), ramp=ramp(),
               slide=slide())
    return json.loads(json.dumps(out), parse_float=lambda s: r4(float(s)))


def markdown(m: dict) -> str:
    rows = ["| e | thrown: exit/approach, vertex Euler | volume RK4 | volume Euler | head-on: separation/approach, "
            "vertex | volume | dropped: rise/drop, vertex | volume | e² |", "|---|---|---|---|---|---|---|---|---|"]
    for i, e in enumerate(m["e"]):
        rows.append(f"| {e} | {m['thrown_vertex_euler'][i]} | {m['thrown_volume_rk4'][i]} | "
                    f"{m['thrown_volume_euler'][i]} | {m['head_on_vertex'][i]} | {m['head_on_volume'][i]} | "
                    f"{m['dropped']['apex_above_touch_ratio'][i]} | {m['dropped_volume']['apex_above_touch_ratio'][i]} | "
                    f"{m['dropped']['e_squared'][i]:.4g} |")
    r, s = m["ramp"], m["slide"]
    rows += ["", f"Ramp 30°, μ = 0.2: acceleration {r['acceleration']} m/s² against g (sin θ − μ cos θ) = "
                 f"{r['expected']} m/s²; μ = 0.7: moved {r['moved_mu07_2s']} m in 2 s. "
                 f"Block sliding, μ = 0.3: deceleration {s['deceleration']} m/s² against μ g = {s['expected']} m/s²."]
    return "\n".join(rows) + "\n"
