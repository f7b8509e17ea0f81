"""Write the student handout from the solution, and the answers file its --check uses.

    python scripts/make_handout.py OUT.py [--solution rigid_body_dynamic.py]
    python scripts/make_handout.py --answers-only [--solution rigid_body_dynamic.py]

The handout's TODOs hold their hints and a placeholder: it runs as it is (the
body sits still) and holds no line of the solution's TODO code (checked before
writing). Beside it goes rigid_body_dynamic.check.npz, the reference's answers
for ``python rigid_body_dynamic.py --check`` (numbers from the grader's seeded
inputs, the same grade.py uses; prepared once per grader version, ~1 min the
first time). --answers-only writes only that file, beside the solution (the
repository keeps one, so the solution's --check works). Students keep the
repository's rigid/ package beside the handout (it imports rigid.engine.rotation and rigid.cli).
"""
import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rigid.run.atomic import atomic_output, check_output_path  # noqa: E402
from rigid.errors import UserError  # noqa: E402
from rigid.grading import answers  # noqa: E402
from rigid.grading.handout import make_handout, solution_lines  # noqa: E402


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="make_handout.py", description=__doc__.splitlines()[0])
    p.add_argument("out", nargs="?", metavar="OUT.py", help="the handout file to write")
    p.add_argument("--solution", default=str(ROOT / "rigid_body_dynamic.py"), metavar="FILE",
                   help="the solution with TODO markers (default: the repository's rigid_body_dynamic.py)")
    p.add_argument("--answers-only", action="store_true",
                   help=f"write only {answers.FILE_NAME}, beside the solution")
    args = p.parse_args(argv)
    if bool(args.out) == args.answers_only:
        p.error("give OUT.py, or --answers-only")
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
