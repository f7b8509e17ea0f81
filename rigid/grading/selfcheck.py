"""``python rigid_body_dynamic.py --check``: the grader's checks of your 7 TODOs, before you submit.

Runs the same checks as ``scripts/grade.py`` (checks.py), in this process, on
this file's units, against the reference's answers in the answers file beside
it (answers.py: numbers, never solution code): each TODO on 64 seeded random
calls, with the grader's diagnosis when it is wrong; once all 7 pass, the
grader's 480-substep simulation with your 7 units. Prints one line per TODO
(✓, or ✗ and the diagnosis) and exits 0 only when all pass (1 otherwise, 2
when the answers file is missing or stale).

What it cannot do, without the reference's code: when each TODO passes alone
but the simulation with all seven strays, grade.py finds the culprit by
swapping in reference units; here the last line says the simulation strays.
It runs your code without the grader's sandbox or time limits.
"""
import sys
from pathlib import Path

from ..errors import UserError
from .specs import DEFAULT_POINTS, TODOS


def check_units(units, expected) -> tuple:
    """({k: {"passed", "message"}}, joint failure message or ""), as grade.py would decide them."""
    from .checks import check_direct, explain
    from . import trajectory

    results = {}
    for k, spec in TODOS.items():
        unit = getattr(units, spec.unit, None)
        if callable(unit):
            results[k] = check_direct(spec, unit, expected.direct(k))
        else:
            results[k] = dict(passed=False, message=f"TODO {k}: no function {spec.unit} in the file; keep the "
                                                    f"handout's function names")
    if not all(r["passed"] for r in results.values()):
        return results, ""
    form = results[5].get("form", "position-first")
    try:
        errors = trajectory.compare(trajectory.run(units), expected.trajectory(form))
    except Exception as err:
        return results, f"right on single calls, but the simulation with all 7 fails: {explain(err)}"
    if not trajectory.passed(errors):
        return results, (f"right on single calls, but a simulation with all 7 strays from the reference: "
                         f"{trajectory.describe(errors)}; grade.py finds which TODO")
    for r in results.values():
        r["message"] += f"; {trajectory.summary(errors)}"
    return results, ""


def marks() -> tuple:
    """(pass, fail) marks this terminal can print."""
    try:
        "✓✗".encode(sys.stdout.encoding or "ascii")
        return "✓", "✗"
    except (UnicodeEncodeError, LookupError):
        return "ok", "XX"


def main(module, argv=None) -> int:
    from . import answers
    from .checks import init_grading_taichi

    args = [a for a in (sys.argv[1:] if argv is None else list(argv)) if a != "--check"]
    if args:
        print(f"error: --check takes no other options (got {' '.join(args)})", file=sys.stderr)
        return 2
    path = Path(module.__file__).resolve()
    try:
        expected = answers.load(path.with_name(answers.FILE_NAME))
    except UserError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    print(f"Checking the 7 TODOs of {path.name} against the reference answers in {answers.FILE_NAME} "
          f"(the grader's checks):", flush=True)
    init_grading_taichi()
    results, joint = check_units(module, expected)
    ok, bad = marks()
    for k, r in results.items():
        print(f"{ok if r['passed'] else bad} {r['message']}", flush=True)
    passed = [k for k, r in results.items() if r["passed"]]
    if joint:
        print(f"{bad} all 7 together: {joint}")
    elif len(passed) == len(TODOS):
        print(f"All {len(TODOS)} TODOs pass ({sum(DEFAULT_POINTS.values()):g}/{sum(DEFAULT_POINTS.values()):g} "
              f"with the default points).")
        return 0
    else:
        points = sum(DEFAULT_POINTS[k] for k in passed)
        print(f"{len(passed)} of {len(TODOS)} TODOs pass ({points:g}/{sum(DEFAULT_POINTS.values()):g} with the "
              f"default points); fix those marked {bad} and run --check again. The simulation check runs once "
              f"all {len(TODOS)} pass.")
    return 1
