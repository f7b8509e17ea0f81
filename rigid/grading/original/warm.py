"""A warm cache for the original format, from the course's handout (``grade.py --original-handout FILE``).

A file in the original format compiles its own kernels for each version the grader runs
(runner.py): the reference lines in every TODO with the file's parameters and with others,
the student's lines, the harness. The versions with reference lines (and a student's TODO
written as the reference writes it) compile to the same kernels for every student who kept
the handout's given code, so Taichi's offline cache can serve them, but only from trusted
code: the cache holds machine code, and a submission's child writes into a private copy.

The TA's handout (unsolved, as given to students) is trusted: ``prepare_original`` fills its
TODOs with the reference lines, grades that like a submission (it must score full marks: the
handout is then one the grader reads right) and keeps the kernels compiled on the way, beside
the reference's cache, once per grader version and handout. The version graded is
velocity-first (the 2023 hint's order), so its reference runs are those of a velocity-first
file, whose first version (the harness, child.likely_form) has its TODO 5 in that order too;
a position-first file's reference runs compile afresh. A submission of the original format
starts from that cache: 14 such files with --jobs 2 on 2 cores (a noisy machine), 132 and
105 CPU-s without it, 80-96 with it (the first run's one grading included).
"""
from __future__ import annotations

import hashlib
import shutil
import tempfile
from dataclasses import replace
from pathlib import Path

from ...errors import UserError
from ..grade_submission import grade_submission
from .detect import detect
from .regions import RegionError
from .variants import FileModel

WARM_FORM = "velocity-first"  # the order of TODO 5 in the version graded (see above)


def solved_version(handout_text: str, form: str = WARM_FORM) -> str:
    """The handout with the reference lines in every TODO, TODO 5 in order ``form`` (expected.FORMS)."""
    return FileModel(handout_text).build(form=form).text


def prepare_original(settings, handout: Path, log=print):
    """``settings`` (batch.prepare's) with the original format's warm cache from ``handout``."""
    try:
        text = Path(handout).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        raise UserError(f"--original-handout {handout}: cannot read it ({err}); give the course's handout file")
    if detect(text) != "original":
        raise UserError(f"--original-handout {handout}: not a file in the course's original handout format "
                        f"(global fields and kernels initial() and substep()); give the course's handout")
    try:
        solved = solved_version(text)
    except RegionError as err:
        raise UserError(f"--original-handout {handout}: {err}")
    stamp = hashlib.sha256(text.encode()).hexdigest()[:12]
    folder = settings.warm_cache.parent / f"original-{stamp}"
    if (folder / "ready").exists():
        return replace(settings, warm_cache_original=folder / "taichi")
    log(f"compiling the kernels of the original handout {handout} (once per grader version) ...")
    tmp = Path(tempfile.mkdtemp(prefix=".prepare-original-", dir=folder.parent))
    try:
        # Trusted code, compiled cold: a short --timeout meant for submissions must not stop it (batch._prepare).
        limits = replace(settings.limits, stage_seconds=max(settings.limits.stage_seconds, 600.0))
        trusted = replace(settings, format="original", limits=limits, handout_folder=Path(handout).resolve().parent)
        result = grade_submission("handout", solved.encode(), trusted, cache_out=tmp / "taichi")
        failed = [t["message"] for t in result["todos"].values() if not t["passed"]]
        if failed:
            raise UserError(f"--original-handout {handout}: with the reference lines in its TODOs it does not score "
                            f"full marks, so it is not a handout the grader reads right: " + "; ".join(failed))
        (tmp / "ready").write_text(f"{handout}\n")
        shutil.rmtree(folder, ignore_errors=True)
        tmp.replace(folder)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return replace(settings, warm_cache_original=folder / "taichi")
