"""Where bodies touch, this engine beside PyBullet's convex hull of the same mesh.

    python scripts/bench_contact.py          # -> report/contact.md and report/contact.json (~2 min)

Scenes (floor y = -1, gravity -9.8 y, this engine's defaults: 1 kg particles, k = 1e4, 1 ms):
- a box (assets/box.obj at scale 0.2: side 0.2) and a sphere (assets/sphere.obj at 0.15, the
  42-vertex icosphere of radius 0.15) dropped from rest 5 cm above touching, alone and with a
  second copy 0.7 m away: the centre's height after 1.5 s. The geometry says -0.9 (the box's face
  on the floor) and -0.85 (the sphere's radius; its facets' planes are 0.139-0.15 from the centre);
  a penalty contact sinks by M g / (n k) more (n particles touching);
- two of those spheres meeting head-on at 0.2 m/s without gravity (e = 0.5, μ = 0, k = 1e5, 10 g
  particles, 0.1 ms): the closest distance of their centres, against 2R = 0.30.
PyBullet (optional ``peers`` extra): the mesh's convex hull (GEOM_MESH), the same masses, its
default 1/240 s step, restitution 0.5 for the head-on pair. Measured, never asserted.
The 6-box stack's jitter and penetration and the 30° ramp: rigid.bench.contact_stack.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SHAPES = {"box": ("box.obj", 0.2, -0.9), "sphere": ("sphere.obj", 0.15, -0.85)}
SECONDS = 1.5
COMPANY = np.array([0.7, 0.0, 0.0])


def _config(name: str, company: bool, **keys):
    from rigid.config import SimConfig

    mesh, scale, touch = SHAPES[name]
    start = np.array([0.0, touch + 0.05, 0.0])
    bodies = (dict(position=tuple(start)),) + ((dict(position=tuple(start + COMPANY)),) if company else ())
    return SimConfig(mesh=str(ROOT / "assets" / mesh), scale=scale, bodies=bodies, **keys).validate()


def ours_rest(units, name: str, company: bool) -> float:
    from rigid.engine.simulator import Simulator

    sim = Simulator(_config(name, company), units)
    return float(sim.advance(round(SECONDS * 60))["x"][-1, 0, 1])


def ours_head_on(units) -> float:
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    config = SimConfig(mesh=str(ROOT / "assets" / "sphere.obj"), scale=0.15, walls=False, gravity=(0.0, 0.0, 0.0),
                       collision_stiffness=1e5, particle_mass=0.01, dt=1e-4, restitution=0.5, friction=0.0,
                       bodies=(dict(position=(-0.2, 0.0, 0.0), initial_velocity=(0.1, 0.0, 0.0)),
                               dict(position=(0.2, 0.01, 0.02), initial_velocity=(-0.1, 0.0, 0.0)))).validate()
    x = Simulator(config, units).advance(50)["x"]
    return float(np.linalg.norm(x[:, 0] - x[:, 1], axis=1).min())


def _hull(p, client, name: str):
    from rigid.bodies.mesh import read_mesh

    mesh, scale, _touch = SHAPES[name]
    v = read_mesh(ROOT / "assets" / mesh, scale).vertices
    return p.createCollisionShape(p.GEOM_MESH, vertices=(v - v.mean(axis=0)).tolist(), physicsClientId=client), len(v)


def pybullet_rest(name: str, company: bool) -> float:
    import pybullet as p

    client = p.connect(p.DIRECT)
    try:
        p.setGravity(0, -9.8, 0, physicsClientId=client)
        plane = p.createCollisionShape(p.GEOM_PLANE, planeNormal=(0, 1, 0), physicsClientId=client)
        p.createMultiBody(0, plane, basePosition=(0, -1, 0), physicsClientId=client)
        shape, n = _hull(p, client, name)
        start = np.array([0.0, SHAPES[name][2] + 0.05, 0.0])
        ids = [p.createMultiBody(float(n), shape, basePosition=(start + k * COMPANY).tolist(), physicsClientId=client)
               for k in range(2 if company else 1)]
        for _ in range(round(SECONDS * 240)):
            p.stepSimulation(physicsClientId=client)
        return float(p.getBasePositionAndOrientation(ids[0], physicsClientId=client)[0][1])
    finally:
        p.disconnect(client)


def pybullet_head_on() -> float:
    import pybullet as p

    client = p.connect(p.DIRECT)
    try:
        p.setGravity(0, 0, 0, physicsClientId=client)
        shape, n = _hull(p, client, "sphere")
        ids = []
        for x, y, z, v in ((-0.2, 0.0, 0.0, 0.1), (0.2, 0.01, 0.02, -0.1)):
            body = p.createMultiBody(0.01 * n, shape, basePosition=(x, y, z), physicsClientId=client)
            p.changeDynamics(body, -1, restitution=0.5, lateralFriction=0.0, physicsClientId=client)
            p.resetBaseVelocity(body, (v, 0, 0), physicsClientId=client)
            ids.append(body)
        closest = np.inf
        for _ in range(200):  # 0.83 s
            p.stepSimulation(physicsClientId=client)
            a, b = (np.array(p.getBasePositionAndOrientation(i, physicsClientId=client)[0]) for i in ids)
            closest = min(closest, float(np.linalg.norm(a - b)))
        return closest
    finally:
        p.disconnect(client)


def measure(units, peers: bool = True) -> dict:
    """Every figure of the table: {row: {column: value}}."""
    rows = {}
    for name in SHAPES:
        for company in (False, True):
            label = f"{name} centre at rest, {'in company' if company else 'alone'} (m)"
            rows[label] = {"geometry": SHAPES[name][2], "ours": ours_rest(units, name, company)}
            if peers:
                rows[label]["PyBullet hull"] = pybullet_rest(name, company)
    rows["two spheres R = 0.15: closest centres (m)"] = {"geometry": 0.30, "ours": ours_head_on(units)}
    if peers:
        rows["two spheres R = 0.15: closest centres (m)"]["PyBullet hull"] = pybullet_head_on()
    from .contact_stack import rows as stack_rows

    for label, values in stack_rows(units, peers).items():  # the reference is a closed form or 0
        rows[label] = {"geometry": values.pop("reference"), **values}
    return rows


def markdown(rows: dict, columns: list[str]) -> list[str]:
    lines = ["| scene | " + " | ".join(columns) + " |", "|---" * (len(columns) + 1) + "|"]
    for label, values in rows.items():
        lines.append(f"| {label} | " + " | ".join(f"{values[c]:.4g}" if c in values else "—" for c in columns) + " |")
    return lines


NOTES = """\
Made by `python scripts/bench_contact.py` (CPU, float32) from report/contact.json; PyBullet (the `peers`
extra) with the convex hull of the same mesh, the same masses, μ and e, and its default solver.
"Geometry or closed form": the box's face on the floor (−0.9), the sphere's radius (−0.85), 2R, no motion
and no overlap at rest, g (sin θ − μ cos θ) on the ramp. A penalty contact sinks by M g / (n k) for n
particles touching (docs/physics.md). The resting and head-on rows run at PyBullet's 1/240 s and this
engine's 1 ms and 0.1 ms; the stack at 1 ms and the ramp at 0.2 ms in both. This engine's ramp box runs
with sleeping off (its friction, not sleep, holds it): a drift of 0 is below float32's round-off of a
position. Jitter is the fastest box's speed over the rest of a 3 s run.
The stack.toml rows nest each box's bottom spheres in the hollows of the one below (its half-cell x, z
offsets), so its faces overlap by design; PyBullet's hulls cannot nest and start at the columns' heights
with the same offsets. Penetration is from the poses and the mesh's vertices: > 0 overlaps, < 0 a gap."""


def report_markdown(rows: dict) -> str:
    """report/contact.md from its JSON (docs/hooks/report_tables.py renders the same in the docs)."""
    columns = [c for c in ("geometry", "ours", "PyBullet hull") if any(c in v for v in rows.values())]
    table = markdown(rows, columns)
    table[0] = table[0].replace("| geometry |", "| geometry or closed form |")
    return "\n".join(["# Where bodies touch: this engine beside PyBullet", "", *table, "", NOTES, ""])


def write(out: Path, rows: dict) -> None:
    out.mkdir(parents=True, exist_ok=True)
    (out / "contact.json").write_text(json.dumps(rows, indent=1) + "\n")
    (out / "contact.md").write_text(report_markdown(rows))
