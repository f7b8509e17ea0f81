"""Grade one submission: child processes, restarts after a crash or hang, one result.

The child checks every TODO in turn. If it dies or hangs, the stage it had
begun (sandbox.ChildRun.last_stage) names the culprit: that TODO loses its
points with the reason, and a fresh child grades the TODOs that remain, so a
TODO that loops forever costs that TODO only. A failure at import costs every
TODO (nothing can be graded without the file). The result follows DESIGN's
contract: {"submission", "total", "max_total", "todos": {"1": {"passed",
"points", "max", "message"}, ...}} plus "seconds", "output" (the child's
captured stdout and stderr, truncated), "format" ("project" or "original",
detected per submission unless Settings.format forces it) and "notes" (what the
TA should know: a mesh the submission lacks, a perturbation that could not be
applied, ti.init called twice).
"""
import json
import shutil
import signal
import tempfile
from dataclasses import dataclass, field
from pathlib import Path, PurePath

from .original.detect import detect
from .original.meshes import plan
from .sandbox import Limits, run_child
from .specs import TODOS

MAX_CHILDREN = 1 + len(TODOS) + 1  # the first, one per blamed TODO, one to split a trajectory run


@dataclass
class Settings:
    reference: Path  # the solution file
    expected: Path  # NPZ of the reference's answers (expected.py)
    warm_cache: Path | None  # a Taichi offline cache to start each child from (copied, never shared)
    points: dict = field(default_factory=lambda: {k: t.points for k, t in TODOS.items()})
    limits: Limits = field(default_factory=Limits)
    format: str = "auto"  # "project", "original" (the course's handout), or "auto": detect per submission
    warm_cache_original: Path | None = None  # the original format's, from the course's handout (original/warm.py)
    sandbox: object = None  # a box.Box each child runs in, or None (not contained)
    handout_folder: Path | None = None  # the course's handout's folder: its meshes stand in for missing ones


def grade_submission(name: str, source: bytes | None, settings: Settings, problem: str = "",
                     cache_out: Path | None = None, meshes: dict | None = None, file_name: str = "") -> dict:
    """Grade the file content ``source``; ``problem`` (no source) fails every TODO with that reason.

    ``cache_out``: copy the child's Taichi cache there afterwards (only for trusted code: the warm-up).
    ``meshes``: mesh files of the submission by name (a file in the original format may read one).
    ``file_name``: the file as the student named it, for messages (default: ``name``'s last part).
    """
    todos = {k: None for k in TODOS}  # k -> (passed, message) once decided
    seconds, output, notes = 0.0, "", []
    if source is not None and not problem:
        problem = _empty(source)
        source = None if problem else source
    if source is None:
        for k in todos:
            todos[k] = (False, f"TODO {k}: not graded — {problem}")
        return _result(name, todos, settings, seconds, output)
    text = source.decode("utf-8", errors="replace")
    fmt = settings.format if settings.format != "auto" else detect(text)
    with tempfile.TemporaryDirectory(prefix="rigid-grade-") as tmp:
        box = Path(tmp) / "box"
        box.mkdir()
        (box / "rigid_body_dynamic.py").write_bytes(source)
        extra = []
        if fmt == "original":
            files, renames, notes = plan(text, meshes, settings.handout_folder)
            for relative, data in files.items():
                (box / relative).parent.mkdir(parents=True, exist_ok=True)
                (box / relative).write_bytes(data)
            extra = ["--format", "original", f"--renames={json.dumps(renames)}",
                     f"--file-name={file_name or PurePath(name).name}"]
        warm = settings.warm_cache_original if fmt == "original" and settings.warm_cache_original else \
            settings.warm_cache
        if warm and warm.is_dir():
            shutil.copytree(warm, box / ".taichi-cache")
        per_todo = False
        for attempt in range(MAX_CHILDREN):
            remaining = [k for k, v in todos.items() if v is None]
            if not remaining:
                break
            args = ["--submission", box / "rigid_body_dynamic.py", "--reference", settings.reference,
                    "--expected", settings.expected, "--todos", ",".join(map(str, remaining)), *extra]
            args += ["--write-cache"] if cache_out is not None else []  # only a trusted run's cache is kept
            run = run_child(args + (["--per-todo-trajectories"] if per_todo else []), box,
                            Path(tmp) / f"events{attempt}.jsonl", settings.limits, settings.sandbox,
                            (settings.reference, settings.expected))
            seconds += run.seconds
            output = "".join(line for line in run.output.splitlines(keepends=True)
                             if not line.startswith("[Taichi] Starting on arch"))
            notes += [e["message"] for e in run.events if e.get("event") == "note" and e["message"] not in notes]
            decided, per_todo = _interpret(run, remaining, settings.limits, per_todo, fmt)
            todos.update(decided)
        if cache_out is not None and (box / ".taichi-cache").is_dir():
            shutil.copytree(box / ".taichi-cache", cache_out, dirs_exist_ok=True)
        for k, v in todos.items():
            if v is None:
                todos[k] = (False, f"TODO {k}: not graded — the submission crashed the grader too often")
    return _result(name, todos, settings, seconds, output, fmt, notes)


def _empty(source: bytes) -> str:
    """Why a file holds nothing to grade ('' when it holds code)."""
    lines = [line.strip() for line in source.decode("utf-8", errors="replace").splitlines()]
    if not any(lines):
        return "the file is empty"
    if all(not line or line.startswith("#") for line in lines):
        return "the file holds only comments, no code"
    return ""


def _interpret(run, remaining, limits, per_todo, fmt="project"):
    """(decided TODOs {k: (passed, message)}, per_todo flag for the next child) from one child run."""
    decided = {}
    direct = {e["todo"]: e for e in run.events if e.get("event") == "direct"}
    traj = {}
    for e in run.events:
        if e.get("event") == "trajectory":
            for k in e["todos"]:
                traj[k] = e
    failed_import = next((e for e in run.events if e.get("event") == "import_failed"), None)
    if failed_import:
        return {k: (False, f"TODO {k}: not graded — {failed_import['message']}") for k in remaining}, per_todo
    if run.done or run.last_stage.get("phase") == "bonus":  # "bonus": a note after every TODO was decided
        for k in remaining:
            d, t = direct.get(k), traj.get(k)
            if d is None:
                decided[k] = (False, f"TODO {k}: not graded (the grader skipped it)")
            elif not d["passed"]:
                decided[k] = (False, d["message"])
            elif t is None:
                decided[k] = (False, f"TODO {k}: not graded — the trajectory check did not run")
            elif t["passed"]:
                decided[k] = (True, f"{d['message']}; {t['message']}")
            else:
                decided[k] = (False, f"TODO {k}: {t['message']}")
        return decided, per_todo
    # The child died or hung: blame the stage it had begun.
    stage, why = run.last_stage, stop_reason(run, limits)
    if stage["phase"] == "import":
        return {k: (False, f"TODO {k}: not graded — the file could not be imported: it {why}")
                for k in remaining}, per_todo
    if stage["phase"] == "setup":
        return {k: (False, f"TODO {k}: not graded — the grading process failed after importing the file: it {why}")
                for k in remaining}, per_todo
    if stage["phase"] == "direct":
        k = stage["todo"]
        who = TODOS[k].unit if fmt == "project" else f"the code under '# TODO {k}:'"
        decided[k] = (False, f"TODO {k}: {who} {why}; the other TODOs were graded in a fresh process")
        return decided, per_todo
    culprits = stage.get("todos", [])
    if len(culprits) == 1:
        k = culprits[0]
        decided[k] = (False, f"TODO {k}: right on single calls, but the simulation with it {why}")
        return decided, True
    if not culprits:  # the reference run itself: not the submission's fault
        return {k: (False, f"TODO {k}: not graded — the reference simulation failed ({why})")
                for k in remaining}, per_todo
    return decided, True  # a joint run died: run each unit alone next time


def stop_reason(run, limits) -> str:
    """Why a child ended without finishing, as the end of a sentence about the submission."""
    if run.timed_out:
        return f"did not finish within {limits.stage_seconds:g} s (an endless loop?)"
    text = run.output
    if any(s in text for s in ("MemoryError", "bad_alloc", "Cannot allocate memory", "out of memory")):
        return f"ran out of memory (limit {limits.memory_mb} MB)"
    rc = run.returncode
    if rc is not None and rc < 0:
        sig = signal.Signals(-rc)
        if sig == signal.SIGXFSZ:
            return f"wrote a file larger than {limits.file_mb} MB"
        return f"crashed the grading process ({sig.name})"
    return f"ended the grading process early (exit code {rc}: os._exit or a fatal error)"


def _result(name, todos, settings, seconds, output, fmt="project", notes=()) -> dict:
    out = {}
    for k, (passed, message) in todos.items():
        max_points = float(settings.points[k])
        out[str(k)] = dict(passed=bool(passed), points=max_points if passed else 0.0, max=max_points,
                           message=message)
    total = sum(v["points"] for v in out.values())
    return dict(submission=name, total=total, max_total=float(sum(settings.points.values())), todos=out,
                seconds=round(seconds, 2), output=output, format=fmt, notes=list(notes))
