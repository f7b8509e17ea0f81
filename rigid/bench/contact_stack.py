"""A 6-box stack and a box on a 30° ramp, this engine beside PyBullet's hull (rows of report/contact.md).

Stack: assets/scenes/stack.toml (six 0.2 boxes of 5 x 5 x 5 volume particles, 10 g each: 1.25 kg,
1 ms) with materials μ = 0.5, e = 0.3, so its contacts are Coulomb with sticking; once as the
scene places it (layers shifted by half a cell in x and z so that a box's bottom spheres sit in
the hollows of the one below) and once in straight columns. Jitter: the peak speed of any box from
1 s (and from 2 s) to 3 s, sampled every frame (16 substeps). Penetration at 3 s, from the poses
and the mesh's vertices: how far the lowest vertex is below the floor, and how far a box's lowest
vertex is below the highest of the box beneath (the faces' overlap; boxes stay level).

Ramp: a lone 0.2 box (8 vertex particles of 0.1 kg, radius 5 mm, k = 1e5, e = 0.3, 0.2 ms, as
assets/scenes/ramp.toml) flat on a 30° [[plane]], one with μ = 0.3 and one with μ = 0.9 (> tan 30°),
started 0.1 mm clear, sleeping off (a body asleep does not drift: the figure is then the
contact's). After 0.2 s to settle: the acceleration down the slope fitted over 1 s,
against g (sin θ − μ cos θ), and the μ = 0.9 box's drift over 2.5 s.

PyBullet gets the same hulls, masses, poses and Δt; it combines two surfaces' friction and
restitution as products, so its floor and ramp carry 1 and the box the value.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
G = 9.8
STACK = dict(mu=0.5, e=0.3, seconds=3.0, frame=16, dt=1e-3)
THETA = math.radians(30)
NORMAL = np.array([-math.sin(THETA), math.cos(THETA), 0.0])  # the ramp rises toward -x
DOWN = np.array([-math.cos(THETA), -math.sin(THETA), 0.0])
TURN = (math.cos(THETA / 2), 0.0, 0.0, math.sin(THETA / 2))  # scalar first: a box flat on the ramp
RAMP = dict(mus=(0.3, 0.9), z=(-0.3, 0.3), dt=2e-4, settle=0.2, fit=1.0, drift=2.5, frame=83)


def _box(scale: float) -> np.ndarray:
    from rigid.bodies.mesh import read_mesh

    v = read_mesh(ROOT / "assets" / "box.obj", scale).vertices
    return v - v.mean(axis=0)


def _matrix(q) -> np.ndarray:
    from rigid.bodies.quaternion import quaternion_to_matrix_np

    return quaternion_to_matrix_np(np.asarray(q, float))


def stack_positions(columns: bool, hulls: bool = False) -> list[np.ndarray]:
    """stack.toml's centres, or the same boxes in one column 0.2 + 1 mm apart. Hulls cannot nest:
    at stack.toml's heights (0.19 apart) they would start 1 cm inside each other, so they keep
    its x, z offsets at the column's heights."""
    from rigid.config import load_scene

    scene = [np.array(b["position"], float) for b in load_scene(ROOT / "assets" / "scenes" / "stack.toml")["bodies"]]
    column = [np.array([0.0, -0.899 + 0.201 * k, 0.0]) for k in range(len(scene))]
    if columns:
        return column
    return [np.array([s[0], c[1], s[2]]) for s, c in zip(scene, column)] if hulls else scene


def penetration(x: np.ndarray, q: np.ndarray) -> tuple[float, float]:
    """(into the floor, between boxes) in m, from centres (B, 3) and quaternions (B, 4), scalar first."""
    v = _box(0.2)
    ys = np.array([(v @ _matrix(qi).T)[:, 1] + xi[1] for xi, qi in zip(x, q)])
    floor = -1.0 - ys.min()
    between = max(ys[i].max() - ys[i + 1].min() for i in range(len(ys) - 1))
    return float(floor), float(between)


def _stack_figures(t: np.ndarray, v: np.ndarray, x: np.ndarray, q: np.ndarray) -> dict:
    speed = np.linalg.norm(v, axis=-1).max(axis=-1)  # the fastest box, per frame
    floor, between = penetration(x, q)
    return {"jitter from 1 s": float(speed[t >= 1.0].max()), "jitter from 2 s": float(speed[t >= 2.0].max()),
            "into floor": floor, "between boxes": between}


def ours_stack(units, columns: bool) -> dict:
    from rigid.config import SimConfig, load_scene
    from rigid.engine.simulator import Simulator

    keys = load_scene(ROOT / "assets" / "scenes" / "stack.toml")
    keys["bodies"] = tuple(dict(position=tuple(p)) for p in stack_positions(columns))
    config = SimConfig(**keys, friction=STACK["mu"], restitution=STACK["e"]).validate()
    sim = Simulator(config, units)
    block = sim.advance_frames(round(STACK["seconds"] / (sim.substeps * config.dt)))
    return _stack_figures(block["t"], block["v"], block["x"][-1], block["q"][-1])


def _world(p, gravity=True):
    client = p.connect(p.DIRECT)
    p.setGravity(0, -G if gravity else 0, 0, physicsClientId=client)
    return client


def _ground(p, client, normal, point):
    shape = p.createCollisionShape(p.GEOM_PLANE, planeNormal=tuple(normal), physicsClientId=client)
    body = p.createMultiBody(0, shape, basePosition=tuple(point), physicsClientId=client)
    p.changeDynamics(body, -1, lateralFriction=1.0, restitution=1.0, physicsClientId=client)


def _hull_body(p, client, scale, mass, position, q, mu, e):
    shape = p.createCollisionShape(p.GEOM_MESH, vertices=_box(scale).tolist(), physicsClientId=client)
    body = p.createMultiBody(mass, shape, basePosition=tuple(position), physicsClientId=client,
                             baseOrientation=(q[1], q[2], q[3], q[0]))  # PyBullet's are x, y, z, w
    p.changeDynamics(body, -1, lateralFriction=mu, restitution=e, physicsClientId=client)
    return body


def _states(p, client, ids):
    x, q, v = [], [], []
    for body in ids:
        pos, orn = p.getBasePositionAndOrientation(body, physicsClientId=client)
        x.append(pos), q.append((orn[3], *orn[:3])), v.append(p.getBaseVelocity(body, physicsClientId=client)[0])
    return np.array(x), np.array(q), np.array(v)


def pybullet_stack(columns: bool) -> dict:
    import pybullet as p

    client = _world(p)
    try:
        p.setTimeStep(STACK["dt"], physicsClientId=client)
        _ground(p, client, (0, 1, 0), (0, -1, 0))
        ids = [_hull_body(p, client, 0.2, 125 * 0.01, x, (1, 0, 0, 0), STACK["mu"], STACK["e"])
               for x in stack_positions(columns, hulls=True)]
        t, v = [], []
        for frame in range(1, round(STACK["seconds"] / (STACK["frame"] * STACK["dt"])) + 1):
            for _ in range(STACK["frame"]):
                p.stepSimulation(physicsClientId=client)
            x, q, vs = _states(p, client, ids)
            t.append(frame * STACK["frame"] * STACK["dt"]), v.append(vs)
        return _stack_figures(np.array(t), np.array(v), x, q)
    finally:
        p.disconnect(client)


def _ramp_figures(t: np.ndarray, x: np.ndarray) -> dict:
    """Acceleration down the slope of body 0 (least squares over the fit window) and body 1's
    drift over the drift window, from centres (frames, 2, 3) at times t."""
    s = x[:, 0] @ DOWN
    window = (t >= RAMP["settle"]) & (t <= RAMP["settle"] + RAMP["fit"])
    accel = 2 * np.polyfit(t[window], s[window], 2)[0]
    start = np.argmin(abs(t - RAMP["settle"]))
    end = np.argmin(abs(t - RAMP["settle"] - RAMP["drift"]))
    return {"acceleration": float(accel), "drift": float(np.linalg.norm(x[end, 1] - x[start, 1]))}


def _ramp_starts():
    return [(0.1 + 1e-4) * NORMAL + np.array([0.0, 0.0, z]) for z in RAMP["z"]]


def ours_ramp(units) -> dict:
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    bodies = tuple(dict(position=tuple(x), orientation=TURN, friction=mu) for x, mu in zip(_ramp_starts(), RAMP["mus"]))
    config = SimConfig(mesh=str(ROOT / "assets" / "box.obj"), scale=0.2, bodies=bodies, particle_radius=0.005,
                       restitution=0.3, walls=False, sleep=False, collision_stiffness=1e5, particle_mass=0.1, dt=RAMP["dt"],
                       planes=(dict(point=(0.0, 0.0, 0.0), normal=tuple(NORMAL)),)).validate()
    sim = Simulator(config, units)
    block = sim.advance(round((RAMP["settle"] + RAMP["drift"]) / (sim.substeps * config.dt)) + 1)
    return _ramp_figures(block["t"], block["x"])


def pybullet_ramp() -> dict:
    import pybullet as p

    client = _world(p)
    try:
        p.setTimeStep(RAMP["dt"], physicsClientId=client)
        _ground(p, client, NORMAL, (0, 0, 0))
        ids = [_hull_body(p, client, 0.2, 8 * 0.1, x, TURN, mu, 0.3) for x, mu in zip(_ramp_starts(), RAMP["mus"])]
        t, x = [0.0], [_states(p, client, ids)[0]]
        for frame in range(1, round((RAMP["settle"] + RAMP["drift"]) / (RAMP["frame"] * RAMP["dt"])) + 2):
            for _ in range(RAMP["frame"]):
                p.stepSimulation(physicsClientId=client)
            t.append(frame * RAMP["frame"] * RAMP["dt"]), x.append(_states(p, client, ids)[0])
        return _ramp_figures(np.array(t), np.array(x))
    finally:
        p.disconnect(client)


def rows(units, peers: bool) -> dict:
    """The stack's and the ramp's rows of report/contact.json: {row: {column: value}}."""
    out = {}
    for columns in (False, True):
        name = "columns" if columns else "stack.toml"
        ours = ours_stack(units, columns)
        theirs = pybullet_stack(columns) if peers else {}
        for key, label, unit in (("jitter from 1 s", "peak box speed from 1 s", "m/s"),
                                 ("jitter from 2 s", "peak box speed from 2 s", "m/s"),
                                 ("into floor", "penetration into the floor at rest", "mm"),
                                 ("between boxes", "penetration between boxes at rest", "mm")):
            scale = 1e3 if unit == "mm" else 1.0
            row = {"reference": 0.0, "ours": ours[key] * scale}
            if peers:
                row["PyBullet hull"] = theirs[key] * scale
            out[f"6-box stack ({name}): {label} ({unit})"] = row
    ours, theirs = ours_ramp(units), (pybullet_ramp() if peers else {})
    mu = RAMP["mus"][0]
    out[f"box on a 30° plane, μ = {mu}: acceleration (m/s²)"] = {
        "reference": G * (math.sin(THETA) - mu * math.cos(THETA)), "ours": ours["acceleration"],
        **({"PyBullet hull": theirs["acceleration"]} if peers else {})}
    out[f"box on a 30° plane, μ = {RAMP['mus'][1]}: drift in {RAMP['drift']} s (mm)"] = {
        "reference": 0.0, "ours": ours["drift"] * 1e3, **({"PyBullet hull": theirs["drift"] * 1e3} if peers else {})}
    return out
