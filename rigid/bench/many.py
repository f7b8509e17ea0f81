"""Many-body speed: the peers (PyBullet, MuJoCo), sleeping, the stage profile, the MuJoCo
comparison pile, cost against particle count (finer spheres; more spheres), 1,000 bodies.

    python scripts/bench_many.py                  # the full run (~30 min on 2 cores)
    python scripts/bench_many.py --quick          # a smoke run: small sizes (seconds)
    python scripts/bench_many.py --only peers     # some sections (peers sleeping profile piles
                                                  # scaling pile_scaling thousand); the JSON keeps the others

0. rigid.bench.peers: the icosphere pile at 27, 125 and 1,000 bodies in this engine (sleeping on
   and off), PyBullet and MuJoCo (same mesh, and sphere primitives), wall s per simulated s;
   rigid.bench.sleeping: a settled pile's cost; rigid.bench.profile: where a substep's time goes.

1. Piles of 125 and 27 spheres (assets/sphere.obj, 42 vertices, scale 0.15, vertex particles,
   a lattice above (0, -0.8, 0), Δt = 1e-3): this engine's time per substep and, if MuJoCo
   is installed, MuJoCo's per step on the same pile (free bodies with the sphere mesh geom,
   same positions and masses), side by side in one process, and their ratio.
2. Cost per substep against particle count (125 volume-sampled spheres, grid chosen to
   reach each target), on the schedule the engine chooses (rigid.engine.schedule), falling
   (frames 2-7) and in contact (frames 61-66) at every size; rigid.bench.pile_scaling: the
   same against particle count with more bodies instead (27 to 24,000 42-vertex spheres).
3. 1,000 volume-sampled spheres (scale 0.05, grid 8: 208,000 particles): rendered frames
   per second, 16 substeps per frame, engine only (no drawing), falling and in contact (from 1 s).
Times: median over repeats of whole frames' wall time. The machine's load and CPU count
are recorded: timings are noisy and never asserted.
"""
from __future__ import annotations

import json
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np

from .many_markdown import markdown
from .pile_scaling import pile_scaling

ROOT = Path(__file__).resolve().parents[2]
PILE = dict(scale=0.15, position=(0.0, -0.8, 0.0), dt=1e-3)


def _setup():
    """Taichi (cpu, float32) and the repository's solved file as TODO units: ``default_units``, one
    module per process, so a process that ran those scenes already (a test worker) has them compiled."""
    from rigid.engine.units import default_units
    from rigid.runtime import init_taichi
    init_taichi("cpu", fp64=False)
    return default_units()


def _build(units, **kw):
    import taichi as ti
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    start = time.perf_counter()
    sim = Simulator(SimConfig(**kw).validate(), units)
    sim.step_frame(1)
    ti.sync()
    return sim, time.perf_counter() - start


def time_steps(step, sync, warmup: int, frames: int, repeats: int, substeps: int) -> list[float]:
    """Wall seconds per substep of each repeat of ``frames`` frames, after ``warmup``."""
    for _ in range(warmup):
        step(substeps)
    sync()
    out = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(frames):
            step(substeps)
        sync()
        out.append((time.perf_counter() - start) / (frames * substeps))
    return out


def mujoco_pile(sim):
    """MuJoCo model and data: one free body per engine body, the mesh geom, the same box."""
    import mujoco
    from rigid.bench.mujoco import _planes

    c, bodies = sim.config, sim.bodies
    g = bodies[0].geometry
    verts = np.asarray(g.vertices, float) - g.particles.mean(axis=0)  # centre of mass at the origin
    vert = " ".join(f"{x:.9g}" for x in verts.reshape(-1))
    face = " ".join(str(int(i)) for i in np.asarray(g.faces).reshape(-1))
    mass = sim.model.body_mass_np
    parts = []
    for i, b in enumerate(bodies):
        p, q = b.position, b.orientation
        parts.append(f'<body pos="{p[0]} {p[1]} {p[2]}" quat="{q[0]} {q[1]} {q[2]} {q[3]}"><freejoint/>'
                     f'<geom type="mesh" mesh="s" mass="{mass[i]}"/></body>')
    gr = c.gravity
    xml = f"""<mujoco>
  <option timestep="{c.dt}" gravity="{gr[0]} {gr[1]} {gr[2]}" integrator="Euler"/>
  <asset><mesh name="s" vertex="{vert}" face="{face}"/></asset>
  <worldbody>{_planes(c.floor, c.wall)}{''.join(parts)}</worldbody>
</mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    return mujoco, model, mujoco.MjData(model)


def pile(units, count: int, quick: bool, row_out: dict) -> None:
    """Engine and MuJoCo on the same pile of ``count`` vertex spheres, side by side."""
    import taichi as ti
    from rigid.bench.mujoco import available

    sim, build_s = _build(units, count=count, **PILE)
    warm, frames, reps = (3, 3, 1) if quick else (30, 30, 5)
    n = sim.substeps
    row = dict(bodies=count, particles=sim.model.num_particles, substeps_per_frame=n,
               engine_build_s=round(build_s, 2))
    step_mj = None
    row["mujoco_version"] = available()
    if row["mujoco_version"]:
        mujoco, model, data = mujoco_pile(sim)
        step_mj = lambda k: mujoco.mj_step(model, data, nstep=k)  # noqa: E731
        time_steps(step_mj, lambda: None, warm, 0, 0, n)
    time_steps(sim.step_frame, ti.sync, warm, 0, 0, n)
    eng, mj = [], []  # interleaved: both see the same load and the same stretch of simulated time
    for _ in range(reps):
        eng += time_steps(sim.step_frame, ti.sync, 0, frames, 1, n)
        if step_mj:
            mj += time_steps(step_mj, lambda: None, 0, frames, 1, n)
    row["engine_us_per_substep"] = round(statistics.median(eng) * 1e6, 2)
    row["engine_repeats_us"] = [round(t * 1e6, 2) for t in eng]
    row["simulated_s"] = [round(warm * n * sim.config.dt, 3), round((warm + reps * frames) * n * sim.config.dt, 3)]
    if step_mj:
        row["mujoco_us_per_step"] = round(statistics.median(mj) * 1e6, 2)
        row["mujoco_repeats_us"] = [round(t * 1e6, 2) for t in mj]
        row["ratio_engine_over_mujoco"] = round(row["engine_us_per_substep"] / row["mujoco_us_per_step"], 3)
        row["mujoco_ncon_at_end"] = int(data.ncon)
    row_out[f"pile_{count}"] = row


def grid_for(target: int, count: int, top: int = 40) -> int:
    """The volume-sampling grid whose ``count`` spheres come closest to ``target`` particles."""
    from rigid.bodies.mesh import body_geometry
    from rigid.config import SimConfig
    best, best_err = 3, None
    for g in range(3, top + 1):
        n = count * len(body_geometry(SimConfig(scale=PILE["scale"], particles="volume", grid=g)).particles)
        err = abs(np.log(n / target))
        if best_err is None or err < best_err:
            best, best_err = g, err
        if n > target * 2:
            break
    return best


CONTACT_FRAME = 60  # the "in contact" window starts 1 s in: every sphere has landed on the pile


def _step_until(sim, frame: int) -> None:
    """Step ``sim`` up to ``frame`` (``sim.frame`` counts every step_frame: the build's, warm-ups, repeats)."""
    while sim.frame < frame:
        sim.step_frame()


def scaling(units, targets, max_build_s: float) -> list[dict]:
    """Time per substep against particle count: 125 volume spheres, the engine's own path, over
    the same simulated windows at every size: falling (frames 2-7, before any contact) and in
    contact (frames 61-66, the pile formed: the costly state, which the issue's figure quotes)."""
    import taichi as ti
    points = []
    for target in targets:
        grid = grid_for(target, 125)
        sim, build_s = _build(units, count=125, particles="volume", grid=grid, **dict(PILE, position=(0.0, -0.7, 0.0)))
        n_p = sim.model.num_particles
        falling = time_steps(sim.step_frame, ti.sync, 0, 2, 3, 16)  # frames 2-7 (the build ran frame 1)
        start = time.perf_counter()
        _step_until(sim, CONTACT_FRAME)
        ti.sync()
        settle_s = time.perf_counter() - start
        contact = time_steps(sim.step_frame, ti.sync, 0, 2, 3, 16)
        f, c = statistics.median(falling), statistics.median(contact)
        points.append(dict(target=target, particles=n_p, bodies=125, grid=grid, path=sim.schedule,
                           build_s=round(build_s, 2), us_per_substep=round(f * 1e6, 2),
                           ns_per_particle_substep=round(f * 1e9 / n_p, 2),
                           contact_us_per_substep=round(c * 1e6, 2), contact_ns_per_particle_substep=round(c * 1e9 / n_p, 2)))
        print(f"  {n_p:>9,} particles ({points[-1]['path']}): {points[-1]['us_per_substep']:,.0f} µs/substep falling, "
              f"{points[-1]['contact_us_per_substep']:,.0f} in contact", flush=True)
        del sim
        if (build_s + settle_s) * 4 > max_build_s:  # the next size (~4x) would take too long
            break
    return points


def thousand(units, quick: bool) -> dict:
    """Rendered frames per second (16 substeps each, engine only) of 1,000 volume spheres: while
    they fall (frames 3-17, the pile forming in the last repeats) and in contact (from 1 s)."""
    import taichi as ti
    count, grid = (8, 3) if quick else (1000, 8)
    sim, build_s = _build(units, count=count, scale=0.05, particles="volume", grid=grid,
                          position=(0.0, -0.8, 0.0), dt=1e-3)
    frames, reps = (2, 1) if quick else (5, 3)
    t = time_steps(sim.step_frame, ti.sync, 2, frames, reps, 16)
    frame_s = statistics.median(t) * 16
    _step_until(sim, CONTACT_FRAME)
    contact = time_steps(sim.step_frame, ti.sync, 0, 2, 1 if quick else 3, 16)
    contact_s = statistics.median(contact) * 16
    return dict(bodies=count, particles=sim.model.num_particles, grid=grid, scale=0.05, substeps_per_frame=16,
                build_s=round(build_s, 2), ms_per_frame=round(frame_s * 1e3, 1), fps=round(1.0 / frame_s, 2),
                fps_repeats=[round(1.0 / (x * 16), 2) for x in t],
                contact_ms_per_frame=round(contact_s * 1e3, 1), contact_fps=round(1.0 / contact_s, 2))


def machine() -> dict:  # shared cores: record the load next to the times
    return dict(cpu_count=os.cpu_count(), loadavg_1_5_15=[round(x, 2) for x in os.getloadavg()],
                platform=platform.platform(), python=platform.python_version())


def figure(points: list[dict], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = np.array([p["particles"] for p in points], float)
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for key, label in (("contact_us_per_substep", "in contact (from 1 s)"), ("us_per_substep", "falling (frames 2-7)")):
        y = np.array([p.get(key, np.nan) for p in points], float)
        ax.loglog(x, y, "o-", label=f"125 volume spheres, {label}")
    ax.loglog(x, 60e-3 * x, "k--", lw=0.8, label="60 ns per particle (the target)")
    ax.set_xlabel("particles")
    ax.set_ylabel("µs per substep")
    ax.set_title("Cost per substep against particle count (CPU)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


SECTIONS = ("peers", "sleeping", "fixed", "profile", "piles", "scaling", "pile_scaling", "thousand")


def run(out: Path, quick: bool = False, sections=SECTIONS) -> dict:
    """Run ``sections`` (default all) and write bench_many.json/.md; with fewer sections, the
    others are kept from the JSON already there."""
    from . import fixed_cost, peers, profile, sleeping

    (out := Path(out)).mkdir(parents=True, exist_ok=True)
    path = out / "bench_many.json"
    partial = set(sections) != set(SECTIONS) and path.exists()
    report = json.loads(path.read_text()) if partial else {}
    report["quick"] = quick
    if not partial:  # a part run alone keeps the whole run's machine and records its own (below)
        report["machine"] = machine()
    units = _setup()
    if "peers" in sections:
        print("side by side with PyBullet and MuJoCo", flush=True)
        report["peer_versions"] = peers.versions()
        report["peers"] = peers.compare(units, counts=(27,) if quick else (27, 125, 1000), seconds=0.1 if quick else 3.0,
                                        repeats={27: 1} if quick else None)
    if "sleeping" in sections and not quick:
        print("sleeping", flush=True)
        report["sleeping"] = sleeping.settled_cost(units)
    if "fixed" in sections:
        print("a small scene's fixed cost", flush=True)
        report["fixed"] = fixed_cost.fixed_cost(units, quick)
    if "profile" in sections and not quick:  # (its kernels would compile for a smoke run)
        print("profile", flush=True)
        report["profile"] = profile.piles(units, quick)
    if "piles" in sections:
        for count in ((27,) if quick else (125, 27)):
            print(f"pile of {count} spheres", flush=True)
            pile(units, count, quick, report)
    if "scaling" in sections:
        print("scaling", flush=True)
        targets = (1_000,) if quick else (1_000, 4_000, 16_000, 64_000, 256_000, 1_000_000)
        report["scaling"] = scaling(units, targets, max_build_s=400.0)
        figure(report["scaling"], out / "figures" / "many_scaling.png")
    if "pile_scaling" in sections:
        print("piles of 42-vertex spheres, 1k to 1M particles", flush=True)
        report["pile_scaling"] = pile_scaling(units, quick)  # pile_scaling.py
    if "thousand" in sections:
        print("1,000 bodies", flush=True)
        report["thousand"] = thousand(units, quick)
    if partial:
        for name in sections:
            if isinstance(report.get(name), dict):
                report[name]["machine"] = machine()
    else:
        report["machine"]["loadavg_1_5_15_at_end"] = [round(x, 2) for x in os.getloadavg()]
    path.write_text(json.dumps(report, indent=2) + "\n")
    (out / "bench_many.md").write_text(markdown(report))  # many_markdown.py
    return report
