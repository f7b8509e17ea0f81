"""What a TA hands out: the student's handout with its answers file beside it, or one zip of all a student needs.

The handout (handout.py's ``make_handout``) replaces the solution's TODO code by
hints and placeholders; ``checked_handout`` refuses one that would still show a
line of that code. Beside it goes the answers file (answers.py) that its
``python rigid_body_dynamic.py --check`` compares with: the reference's numbers
on the grader's seeded inputs, never code.

The zip (``write_bundle``) holds, under a folder named after it, everything a
student needs: the handout as rigid_body_dynamic.py, its answers file, the
rigid/ package without the TA's parts (BUNDLE_LEAVES_OUT: the grader of the
original format with its reference lines, the benchmarks, the report, and this
module), the meshes and scenes of assets/, requirements.txt (the package's
dependencies, from pyproject.toml) and a README.txt (STUDENT_README) saying how
to run it. Unzipped anywhere, with those requirements installed, ``python
rigid_body_dynamic.py --check`` runs with the zip's own rigid/
(tests/test_grading_handout.py checks it in a fresh venv). Its entries carry a
fixed date, so the same files give the same bytes.

Run by scripts/make_handout.py from a checkout: it reads the repository's
pyproject.toml, rigid/ and assets/.
"""
import re
import zipfile
from pathlib import Path

from ..errors import UserError
from ..run.atomic import atomic_output, check_output_path
from . import answers
from .handout import make_handout, solution_lines

ROOT = Path(__file__).resolve().parents[2]
BUNDLE_LEAVES_OUT = ("rigid/grading/original/", "rigid/bench/", "rigid/report/", "rigid/grading/bundle.py")
STUDENT_README = """Assignment 3: rigid body simulation

    pip install -r requirements.txt            # Python 3.9-3.13
    python rigid_body_dynamic.py --check       # the grader's checks of your 7 TODOs
    python rigid_body_dynamic.py               # a window (needs a display and Vulkan)
    python rigid_body_dynamic.py --record out.mp4 --frames 300   # a video, no display needed
    python rigid_body_dynamic.py --help        # every option

Write your code between each '# TODO k:' line and its '# END TODO k' line in
rigid_body_dynamic.py; keep rigid/ and rigid_body_dynamic.check.npz beside it.
"""


def checked_handout(solution: str) -> str:
    """The handout of ``solution``; UserError if it would show a line of the solution's TODO code."""
    handout = make_handout(solution)
    leaked = solution_lines(solution) & {line.strip() for line in handout.splitlines()}
    if leaked:
        raise UserError(f"the handout would show solution lines {sorted(leaked)}; change the placeholders")
    return handout


def write_handout(solution_path: Path, out, log=print) -> Path:
    """Write the handout to ``out`` (its folder created if missing) and the answers file beside it; its path."""
    Path(out).resolve().parent.mkdir(parents=True, exist_ok=True)  # handout/ in a fresh clone
    check_output_path(out, (".py",))
    if Path(out).resolve() == solution_path.resolve():
        raise UserError(f"{out} is the solution itself; write the handout elsewhere")
    handout = checked_handout(solution_path.read_text(encoding="utf-8"))
    data = Path(out).resolve().with_name(answers.FILE_NAME)
    answers.make(solution_path, data, log)
    with atomic_output(out) as tmp:
        tmp.write_text(handout, encoding="utf-8")
    return data


def make_bundle(solution_path: Path, out, log=print) -> int:
    """Write the zip ``out`` (its folder created if missing) for ``solution_path``; the number of files in it."""
    Path(out).resolve().parent.mkdir(parents=True, exist_ok=True)
    check_output_path(out, (".zip",))
    handout = checked_handout(solution_path.read_text(encoding="utf-8"))
    data = Path(out).resolve().with_name(f".{Path(out).stem}.{answers.FILE_NAME}")
    try:
        answers.make(solution_path, data, log)
        return write_bundle(Path(out), handout, data)
    finally:
        data.unlink(missing_ok=True)


def requirements() -> str:
    """The package's dependencies, from pyproject.toml."""
    text = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    block = re.search(r"^dependencies\s*=\s*\[(.*?)^\]", text, re.MULTILINE | re.DOTALL)
    names = re.findall(r'"([^"]+)"', block[1]) if block else ["taichi>=1.7,<1.8", "numpy"]
    return "\n".join(names) + "\n"


def bundle_files(handout: str, answers_path: Path) -> dict:
    """{name in the zip (under its folder): bytes} of everything a student needs."""
    files = {"rigid_body_dynamic.py": handout.encode("utf-8"), answers.FILE_NAME: answers_path.read_bytes(),
             "requirements.txt": requirements().encode(), "README.txt": STUDENT_README.encode()}
    for path in sorted((ROOT / "rigid").rglob("*")):
        name = path.relative_to(ROOT).as_posix()
        if (path.is_file() and "__pycache__" not in path.parts and path.suffix in (".py", ".npz", ".json", ".toml")
                and not name.startswith(BUNDLE_LEAVES_OUT)):
            files[name] = path.read_bytes()
    for path in sorted((ROOT / "assets").rglob("*")):
        if path.is_file() and path.suffix.lower() in (".obj", ".stl", ".ply", ".off", ".glb", ".toml"):
            files[path.relative_to(ROOT).as_posix()] = path.read_bytes()
    return files


def write_bundle(out: Path, handout: str, answers_path: Path) -> int:
    """Write the zip of bundle_files under a folder named after ``out``; the number of files in it."""
    folder = out.stem
    files = bundle_files(handout, answers_path)
    with atomic_output(out) as tmp, zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in files.items():
            info = zipfile.ZipInfo(f"{folder}/{name}", date_time=(2024, 1, 1, 0, 0, 0))  # the same bytes each time
            info.compress_type, info.external_attr = zipfile.ZIP_DEFLATED, 0o644 << 16
            z.writestr(info, data)
    return len(files)
