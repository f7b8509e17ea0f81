"""Run one version of a submission (variants.py) for a few frames and return its trajectory.

``run(variant, path, frames)`` writes the text to ``path`` (Taichi needs kernel
source in a file), imports it under a fresh module name with the stand-ins of
headless.py, and returns the body's state at each frame boundary: rows of
body_cm_position (3), body_rotation_quaternion (4), body_velocity (3),
body_angular_velocity (3), body_angular_momentum (3). The file's own window
loop runs the frames. A file whose loop does not run at import (none, or under
``if __name__ == "__main__":``) is driven by calling ``substep()``
``int(1/60 // dt)`` times a frame, with a note. Numpy's and Python's random
generators are seeded before each run, so bonus code that draws random numbers
draws the same ones in every version. A version with the same text as one
already run in this process is not run again: it would run the same (seeded, on
zeroed fields, fields.py), and compiling a version's kernels is most of its cost.
So the bonus note's run without the bonus terms reuses the run of all seven
TODOs, and in the warm-up (warm.py) the file's versions are the reference's. A
failed run is reused only for the same line origins, as its error names lines.
"""
import ast
import importlib.util
import random
import re
import sys
import traceback
import uuid
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import fields
from .headless import Recorder, State, StopRun

FRAMES = 30  # half a second at the handout's 16 substeps of 1 ms a frame
SNAPSHOT = ("body_cm_position", "body_rotation_quaternion", "body_velocity", "body_angular_velocity",
            "body_angular_momentum")
COLUMNS = {"body_cm_position": slice(0, 3), "body_rotation_quaternion": slice(3, 7),
           "body_velocity": slice(7, 10), "body_angular_velocity": slice(10, 13),
           "body_angular_momentum": slice(13, 16)}


class MissingField(BaseException):
    """The file lacks one of the handout's fields (BaseException: the file's own except clauses let it pass)."""


@dataclass
class Run:
    rows: np.ndarray | None  # (frames + 1, 16), or None when it failed
    error: str = ""  # why it failed, for the student (their line numbers)
    notes: list = field(default_factory=list)
    module: object = None


_DONE = {}  # (text, frames) -> (line origins, Run) of the versions run in this process


def run(variant, path: Path, frames: int = FRAMES) -> Run:
    key = (variant.text, frames)
    origin, done = _DONE.get(key, (None, None))
    if done is None or (done.rows is None and origin != variant.origin):
        done = _run(variant, Path(path), frames)
        _DONE[key] = (variant.origin, done)
    return done


def _run(variant, path: Path, frames: int) -> Run:
    path.write_text(variant.text, encoding="utf-8")
    fields.new_version()  # the fields of earlier versions, zeroed (fields.py)
    name = f"_original_{uuid.uuid4().hex[:8]}"
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    recorder = Recorder(frames, _snapshotter(module))
    State.recorder, State.init_calls = recorder, 0
    np.random.seed(0)
    random.seed(0)
    notes = []
    try:
        try:
            spec.loader.exec_module(module)
        except StopRun:
            pass
        if not recorder.rows:
            notes.append(_drive(module, recorder, variant.text))
    except MissingField as err:
        return Run(None, f"the file has no field {err.args[0]}; keep the handout's field names", notes, module)
    except SystemExit as err:
        if not recorder.complete:
            return Run(None, f"the file calls sys.exit() (or exit(), code {err.code}) before the simulation "
                             f"has run {frames} frames", notes, module)
    except BaseException as err:  # the file's own error: the caller says which TODOs it costs
        return Run(None, describe(err, variant, path), notes, module)
    finally:
        State.recorder = None
    if State.init_calls > 1:
        notes.append(f"the file calls ti.init {State.init_calls} times; the grader keeps one Taichi runtime "
                     f"and ignores the calls")
    return Run(np.array(recorder.rows), "", notes, module)


def _snapshotter(module):
    kernel, width = None, 0

    def snapshot():
        nonlocal kernel, width
        if kernel is None:
            fields = []
            for name in SNAPSHOT:
                if not hasattr(module, name):
                    raise MissingField(name)
                fields.append(getattr(module, name))
            kernel, width = snapshot_kernel(fields)
        out = np.zeros(width, np.float64)
        kernel(out)
        return out

    return snapshot


def snapshot_kernel(fields):
    """A kernel copying the 0-d vector fields ``fields`` into one float64 array, and its length."""
    import taichi as ti

    sizes = [int(f.n) for f in fields]
    offsets = [sum(sizes[:i]) for i in range(len(sizes))]

    @ti.kernel
    def copy(out: ti.types.ndarray(dtype=ti.f64, ndim=1)):
        for f in ti.static(range(len(fields))):
            value = ti.static(fields)[f][None]
            for c in ti.static(range(sizes[f])):
                out[offsets[f] + c] = value[c]

    return copy, sum(sizes)


def _drive(module, recorder, text) -> str:
    """No frame ran at import: call initial() (unless the file does at module level) and substep()."""
    substep, initial = getattr(module, "substep", None), getattr(module, "initial", None)
    dt = getattr(module, "dt", None)
    if not callable(substep) or not isinstance(dt, (int, float)) or dt <= 0:
        raise RuntimeError("the file runs no simulation at import and has no substep() and dt to run one")
    calls = {n.value.func.id for n in ast.parse(text).body if isinstance(n, ast.Expr)
             and isinstance(n.value, ast.Call) and isinstance(n.value.func, ast.Name)}
    if callable(initial) and "initial" not in calls:
        initial()
    per_frame = max(1, int(1 / 60 // dt))
    while recorder.running():
        for _ in range(per_frame):
            substep()
    return (f"the file runs no window loop at import; the grader called substep() {per_frame} times a frame "
            f"itself")


FILE_NAME = ["the submitted file"]  # the student's file name, for messages (child.py sets it)


def describe(err: BaseException, variant, path: Path) -> str:
    """One line: the error's type and last line, and the line of the student's file it points at (never
    a line of the version the grader wrote: its name and numbers mean nothing to the student)."""
    text = str(err)
    if isinstance(err, SyntaxError):  # TabError, IndentationError: the message names the version's file
        text = err.msg or type(err).__name__
        numbers = [err.lineno] if err.lineno and Path(err.filename or "").name == path.name else []
    else:
        numbers = [int(n) for n in re.findall(rf'File "{re.escape(str(path))}", line (\d+)', text)]
        numbers = numbers or [f.lineno for f in traceback.extract_tb(err.__traceback__)
                              if Path(f.filename).resolve() == path.resolve()]
    text = text.replace(str(path), FILE_NAME[0]).replace(path.name, FILE_NAME[0])
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    last = lines[-1] if lines else ""
    place = ""
    if numbers:
        line = variant.student_line(numbers[-1])
        place = f" ({FILE_NAME[0]}, line {line})" if line else " (in the grader's reference lines)"
    return f"{type(err).__name__}: {last}{place}"[:300] if last else f"{type(err).__name__}{place}"
