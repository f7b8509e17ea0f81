"""Grade many submissions in parallel, after preparing the reference once.

``prepare(reference, limits, cache_root)`` runs, once per version of the
grader, engine, reference and Taichi (a hash of them all names the folder):
a trusted child computes the reference's answers (expected.py), then the
reference itself is graded like a submission as a self-check (it must score
full marks, or the grader refuses to grade: a bug in the engine or the grader
must not cost students points). The Taichi kernels compiled on the way form
a warm cache that each child starts from (a private copy).
``grade_batch`` then grades each submission in its own child(ren),
``jobs`` at a time.
"""
import fcntl
import hashlib
import os
import platform
import shutil
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from ..config import REPO_ROOT
from ..errors import UserError
from .grade_submission import Settings, grade_submission, stop_reason
from .original.warm import prepare_original
from .sandbox import Limits, run_child

KEEP_VERSIONS = 4


def default_cache_root() -> Path:
    return Path.home() / ".cache" / "rigid-body-taichi" / "grader"


def version_stamp(reference: Path) -> str:
    """Hash of everything the reference's answers and compiled kernels depend on."""
    from importlib.metadata import version  # Taichi's version without importing Taichi in the parent

    h = hashlib.sha256()
    h.update(reference.read_bytes())
    for path in sorted((REPO_ROOT / "rigid").rglob("*.py")):
        h.update(path.relative_to(REPO_ROOT).as_posix().encode())
        h.update(path.read_bytes())
    h.update(f"{sys.version} {platform.machine()} {version('taichi')}".encode())
    return h.hexdigest()[:16]


def prepare(reference: Path, limits: Limits, cache_root: Path, log=print,
            original_handout: Path | None = None) -> Settings:
    """Settings for grading against ``reference``; computes and self-checks it if not done yet,
    and with ``original_handout`` (the course's handout file) the original format's warm cache
    (original/warm.py).

    A lock file makes a second batch started meanwhile wait for the first one's preparation.
    """
    folder = cache_root / version_stamp(reference)
    settings = Settings(reference, folder / "expected.npz", folder / "taichi", limits=limits)
    if (folder / "ready").exists() and original_handout is None:
        return settings
    try:
        cache_root.mkdir(parents=True, exist_ok=True)
        lock = open(cache_root / ".lock", "w")
    except OSError as err:
        raise UserError(f"cache folder {cache_root} is not writable ({err.strerror}); pick one with --cache-dir")
    with lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (folder / "ready").exists():
            log(f"preparing the reference answers from {reference} (once per grader version) ...")
            _prepare(reference, limits, cache_root, folder)
            _forget_old(cache_root, keep=KEEP_VERSIONS)
        if original_handout is not None:
            settings = prepare_original(settings, original_handout, log)
    return settings


def _prepare(reference: Path, limits: Limits, cache_root: Path, folder: Path) -> None:
    # Trusted code, compiled cold: a short --timeout meant for submissions must not stop it.
    limits = Limits(max(limits.stage_seconds, 600.0), max(limits.memory_mb, 4096), limits.file_mb)
    tmp = Path(tempfile.mkdtemp(prefix=".prepare-", dir=cache_root))
    try:
        box = tmp / "box"
        box.mkdir()
        run = run_child(["--make-expected", tmp / "expected.npz", "--reference", reference], box,
                        tmp / "events.jsonl", limits)
        if not run.done:
            raise UserError(f"computing the reference's answers failed: it {stop_reason(run, limits)}:\n"
                            f"{run.output}")
        shutil.copytree(box / ".taichi-cache", tmp / "taichi", dirs_exist_ok=True)
        check = Settings(reference, tmp / "expected.npz", tmp / "taichi", limits=limits)
        result = grade_submission("reference", reference.read_bytes(), check, cache_out=tmp / "taichi")
        failed = [t["message"] for t in result["todos"].values() if not t["passed"]]
        if failed:
            raise UserError("the reference solution fails the grader's own checks (a bug in the engine or "
                            "the grader; nothing was graded):\n  " + "\n  ".join(failed))
        shutil.rmtree(box, ignore_errors=True)
        (tmp / "ready").write_text(f"{reference}\n")
        os.replace(tmp, folder)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _forget_old(cache_root: Path, keep: int) -> None:
    """Remove all but the ``keep`` most recently prepared versions (each ~2 MB)."""
    ready = sorted((p for p in cache_root.iterdir() if (p / "ready").exists()),
                   key=lambda p: (p / "ready").stat().st_mtime, reverse=True)
    for old in ready[keep:]:
        shutil.rmtree(old, ignore_errors=True)


def grade_batch(submissions, settings: Settings, jobs: int = 1, on_result=None) -> list:
    """Results (grade_submission's dicts) in the order of ``submissions``; on_result(i, result) as each ends."""
    def one(i, sub):
        try:
            source, problem = sub.read()
            result = grade_submission(sub.name, source, settings, problem, meshes=sub.meshes(), file_name=sub.file_name)
        except Exception as err:  # the grader's own trouble (a full disk ...): this one fails, the batch goes on
            result = grade_submission(sub.name, None, settings, f"internal error of the grader: {err!r}")
        result["student"] = dict(zip(("uid", "name"), sub.student))
        if on_result:
            on_result(i, result)
        return result

    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        return list(pool.map(one, range(len(submissions)), submissions))
