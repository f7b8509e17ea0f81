"""Write the student handout from the solution, and the answers file its --check uses.

    python scripts/make_handout.py OUT.py [--solution rigid_body_dynamic.py]
    python scripts/make_handout.py --bundle OUT.zip [--solution rigid_body_dynamic.py]
    python scripts/make_handout.py --answers-only [--solution rigid_body_dynamic.py]

The handout's TODOs hold their hints and a placeholder: it runs as it is (the
body sits still) and holds no line of the solution's TODO code (checked before
writing). Beside it goes rigid_body_dynamic.check.npz, the reference's answers
for ``python rigid_body_dynamic.py --check`` (numbers from the grader's seeded
inputs, the same grade.py uses; prepared once per grader version, ~1 min the
first time). --answers-only writes only that file, beside the solution (the
repository keeps one, so the solution's --check works). The handout imports
the repository's rigid/ package (rigid.engine.rotation, rigid.cli, and
rigid.grading for --check). OUT.py's folder is created if it is missing.

--bundle OUT.zip writes everything a student needs in one zip, under a folder
named after it: the handout as rigid_body_dynamic.py, its answers file, the
rigid/ package without the TA's parts (BUNDLE_LEAVES_OUT: the grader of the
original format with its reference lines, the benchmarks, the report), the
meshes and scenes of assets/, requirements.txt (the package's dependencies)
and a README.txt saying how to run it. Unzipped anywhere, with those
requirements installed, ``python rigid_body_dynamic.py --check`` runs
(tests/test_grading_handout.py checks it in a fresh venv).
"""
import argparse
import re
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rigid.run.atomic import atomic_output, check_output_path  # noqa: E402
from rigid.errors import UserError  # noqa: E402
from rigid.grading import answers  # noqa: E402
from rigid.grading.handout import make_handout, solution_lines  # noqa: E402


BUNDLE_LEAVES_OUT = ("rigid/grading/original/", "rigid/bench/", "rigid/report/")
STUDENT_README = """Assignment 3: rigid body simulation

    pip install -r requirements.txt            # Python 3.9-3.13
    python rigid_body_dynamic.py --check       # the grader's checks of your 7 TODOs
    python rigid_body_dynamic.py               # a window (needs a display and Vulkan)
    python rigid_body_dynamic.py --record out.mp4 --frames 300   # a video, no display needed
    python rigid_body_dynamic.py --help        # every option

Write your code between each '# TODO k:' line and its '# END TODO k' line in
rigid_body_dynamic.py; keep rigid/ and rigid_body_dynamic.check.npz beside it.
"""


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
    folder = out.stem
    files = bundle_files(handout, answers_path)
    with atomic_output(out) as tmp, zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in files.items():
            info = zipfile.ZipInfo(f"{folder}/{name}", date_time=(2024, 1, 1, 0, 0, 0))  # the same bytes each time
            info.compress_type, info.external_attr = zipfile.ZIP_DEFLATED, 0o644 << 16
            z.writestr(info, data)
    return len(files)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="make_handout.py", description=__doc__.splitlines()[0])
    p.add_argument("out", nargs="?", metavar="OUT.py", help="the handout file to write")
    p.add_argument("--solution", default=str(ROOT / "rigid_body_dynamic.py"), metavar="FILE",
                   help="the solution with TODO markers (default: the repository's rigid_body_dynamic.py)")
    p.add_argument("--answers-only", action="store_true",
                   help=f"write only {answers.FILE_NAME}, beside the solution")
    p.add_argument("--bundle", metavar="OUT.zip",
                   help="write a zip of what a student needs: the handout, its answers file, rigid/ without the "
                        "TA's parts, the assets, requirements.txt and a README")
    args = p.parse_args(argv)
    if sum(map(bool, (args.out, args.answers_only, args.bundle))) != 1:
        p.error("give OUT.py, --bundle OUT.zip, or --answers-only")
    try:
        solution_path = Path(args.solution)
        if not solution_path.is_file():
            raise UserError(f"solution {solution_path} not found")
        log = lambda m: print(m, file=sys.stderr)  # noqa: E731
        if args.answers_only:
            out = solution_path.resolve().with_name(answers.FILE_NAME)
            answers.make(solution_path, out, log)
            print(f"wrote {out}")
            return 0
        if args.bundle:
            Path(args.bundle).resolve().parent.mkdir(parents=True, exist_ok=True)
            check_output_path(args.bundle, (".zip",))
            solution = solution_path.read_text(encoding="utf-8")
            handout = make_handout(solution)
            leaked = solution_lines(solution) & {line.strip() for line in handout.splitlines()}
            if leaked:
                raise UserError(f"the handout would show solution lines {sorted(leaked)}; change the placeholders")
            data = Path(args.bundle).resolve().with_name(f".{Path(args.bundle).stem}.{answers.FILE_NAME}")
            try:
                answers.make(solution_path, data, log)
                count = write_bundle(Path(args.bundle), handout, data)
            finally:
                data.unlink(missing_ok=True)
            print(f"wrote {args.bundle} ({count} files under {Path(args.bundle).stem}/; unzip it and run "
                  f"python rigid_body_dynamic.py --check)")
            return 0
        Path(args.out).resolve().parent.mkdir(parents=True, exist_ok=True)  # handout/ in a fresh clone
        check_output_path(args.out, (".py",))
        if Path(args.out).resolve() == solution_path.resolve():
            raise UserError(f"{args.out} is the solution itself; write the handout elsewhere")
        solution = solution_path.read_text(encoding="utf-8")
        handout = make_handout(solution)
        leaked = solution_lines(solution) & {line.strip() for line in handout.splitlines()}
        if leaked:
            raise UserError(f"the handout would show solution lines {sorted(leaked)}; change the placeholders")
        data = Path(args.out).resolve().with_name(answers.FILE_NAME)
        answers.make(solution_path, data, log)
        with atomic_output(args.out) as tmp:
            tmp.write_text(handout, encoding="utf-8")
    except UserError as err:
        print(f"error: {err}", file=sys.stderr)
        return err.exit_code
    print(f"wrote {args.out} (TODOs 1-7 replaced by their hints and placeholders) and {data.name} beside it")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
