"""``rigid.sweep``: plan the runs, check everything, resume, run them, write what comes back.

Everything a user can get wrong (the scene, a --vary, --seeds, --frames, --workers, --ray, the
output folder) is checked before the first worker starts, each as one line (UserError). A run
that fails is a row of index.csv whose status is the failure's line; the others go on.
"""
from __future__ import annotations

import contextlib
import os
import sys
import time
from pathlib import Path

from ..config import SimConfig, load_scene
from ..errors import UserError
from .batch import batchable, batches
from .folder import SweepFolder
from .vary import as_varies, plan_runs

INDEX_EVERY = 1.0  # s: index.csv is rewritten at most this often while runs finish (and at the end)


def default_workers() -> int:
    """One worker per CPU this process may use."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def sweep(scene, vary=(), frames: int = None, out=None, seeds: int = 1, workers: int | None = None,
          ray: str | None = None, record: bool = False, units=None, log=sys.stderr) -> list[dict]:
    """Run ``scene`` (a scene TOML's path, or a SimConfig) once for every combination of the
    ``vary`` values (``{"restitution": [0.2, 0.5], "dt": "1e-3:2e-3:3"}`` or
    ``["restitution=0.2,0.5", ...]``) and each of ``seeds`` seeds, ``frames`` frames each, into
    the folder ``out``: ``index.csv``, ``runs/<run>.npz`` (and ``.mp4`` with ``record``).
    ``workers`` processes (default one per CPU), or a Ray cluster (``ray="local"`` or an
    address). ``units``: the assignment file (or its module) whose TODO units run; default the
    repository's solution. Runs finished in ``out`` before are kept. Returns index.csv's rows as
    dicts of numbers and words (None for an empty cell)."""
    base, scene_text = _scene(scene)
    if not isinstance(frames, int) or isinstance(frames, bool) or frames < 1:
        raise UserError(f"--frames {frames}: give every run's frame count, a whole number from 1, e.g. --frames 60")
    if out is None:
        raise UserError("--out is missing: name the folder for index.csv and runs/, e.g. --out sweep1")
    workers = default_workers() if workers is None else workers
    if not isinstance(workers, int) or isinstance(workers, bool) or workers < 1:
        raise UserError(f"--workers {workers}: use a whole number of processes, 1 or more")
    units_file = _units_file(units)
    varies = as_varies(vary)
    runs = plan_runs(base, varies, seeds)
    _check_runs(base, runs)
    if ray:
        from .cluster import check_ray

        check_ray(ray)
    folder = SweepFolder(out, runs, [v.key for v in varies], scene_text, frames, record)
    rows = folder.check()  # nothing is written before here, nor before Ray has started or joined
    tasks = [dict(name=r.name, config=r.config, frames=frames, record=record, units=units_file,
                  quick_compile=os.environ.get("RIGID_QUICK_COMPILE") == "1")  # rigid.runtime's, for every worker
             for r in runs if r.name not in rows]
    if batchable(base, [t["config"] for t in tasks], record):  # runs that differ only in their bodies' starts
        tasks = batches(tasks, workers)
    # A local Ray cluster of no more CPUs than tasks: Ray starts a worker process per CPU, whether
    # a task comes to it or not (the local pool already starts no more workers than tasks).
    with _cluster(ray, min(workers, len(tasks)), bool(tasks)) as cluster:
        folder.prepare()
        _run(folder, runs, rows, tasks, frames, workers, cluster, log)
    return [_typed(r, rows.get(r.name) or folder.row(r)) for r in runs]


def _typed(run, row: dict) -> dict:
    """A row of index.csv for Python: the varied values and the seed as the run used them, the
    energy and the time as floats (None where empty), whether the row was written now or read back."""
    def number(text):
        return float(text) if text not in ("", None) else None

    return {"run": run.name, **run.values, "seed": run.seed, "status": row["status"],
            "final_energy": number(row["final_energy"]), "wall_seconds": number(row["wall_seconds"])}


def _cluster(ray: str | None, workers: int, needed: bool):
    """Ray's session where --ray is given and there is something to run."""
    if not (ray and needed):
        return contextlib.nullcontext()
    from .cluster import ray_session

    return ray_session(ray, workers)


def _run(folder, runs, rows: dict, tasks: list[dict], frames: int, workers: int, cluster, log) -> None:
    """Run ``tasks`` (single runs, or batches of runs as worlds: batch.py) on the pool or on Ray
    (``cluster``: the ray module), writing each run's files and its row of ``rows`` as it finishes,
    and index.csv at most every INDEX_EVERY s and at the end."""
    by_name = {r.name: r for r in runs}
    used = min(workers, max(1, len(tasks)))
    where = "Ray" if cluster else f"{used} worker process{'es' if used > 1 else ''}"
    batched = sum(len(t["runs"]) for t in tasks if "runs" in t)
    count = batched or len(tasks)
    if batched:  # (rigid.engine.worlds: no contact across worlds, each world's rows its run's alone)
        where += f", as {len(tasks)} batch{'es' if len(tasks) > 1 else ''} of worlds of one simulator each"
    print(f"sweep: {_runs(len(runs))} of {frames} frames into {folder.out} ({len(runs) - count} kept from "
          f"before, {count} to run on {where})", file=log, flush=True)
    began, last_index = time.perf_counter(), [0.0]

    def on_result(task, outcome):
        """A task's outcome, or a batch's: each of its runs' (all failed alike if the batch's worker died)."""
        if "runs" not in task:
            return on_run(task, outcome)
        for k, run in enumerate(task["runs"]):
            on_run(run, outcome["batch"][k] if "batch" in outcome else dict(outcome, name=run["name"]))

    def on_run(task, outcome):
        run = by_name[task["name"]]
        status = outcome["status"]
        if status == "ok":
            folder.write_run(run.name, outcome["npz"], outcome["mp4"])
        else:
            shown = ", ".join([*(f"{k}={v}" for k, v in run.values.items()), f"seed={run.seed}"])
            print(f"{run.name} ({shown}): {status}", file=log, flush=True)
        rows[run.name] = folder.row(run, status, outcome["energy"], outcome["seconds"])
        if time.perf_counter() - last_index[0] > INDEX_EVERY:
            folder.write_index(rows)
            last_index[0] = time.perf_counter()

    try:
        if tasks and cluster:
            from .cluster import run_ray

            run_ray(cluster, tasks, on_result)
        elif tasks:
            from .pool import run_local

            run_local(tasks, workers, on_result)
    finally:
        folder.write_index(rows)  # after Ctrl-C too: what finished is kept for the next start
        folder.remove_partials()
    failed = sum(1 for r in runs if rows.get(r.name, {}).get("status") != "ok")
    print(f"sweep: {len(runs) - failed} of {_runs(len(runs))} ok in {time.perf_counter() - began:.1f} s"
          + (f"; {failed} failed (their status is in {folder.out / 'index.csv'}): run the same command again "
             f"to retry them" if failed else f"; wrote {folder.out / 'index.csv'}"), file=log, flush=True)


def _units_file(units) -> str | None:
    """The assignment file of ``units`` (a path or a loaded module), checked now; None: the solution."""
    if units is None:
        return None
    path = Path(getattr(units, "__file__", None) or units)
    if not path.is_file():
        raise UserError(f"assignment file {path} not found; give the path of a rigid_body_dynamic.py")
    return str(path.resolve())


def _runs(n: int) -> str:
    return f"{n} run{'s' if n != 1 else ''}"


def _scene(scene) -> tuple[SimConfig, str]:
    """The base config and the text that identifies it (a resumed sweep must have the same)."""
    if isinstance(scene, SimConfig):
        return scene.validate(), repr(scene)
    if scene is None:
        raise UserError("a sweep needs a scene file, e.g. python -m rigid sweep assets/scenes/thrown_sphere.toml ...")
    path = Path(scene)
    config = SimConfig(**load_scene(path)).validate()  # one line for a missing or bad file
    return config, path.read_text()


def _check_runs(base: SimConfig, runs) -> None:
    """What the command line checks before Taichi starts: float32 against each run's Δt, and the
    scene's meshes and placement (the base scene's: a varied key's effect is each run's own)."""
    from ..bodies.placement import check_inside_box, scene_bodies
    from ..run.precision import float32_problem

    for run in runs:
        problem = float32_problem(run.config)
        if problem:
            shown = ", ".join(f"{k}={v}" for k, v in run.values.items())
            raise UserError(f"--vary: the run with {shown}: {problem}" if shown else problem)
    bodies = scene_bodies(base)
    if base.walls:
        check_inside_box(bodies, base.floor, base.wall, use_radius=True)
