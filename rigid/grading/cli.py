"""``python scripts/grade.py PATH... [--json OUT] [--csv OUT] [--jobs N] [--points ...]``.

Prints the points split, one progress line per submission as it finishes
(stderr), then the table, the feedback and the batch summary (stdout); the
summary also goes to a file beside the CSV/JSON (--summary). Exit 0 when every
submission was graded (whatever its score), 2 on bad arguments.
"""
import argparse
import os
import sys
from pathlib import Path

from ..run.atomic import check_output_path
from ..config import REPO_ROOT
from ..errors import UserError
from .original.detect import FORMATS
from .specs import DEFAULT_POINTS, TODOS

MIN_MEMORY_MB = 2048  # measured: a grading child fails at 1536 MB and passes at 1792 MB (RLIMIT_AS)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="grade.py", description="Grade Assignment 3 submissions TODO by TODO, each in its own sandboxed "
                                     "process.",
        epilog="examples:\n  python scripts/grade.py submissions/ --csv grades.csv --json grades.json\n"
               "  python scripts/grade.py course_submissions/ --format original --jobs 4\n"
               "  python scripts/grade.py 3035_alice_assignment3.zip bob.py --points 20,10,10,10,10,15,15",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("paths", nargs="+", metavar="PATH", help=".py files, .zip files, or folders of them")
    p.add_argument("--json", metavar="OUT.json", help="write every result, with messages")
    p.add_argument("--csv", metavar="OUT.csv", help="write one row per submission for a gradebook")
    p.add_argument("--summary", metavar="OUT.txt",
                   help="write the batch summary (score histogram, TODOs lost most often and why, submissions "
                        "not graded) there; by default beside the CSV or JSON as NAME.summary.txt")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, metavar="N",
                   help="submissions graded at once (default: the number of CPU cores)")
    p.add_argument("--points", metavar="P1,...,P7",
                   help="points of TODOs 1..7 (default " + ",".join(f"{v:g}" for v in DEFAULT_POINTS.values()) + ")")
    p.add_argument("--timeout", type=float, default=60.0, metavar="S",
                   help="time limit of each stage of grading one submission (its import, each TODO's "
                        "check, each simulation): CPU seconds, or wall seconds of a stage that waits "
                        "doing nothing (default 60)")
    p.add_argument("--memory-mb", type=int, default=4096, metavar="MB",
                   help=f"address-space limit of each grading process (default 4096, at least {MIN_MEMORY_MB}: "
                        f"Taichi's LLVM alone needs ~1800)")
    p.add_argument("--reference", default=str(REPO_ROOT / "rigid_body_dynamic.py"), metavar="FILE",
                   help="the solution to grade against (default: the repository's rigid_body_dynamic.py)")
    p.add_argument("--format", choices=("auto", *FORMATS), default="auto",
                   help="the handout the submissions were written for: project (the TODO functions of this "
                        "repository's rigid_body_dynamic.py), original (the course's module-level script with "
                        "global fields and kernels initial() and substep()), or auto: detect it per submission "
                        "(default)")
    p.add_argument("--original-handout", metavar="FILE",
                   help="the course's handout as given to students (original format): its kernels, with the "
                        "reference lines in its TODOs, are compiled once and each original-format submission "
                        "starts from them (about a third less CPU a file that keeps the given code)")
    p.add_argument("--require-sandbox", action="store_true",
                   help="refuse to grade unless each submission can run in a bubblewrap sandbox (bwrap: no "
                        "network, no files but its own folder; see docs/ta-guide.md)")
    p.add_argument("--cache-dir", metavar="DIR", help="where the reference's answers and compiled kernels "
                                                      "are kept (default ~/.cache/rigid-body-taichi/grader)")
    return p


def parse_points(text) -> dict:
    if text is None:
        return dict(DEFAULT_POINTS)
    parts = text.replace(" ", "").split(",")
    try:
        values = [float(v) for v in parts]
    except ValueError:
        values = []
    if len(values) != len(TODOS) or any(v < 0 or v != v for v in values):
        raise UserError(f"--points {text}: give {len(TODOS)} non-negative numbers separated by commas, "
                        f"e.g. --points 15,10,10,15,10,15,15")
    return dict(zip(TODOS, values))


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return _run(args)
    except UserError as err:
        print(f"error: {err}", file=sys.stderr)
        return err.exit_code


def _run(args) -> int:
    from . import report
    from .batch import default_cache_root, grade_batch, prepare
    from .sandbox import Limits
    from .submissions import discover

    points = parse_points(args.points)
    if args.jobs < 1:
        raise UserError(f"--jobs {args.jobs}: use 1 or more")
    if not args.timeout > 0:
        raise UserError(f"--timeout {args.timeout:g}: use a positive number of seconds")
    if args.memory_mb < MIN_MEMORY_MB:
        raise UserError(f"--memory-mb {args.memory_mb}: Taichi alone needs about 1800 MB of address space; "
                        f"use {MIN_MEMORY_MB} or more")
    if args.summary is None and (args.csv or args.json):
        first = Path(args.csv or args.json)
        args.summary = str(first.with_name(first.stem + ".summary.txt"))
    for out, suffix in ((args.json, ".json"), (args.csv, ".csv"), (args.summary, ".txt")):
        if out:
            check_output_path(out, (suffix,))
    reference = Path(args.reference).resolve()
    if not reference.is_file():
        raise UserError(f"reference {reference} not found; give the solution file with --reference")
    from .box import find_box

    sandbox, why = find_box()
    if sandbox is None and args.require_sandbox:
        raise UserError(f"--require-sandbox: {why}; install it (apt-get install bubblewrap) or grade without "
                        f"--require-sandbox")
    if sandbox is None:
        print(f"WARNING: submissions are NOT contained: {why}, so each runs as you and can read and write "
              f"your files and open network connections. Install bubblewrap (apt-get install bubblewrap) "
              f"or pass --require-sandbox to refuse.", file=sys.stderr)
    submissions, notes = discover(args.paths)
    for note in notes:
        print(note, file=sys.stderr)
    limits = Limits(stage_seconds=args.timeout, memory_mb=args.memory_mb)
    cache_root = Path(args.cache_dir) if args.cache_dir else default_cache_root()
    handout = Path(args.original_handout) if args.original_handout else None
    if handout is not None and not handout.is_file():  # before the reference's preparation, which takes a while
        raise UserError(f"--original-handout {handout}: no such file; give the course's handout file")
    settings = prepare(reference, limits, cache_root, log=lambda m: print(m, file=sys.stderr), original_handout=handout)
    settings.points = points
    settings.format = args.format
    settings.sandbox = sandbox
    settings.handout_folder = handout.resolve().parent if handout is not None else None
    print(report.points_line(points))
    n = len(submissions)

    def progress(i, result):
        print(f"[{i + 1}/{n}] {result['submission']}: {result['total']:g}/{result['max_total']:g} "
              f"({result['seconds']:.1f} s)", file=sys.stderr, flush=True)

    results = grade_batch(submissions, settings, args.jobs, progress)
    print(report.table(results))
    text = report.details(results)
    if text:
        print("\n" + text)
    print("\n" + report.summary(results))
    if args.summary:
        report.write_summary(results, args.summary)
    if args.json:
        report.write_json(results, args.json)
    if args.csv:
        report.write_csv(results, args.csv)
    return 0
