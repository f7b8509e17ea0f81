"""One run of a sweep, inside a worker process (the local pool's or a Ray worker).

A worker starts Taichi once, on its first task, and keeps it: a Simulator per run reuses the
kernels compiled for the first (rigid.engine.kernels caches them per process). The run goes
through the command line's own frame loop (``run_frames``, or ``record`` with ``--record``)
and its own NPZ writer, into a folder of the worker's; the bytes come back to the driver,
which alone writes into the sweep's folder. So a run's NPZ is byte for byte the file
``--headless --export`` writes for the same scene, wherever the worker runs.

A task is a plain dict (it crosses process and machine boundaries): ``name``, ``config``
(a validated SimConfig), ``frames``, ``record``, ``quick_compile``, ``units`` (the assignment
file whose TODO units run, or None for the repository's solution: a module cannot travel, its
path can).
"""
from __future__ import annotations

import contextlib
import io
import os
import signal
import tempfile
import time
from pathlib import Path

from ..errors import UserError

_units: dict = {}  # this process's TODO units by assignment file (None: the repository's solution)


def ignore_ctrl_c() -> None:
    """The local pool's initializer: a Ctrl-C in the terminal is the driver's to handle (it
    stops the workers itself), not each worker's."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _start(config, quick_compile: bool, units_file: str | None):
    """Taichi, once per process, on the scene's backend and precision; the units, once per file
    (their kernels compile once per units module)."""
    from ..engine.units import default_units, load_units
    from ..runtime import init_taichi

    init_taichi(config.arch, config.fp64, quick_compile=quick_compile)
    if units_file is not None and Path(units_file).resolve() == Path(default_units().__file__).resolve():
        units_file = None  # the repository's own file: the module every other caller shares
    if units_file not in _units:
        _units[units_file] = default_units() if units_file is None else load_units(units_file)
    return _units[units_file]


def run_task(task: dict) -> dict:
    """Simulate one run. Returns ``name``, ``status`` ("ok" or the failure's one line),
    ``energy`` (the last frame's total, J), ``seconds`` (wall, this run), ``npz`` and ``mp4``
    (bytes, or None), ``pid`` (the worker's process id). A batch task (``runs``: batch.py)
    returns ``{"batch": [each run's outcome]}``."""
    if "runs" in task:
        return _run_batch(task)
    began = time.perf_counter()
    out = dict(name=task["name"], status="ok", energy=None, npz=None, mp4=None, pid=os.getpid())
    try:
        with tempfile.TemporaryDirectory(prefix="rigid-sweep-") as folder, \
                contextlib.redirect_stderr(io.StringIO()):  # Taichi's start and "wrote ..." lines: the driver reports
            units = _start(task["config"], task["quick_compile"], task.get("units"))
            result = _simulate(task, units, Path(folder))
            if result.status == "done":
                out["npz"] = (Path(folder) / "run.npz").read_bytes()
                if task["record"]:
                    out["mp4"] = (Path(folder) / "run.mp4").read_bytes()
        row = result.last_row
        out["energy"] = float(row["kinetic_energy"] + row["potential_energy"]) if row else None
        if result.status != "done":
            out["status"] = result.message or result.status
    except UserError as err:
        out["status"] = str(err)
    except Exception as err:  # one run's failure is its row's status, never the sweep's end
        out["status"] = f"{type(err).__name__}: {err}"
    out["status"] = " ".join(str(out["status"]).split())  # one line, for the CSV
    out["seconds"] = time.perf_counter() - began
    return out


def _run_batch(task: dict) -> dict:
    """A batch's runs as worlds of one Simulator (batch.py); should the batch as a whole fail (a
    world's bodies that overlap, say), each run alone, so that each gets its own status line."""
    from .batch import run_batch

    try:
        with contextlib.redirect_stderr(io.StringIO()):
            units = _start(task["runs"][0]["config"], task["quick_compile"], task.get("units"))
            return run_batch(task, units, run_task)
    except Exception:  # (each run alone says what is wrong with it, or succeeds)
        return {"batch": [run_task(run) for run in task["runs"]]}


def _simulate(task: dict, units, folder: Path):
    from ..engine.simulator import Simulator
    from ..run.runner import run_frames

    config, frames = task["config"], task["frames"]
    sim = Simulator(config, units)
    if not task["record"]:
        return run_frames(sim, frames, export_path=folder / "run.npz")
    from ..view.camera import camera_spec
    from ..view.video import record

    camera = camera_spec(config.camera, "scene file: [camera]")
    return record(sim, folder / "run.mp4", frames, config.resolution, export_path=folder / "run.npz",
                  progress=False, camera=camera)
