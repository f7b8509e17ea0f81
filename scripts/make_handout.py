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
rigid/ package without the TA's parts, the meshes and scenes of assets/,
requirements.txt and a README.txt saying how to run it. Unzipped anywhere, with
those requirements installed, ``python rigid_body_dynamic.py --check`` runs
(tests/test_grading_handout.py checks it in a fresh venv). Logic:
rigid.grading.bundle (what the zip holds and leaves out).
"""
import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rigid.errors import UserError  # noqa: E402
from rigid.grading import answers  # noqa: E402
from rigid.grading.bundle import make_bundle, write_handout  # noqa: E402


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
            count = make_bundle(solution_path, args.bundle, log)
            print(f"wrote {args.bundle} ({count} files under {Path(args.bundle).stem}/; unzip it and run "
                  f"python rigid_body_dynamic.py --check)")
            return 0
        data = write_handout(solution_path, args.out, log)
    except UserError as err:
        print(f"error: {err}", file=sys.stderr)
        return err.exit_code
    print(f"wrote {args.out} (TODOs 1-7 replaced by their hints and placeholders) and {data.name} beside it")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
