"""Measure the grader: preparation, seconds per submission, batch throughput.

    python scripts/bench_grading.py [--copies 8]

Grades, in a fresh cache folder (so the once-per-version preparation is timed
too): the solution, the handout, a correct submission written differently
(its kernels compile cold), and one whose TODO 3 is right on the grader's
single calls but wrong in a simulation (the slowest path: the trajectory run
is split until the culprit is found). Then a batch of ``copies`` wrong
submissions with --jobs 1 and --jobs 2. Then the course's original handout
format (--original, default on): the real handout's shape solved, unsolved, a
one-TODO mistake and a file with bonus terms (tests/data/original_handout/ and
the variants of tests/grading_original_variants.py), one at a time, and the
seconds per file of a batch with --jobs 2 of those four and four more (solved.py
after black, files with several mistakes, lost markers, edits of the given code). Each figure comes with the
CPU seconds of the grading processes (the grader and every child it waited
for): on a machine shared with other work the wall time grows, the CPU time
much less, and CPU seconds / cores is the wall time an idle machine would take.
Prints the figures; asserts nothing.
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the repository

from rigid.grading.handout import make_handout

SOLUTION = (ROOT / "rigid_body_dynamic.py").read_text()
VARIANTS = {
    "solution": SOLUTION,
    "handout": make_handout(SOLUTION),
    "different_but_right": SOLUTION.replace(
        "    new_position = position + dt * momentum / mass\n    new_momentum = momentum + dt * force\n",
        "    new_momentum = force * dt + momentum\n    new_position = position + dt * new_momentum / mass\n"),
    "wrong_only_in_simulation": SOLUTION.replace(
        "    term = particle_force\n",
        "    term = particle_force\n    if particle_force.norm() > 60.0:\n        term = 1.5 * particle_force\n"),
}


def children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


LAST_CPU = [0.0]  # CPU seconds of the last grade() call's processes


def grade(paths, cache, jobs, out):
    start, cpu = time.monotonic(), children_cpu()
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "grade.py"), *map(str, paths), "--jobs",
                           str(jobs), "--cache-dir", str(cache), "--json", str(out)],
                          capture_output=True, text=True)
    if proc.returncode:
        sys.exit(proc.stderr)
    LAST_CPU[0] = children_cpu() - cpu
    return time.monotonic() - start, json.loads(Path(out).read_text())


def original_files() -> dict:
    """name -> text of original-format submissions (the test fixtures in the real handout's shape)."""
    sys.path.insert(0, str(ROOT / "tests"))
    from grading_original_variants import make

    return {name: make(name) for name in ("solved", "unsolved", "t4_swapped_cross", "bonus_inside", "black_formatted",
                                          "marker_syntax_unrotated", "unknown_mistakes_given_edits", "mistakes_a")}


ALONE = 4  # the first four are also graded one at a time


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--copies", type=int, default=8, help="wrong submissions in the throughput batch")
    p.add_argument("--no-project", action="store_true", help="skip the project format's figures")
    p.add_argument("--no-original", action="store_true", help="skip the original handout format's figures")
    args = p.parse_args()
    print(f"{os.cpu_count()} CPU cores; load average {os.getloadavg()[0]:.2f}")
    with tempfile.TemporaryDirectory() as tmp:
        tmp, cache = Path(tmp), Path(tmp) / "cache"
        files = []
        for name, text in VARIANTS.items():
            (tmp / f"{name}.py").write_text(text)
            files.append(tmp / f"{name}.py")
        wall, _ = grade([files[1]], cache, 1, tmp / "a.json")
        print(f"first run (prepares the reference, then grades the handout): {wall:.1f} s")
        if not args.no_original:
            bench_original(tmp, cache)
        if args.no_project:
            return
        print("project format:")
        wall, results = grade(files, cache, 1, tmp / "b.json")
        for r in results:
            print(f"  {Path(r['submission']).stem:26s} {r['total']:>3g}/90  {r['seconds']:5.1f} s")
        batch = tmp / "batch"
        batch.mkdir()
        for i in range(args.copies):
            (batch / f"wrong_{i}.py").write_text(SOLUTION.replace("force = particle_mass * gravity",
                                                                  f"force = {i + 2} * particle_mass * gravity"))
        for jobs in (1, 2):
            wall, _ = grade([batch], cache, jobs, tmp / "c.json")
            print(f"batch of {args.copies} (--jobs {jobs}): {wall:.1f} s, {wall / args.copies:.2f} s per submission; "
                  f"{LAST_CPU[0] / args.copies:.2f} CPU-s per submission")


def bench_original(tmp, cache):
    folder = tmp / "original"
    folder.mkdir()
    texts = original_files()
    print("original handout format (one file at a time, --jobs 1; 'seconds' is the file's own grading):")
    for name, text in texts.items():
        (folder / f"{name}.py").write_text(text)
    for name in list(texts)[:ALONE]:
        wall, (r,) = grade([folder / f"{name}.py"], cache, 1, tmp / "o.json")
        print(f"  {name:26s} {r['total']:>3g}/90  {r['seconds']:5.1f} s  (whole command {wall:.1f} s, "
              f"{LAST_CPU[0]:.1f} CPU-s)")
    wall, results = grade([folder], cache, 2, tmp / "o.json")
    n, cores = len(results), min(2, os.cpu_count() or 1)
    print(f"  batch of {n} (--jobs 2): {wall:.1f} s, {wall / n:.2f} s per file; {LAST_CPU[0]:.1f} CPU-s, "
          f"{LAST_CPU[0] / n:.2f} CPU-s per file ({LAST_CPU[0] / n / cores:.2f} s per file on {cores} idle cores)")


if __name__ == "__main__":
    main()
