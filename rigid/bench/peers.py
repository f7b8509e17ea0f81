"""Many bodies side by side with PyBullet and MuJoCo: wall seconds per simulated second.

    python scripts/bench_many.py --peers          # 27, 125 and 1,000 bodies (long: ~15 min on 2 cores)
    python scripts/bench_many.py --peers --quick  # 27 bodies, 0.2 s simulated (seconds)

The scene, the same for every engine: the handout's icosphere (assets/sphere.obj, 42
vertices) at scale 0.15 (27 and 125 bodies) or 0.07 (1,000), 0.42 kg each, dropped from rest
as this engine's lattice (scale 1.02 × the body's reach apart, seeded random orientations)
jittered by up to ±3 mm in x and z, into the box (floor y = −1, walls x, z = ±1), gravity
−9.8 y, for 3 s. Each engine at its own default step: this engine 1 ms, symplectic Euler,
10 g particles, damping 12, friction 0.4 (the shipped scenes' materials), sleeping on and off;
PyBullet 1/240 s; MuJoCo 2 ms with its CG solver (its default Newton solver is far slower on
piles). The peers get the same mesh (each collides with its convex hull) and, separately, a
sphere primitive of the mesh's radius. The peers are optional (``pip install '.[peers]'``);
an engine that is not installed is left out. Repeats interleave the engines (same load);
medians. Times are reported, never asserted.
"""
from __future__ import annotations

import statistics
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SPHERE = ROOT / "assets" / "sphere.obj"
MATERIALS = dict(particle_mass=0.01, velocity_damping_stiffness=12.0, friction_stiffness=0.4,
                 integrator="symplectic", dt=1e-3)
SCALE = {27: 0.15, 125: 0.15, 1000: 0.07}
JITTER = 0.003  # m, in x and z


def versions() -> dict:
    """The peers' installed versions (None: not installed)."""
    from importlib import metadata

    out = {}
    for name in ("pybullet", "mujoco"):
        try:
            __import__(name)
            out[name] = metadata.version(name)
        except (ImportError, metadata.PackageNotFoundError):
            out[name] = None
    return out


def scene(count: int, seed: int = 0, scale: float | None = None):
    """(config, bodies) of the benchmark's pile: the engine's lattice, jittered (by less for spheres
    smaller than 0.07, whose lattice leaves smaller gaps)."""
    from rigid.bodies.placement import scene_bodies
    from rigid.config import SimConfig

    scale = scale or SCALE.get(count, 0.15 if count <= 125 else 0.07)
    config = SimConfig(mesh=str(SPHERE), scale=scale, count=count, position=(0.0, -0.8, 0.0), seed=seed,
                       **MATERIALS).validate()
    bodies = scene_bodies(config)
    rng = np.random.default_rng(seed + 1000)
    jitter = JITTER * min(1.0, scale / 0.07)
    for b in bodies:
        b.position = b.position + np.array([1.0, 0.0, 1.0]) * rng.uniform(-jitter, jitter, 3)
    return config, bodies


def run_engine(units, config, bodies, seconds: float, sleep: bool) -> dict:
    """This engine: wall seconds per simulated second (the kernels compiled beforehand)."""
    import taichi as ti
    from rigid.engine.simulator import Simulator

    sim = Simulator(config.replace(sleep=sleep), units, bodies=bodies)
    sim.advance_frames(1)  # compile (or load) the kernels, the row copy included
    sim.reset()
    frames = max(1, round(seconds * 60))
    start = time.perf_counter()
    sim.advance_frames(frames)
    ti.sync()
    wall = time.perf_counter() - start
    return dict(wall_per_sim_s=wall / (frames / 60.0), asleep_at_end=int(sim.asleep().sum()),
                us_per_substep=wall / (frames * sim.substeps) * 1e6)


def _mesh_local(config, bodies):
    g = bodies[0].geometry
    return (np.asarray(g.vertices, float) - g.particles.mean(axis=0)), np.asarray(g.faces, int), config.scale


def run_mujoco(config, bodies, seconds: float, shape: str, solver: str = "CG") -> dict:
    import mujoco
    from rigid.bench.mujoco import _planes

    verts, faces, radius = _mesh_local(config, bodies)
    mass = bodies[0].particle_mass * len(bodies[0].geometry.particles)
    if shape == "mesh":
        asset = (f'<asset><mesh name="s" vertex="{" ".join(f"{c:.9g}" for c in verts.reshape(-1))}" '
                 f'face="{" ".join(str(int(i)) for i in faces.reshape(-1))}"/></asset>')
        geom = f'<geom type="mesh" mesh="s" mass="{mass}"/>'
    else:
        asset, geom = "", f'<geom type="sphere" size="{radius}" mass="{mass}"/>'
    parts = "".join(f'<body pos="{b.position[0]} {b.position[1]} {b.position[2]}" quat="{b.orientation[0]} '
                    f'{b.orientation[1]} {b.orientation[2]} {b.orientation[3]}"><freejoint/>{geom}</body>' for b in bodies)
    g = config.gravity
    xml = (f'<mujoco><option gravity="{g[0]} {g[1]} {g[2]}" solver="{solver}"/>{asset}'
           f'<worldbody>{_planes(config.floor, config.wall)}{parts}</worldbody></mujoco>')
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    steps = max(1, round(seconds / model.opt.timestep))
    start = time.perf_counter()
    mujoco.mj_step(model, data, nstep=steps)
    wall = time.perf_counter() - start
    return dict(wall_per_sim_s=wall / (steps * model.opt.timestep), dt=model.opt.timestep, contacts_at_end=int(data.ncon))


def run_pybullet(config, bodies, seconds: float, shape: str) -> dict:
    import pybullet as p

    verts, _faces, radius = _mesh_local(config, bodies)
    mass = bodies[0].particle_mass * len(bodies[0].geometry.particles)
    client = p.connect(p.DIRECT)
    try:
        p.setGravity(*config.gravity, physicsClientId=client)
        f, w = config.floor, config.wall
        for normal, point in (((0, 1, 0), (0, f, 0)), ((-1, 0, 0), (w, 0, 0)), ((1, 0, 0), (-w, 0, 0)),
                              ((0, 0, -1), (0, 0, w)), ((0, 0, 1), (0, 0, -w))):
            plane = p.createCollisionShape(p.GEOM_PLANE, planeNormal=normal, physicsClientId=client)
            p.createMultiBody(0, plane, basePosition=point, physicsClientId=client)
        if shape == "mesh":
            collision = p.createCollisionShape(p.GEOM_MESH, vertices=verts.tolist(), physicsClientId=client)
        else:
            collision = p.createCollisionShape(p.GEOM_SPHERE, radius=radius, physicsClientId=client)
        for b in bodies:
            s, x, y, z = b.orientation
            p.createMultiBody(mass, collision, basePosition=b.position.tolist(), baseOrientation=[x, y, z, s],
                              physicsClientId=client)
        dt = p.getPhysicsEngineParameters(physicsClientId=client)["fixedTimeStep"]
        steps = max(1, round(seconds / dt))
        start = time.perf_counter()
        for _ in range(steps):
            p.stepSimulation(physicsClientId=client)
        wall = time.perf_counter() - start
    finally:
        p.disconnect(client)
    return dict(wall_per_sim_s=wall / (steps * dt), dt=dt)


COLUMNS = (("ours, sleep on", "engine", True), ("ours, sleep off", "engine", False),
           ("PyBullet, same mesh", "pybullet", "mesh"), ("MuJoCo CG, same mesh", "mujoco", "mesh"),
           ("PyBullet spheres", "pybullet", "sphere"), ("MuJoCo CG spheres", "mujoco", "sphere"))


def compare(units, counts=(27, 125, 1000), seconds: float = 3.0, repeats=None) -> list[dict]:
    """One row per body count: each column's median wall s per simulated s over interleaved repeats
    (``repeats`` maps a count to its repeats; default 3, 1 at 1,000 bodies)."""
    have = versions()
    rows = []
    for count in counts:
        config, bodies = scene(count)
        reps = (repeats or {}).get(count, 3 if count < 1000 else 1)
        times: dict = {name: [] for name, _e, _a in COLUMNS}
        extra: dict = {}
        for _ in range(reps):
            for name, engine, arg in COLUMNS:
                if engine != "engine" and not have[engine]:
                    continue
                if engine == "engine":
                    r = run_engine(units, config, bodies, seconds, arg)
                elif engine == "mujoco":
                    r = run_mujoco(config, bodies, seconds, arg)
                else:
                    r = run_pybullet(config, bodies, seconds, arg)
                times[name].append(r["wall_per_sim_s"])
                extra[name] = {k: v for k, v in r.items() if k != "wall_per_sim_s"}
                print(f"  {count} bodies, {name}: {r['wall_per_sim_s']:.3f} s per simulated s", flush=True)
        rows.append(dict(bodies=count, particles=count * len(bodies[0].geometry.particles), scale=config.scale,
                         repeats=reps, seconds=seconds,
                         wall_per_sim_s={n: round(statistics.median(t), 4) for n, t in times.items() if t},
                         repeats_s={n: [round(x, 4) for x in t] for n, t in times.items() if t}, detail=extra))
    return rows


def table(rows: list[dict]) -> tuple[list[str], list[list[str]]]:
    """The side-by-side table (bench_many.md's and the report's): its header and each pile's cells,
    wall seconds per simulated second ("-": an engine not installed)."""
    names = [n for n, _e, _a in COLUMNS]
    cells = [[f"{r['bodies']:,} ({r['particles']:,})"]
             + [f"{r['wall_per_sim_s'][n]:.3f}" if n in r["wall_per_sim_s"] else "-" for n in names] for r in rows]
    return ["bodies (particles)"] + names, cells


def markdown(rows: list[dict], have: dict) -> list[str]:
    header, cells = table(rows)
    lines = ["## Side by side with PyBullet and MuJoCo (wall seconds per simulated second)", "",
             f"PyBullet {have.get('pybullet') or 'not installed'}, MuJoCo {have.get('mujoco') or 'not installed'}; "
             "the icosphere pile dropped into the box, 3 s simulated, each engine at its default step "
             "(ours 1 ms symplectic, PyBullet 1/240 s, MuJoCo 2 ms CG); medians of interleaved repeats "
             "(rigid/bench/peers.py). Below 1: faster than real time.", "",
             "| " + " | ".join(header) + " | repeats |",
             "|---|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + f" | {r['repeats']} |" for row, r in zip(cells, rows)]
    return lines + [""]
