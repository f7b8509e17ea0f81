"""A sweep's runs as the worlds of one Simulator, where the runs differ only in what worlds may.

Runs whose scenes differ from the sweep's base only in the bodies' starts and per-body values
(``BATCH_KEYS``: position, orientation, the initial velocities, particle_mass, drag, and the
seed that places copies) are stepped together: one Simulator of W worlds
(rigid.engine.worlds), each world one run's bodies, one launch a chunk of frames for all of
them. A world's rows are its run's rows alone, bit for bit (tests/test_worlds.py), so each
run's NPZ is written from them by the same Trajectory as ``run_frames`` writes, and its bytes
are the single run's. A world that blows up or leaves the box is run again alone, by
``run_task``, so that its file and status line are exactly the single run's too.
"""
from __future__ import annotations

import dataclasses
import tempfile
import time
from pathlib import Path

import numpy as np

BATCH_KEYS = frozenset({"position", "orientation", "initial_velocity", "initial_angular_velocity", "particle_mass",
                        "drag", "seed"})
MAX_WORLDS = 512  # runs a batch steps together (memory: rows of W worlds, ~1 kB a frame each)


def batchable(base, configs: list, record: bool) -> bool:
    """Whether runs of these ``configs`` may be worlds of one Simulator: no video (each run's own
    camera and encoder), and no key other than BATCH_KEYS differs from ``base``."""
    if record or len(configs) < 2:
        return False
    names = [f.name for f in dataclasses.fields(base)]
    return all(getattr(c, n) == getattr(base, n) for c in configs for n in names if n not in BATCH_KEYS)


def batches(tasks: list[dict], workers: int) -> list[dict]:
    """``tasks`` in about one batch per worker (at most MAX_WORLDS runs each), as batch tasks:
    ``name``, ``runs`` (the tasks), and the shared ``frames``, ``units``, ``quick_compile``."""
    count = max(workers, -(-len(tasks) // MAX_WORLDS))
    size = -(-len(tasks) // count)
    groups = [tasks[i:i + size] for i in range(0, len(tasks), size)]
    return [dict(name=f"batch-{k}", runs=group, frames=group[0]["frames"], record=False, units=group[0]["units"],
                 quick_compile=group[0]["quick_compile"]) for k, group in enumerate(groups)]


def run_batch(task: dict, units, run_alone) -> dict:
    """Simulate a batch task's runs as worlds; ``run_alone(task)`` runs one of them by itself.
    Returns ``{"batch": [run_task's outcome for each run, in order]}``."""
    from ..bodies.placement import scene_bodies
    from ..bodies.statics import static_bodies
    from ..engine.simulator import Simulator

    began = time.perf_counter()
    runs, frames = task["runs"], task["frames"]
    configs = [r["config"] for r in runs]
    bodies = []
    for config in configs:
        placed = scene_bodies(config)
        bodies.append(placed + static_bodies(config, placed))
    if len({tuple((b.name, len(b.geometry.particles), b.static) for b in world) for world in bodies}) != 1:
        return {"batch": [run_alone(r) for r in runs]}  # the seeds placed different bodies: one by one
    vary = {key: np.array([[getattr(b, field) for b in world] for world in bodies], np.float64)
            for key, field in (("position", "position"), ("orientation", "orientation"),
                               ("initial_velocity", "velocity"), ("initial_angular_velocity", "angular_velocity"),
                               ("particle_mass", "particle_mass"), ("drag", "drag"))}
    # One thread: the sweep runs a worker per core (the parallel schedule's threads would only contend).
    sim = Simulator(configs[0], units, worlds=len(runs), vary=vary, schedule="serial")
    written, trouble = _run_worlds(sim, configs, frames)
    seconds = (time.perf_counter() - began) / len(runs)
    outcomes = []
    for w, run in enumerate(runs):
        if w in trouble:
            outcomes.append(run_alone(run))
            continue
        npz, last = written[w]
        energy = float(last["kinetic_energy"] + last["potential_energy"])
        outcomes.append(dict(name=run["name"], status="ok", energy=energy, npz=npz, mp4=None, seconds=seconds))
    return {"batch": outcomes}


def _run_worlds(sim, configs: list, frames: int):
    """Every world's NPZ bytes and last row ({w: (bytes, row)}), and the worlds that blew up or
    escaped (checked as run_frames checks a single run)."""
    from ..run.diagnostics import Trajectory, first_blow_up
    from ..run.escape import first_escape
    from ..run.runner import baseline, row_of

    W, per_world = len(configs), sim.num_bodies // len(configs)
    m = sim.model
    start = sim.current_block()
    worlds, trouble = [], set()
    for w in range(W):
        part = slice(w * per_world, (w + 1) * per_world)
        trajectory = Trajectory(m.body_mass_np[part], m.inertia_body_np[part], configs[w].dt, sim.substeps,
                                configs[w].fp64)
        first = _world(start, w)
        trajectory.append_block(first)
        e0, bound = baseline(first, float(m.body_mass_np[part].sum()), sim.params.gravity)
        worlds.append(dict(trajectory=trajectory, e0=e0, bound=bound, last=row_of(first, 0)))
    done = 0
    while done < frames:
        k = min(sim.rows.capacity, frames - done)
        block = sim.advance_frames(k)
        for w, world in enumerate(worlds):
            if w in trouble:
                continue
            part = _world(block, w)
            if first_blow_up(part, world["e0"], world["bound"]) or first_escape(part, configs[w], world["last"]):
                trouble.add(w)
                continue
            world["trajectory"].append_block(part)
            world["last"] = row_of(part, k - 1)
        done += k
    written = {}
    with tempfile.TemporaryDirectory(prefix="rigid-batch-") as folder:
        for w, world in enumerate(worlds):
            if w not in trouble:
                path = Path(folder) / f"{w}.npz"
                world["trajectory"].save(path)
                written[w] = (path.read_bytes(), world["last"])
    return written, trouble


def _world(block: dict, w: int) -> dict:
    """World w's rows of a many-worlds block, shaped as a single run's (the world axis dropped)."""
    return {key: (value if key == "t" else value[:, w]) for key, value in block.items()}
