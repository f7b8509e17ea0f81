"""Write the student handout from the solution: each TODO's code becomes its hints and a placeholder.

    python scripts/make_handout.py OUT.py [--solution rigid_body_dynamic.py]

The handout runs as it is (the body sits still) and holds no line of the
solution's TODO code (checked before writing). Students keep the repository's
rigid/ package beside it (the file imports rigid.engine.rotation and rigid.cli).
"""
import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from rigid.run.atomic import atomic_output, check_output_path  # noqa: E402
from rigid.errors import UserError  # noqa: E402
from rigid.grading.handout import make_handout, solution_lines  # noqa: E402


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="make_handout.py", description=__doc__.splitlines()[0])
    p.add_argument("out", metavar="OUT.py", help="the handout file to write")
    p.add_argument("--solution", default=str(ROOT / "rigid_body_dynamic.py"), metavar="FILE",
                   help="the solution with TODO markers (default: the repository's rigid_body_dynamic.py)")
    args = p.parse_args(argv)
    try:
        check_output_path(args.out, (".py",))
        solution_path = Path(args.solution)
        if not solution_path.is_file():
            raise UserError(f"solution {solution_path} not found")
        if Path(args.out).resolve() == solution_path.resolve():
            raise UserError(f"{args.out} is the solution itself; write the handout elsewhere")
        solution = solution_path.read_text(encoding="utf-8")
        handout = make_handout(solution)
        leaked = solution_lines(solution) & {line.strip() for line in handout.splitlines()}
        if leaked:
            raise UserError(f"the handout would show solution lines {sorted(leaked)}; change the placeholders")
        with atomic_output(args.out) as tmp:
            tmp.write_text(handout, encoding="utf-8")
    except UserError as err:
        print(f"error: {err}", file=sys.stderr)
        return err.exit_code
    print(f"wrote {args.out}: TODOs 1-7 replaced by their hints and placeholders")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
