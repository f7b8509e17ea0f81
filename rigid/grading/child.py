"""Inside the sandboxed child: import one submission, check each TODO, report events.

    python -m rigid.grading.child --submission FILE --events FILE --reference FILE --expected FILE.npz
        [--memory-mb N] [--file-mb N] [--todos 1,2,...] [--per-todo-trajectories] [--write-cache]
    python -m rigid.grading.child --make-expected FILE.npz --events FILE --reference FILE
    ... --format original [--renames JSON]    a file in the course's original handout format (original/)

Started by sandbox.py with cwd and HOME in a temporary folder. Resource limits
are set first, before numpy, Taichi or the submission load. Results go as JSON
lines to the --events file, never to stdout (which the submission shares), so
a print can never be mistaken for a result:

    {"phase": "import"} | {"phase": "setup"} | {"phase": "direct", "todo": k}
    | {"phase": "trajectory", "todos": [k, ...]}          a stage begins
    {"event": "import_failed", "message": ...}
    {"event": "direct", "todo": k, "passed": bool, "message": ..., "form": ...}
    {"event": "trajectory", "todos": [...], "passed": bool, "message": ...}
    {"event": "note", "message": ...}                      something the TA should know (original format)
    {"event": "done"}

If the process dies or hangs, the parent reads the last stage begun and blames it.
"""
import argparse
import json
import os
import resource
import sys
import time


PROCESSES = 256  # threads and processes of a sandboxed child (Taichi's threads fit many times over)


def apply_limits(memory_mb: int, file_mb: int) -> None:
    """Hard limits the submission cannot raise again (soft = hard); in the sandbox as root, first the
    unprivileged uid the parent chose (box.py: root ignores the process limit and reads every file)."""
    uid = os.environ.pop("RIGID_CHILD_UID", None)
    if uid is not None:
        os.setgroups([])
        os.setgid(int(uid))
        os.setuid(int(uid))
    limits = [(resource.RLIMIT_AS, memory_mb << 20), (resource.RLIMIT_FSIZE, file_mb << 20), (resource.RLIMIT_CORE, 0)]
    if os.environ.get("RIGID_SANDBOXED"):  # counted per box there; outside, it would count all the TA's processes
        limits.append((resource.RLIMIT_NPROC, PROCESSES))
    for limit, value in limits:
        resource.setrlimit(limit, (value, value))


class Events:
    def __init__(self, path):
        self.file = open(path, "a", buffering=1, encoding="utf-8")
        self.start = time.perf_counter()

    def emit(self, **fields):
        fields["t"] = round(time.perf_counter() - self.start, 3)
        self.file.write(json.dumps(fields) + "\n")
        self.file.flush()


WRITE_CACHE = [False]  # --write-cache: the grader keeps this child's kernels (trusted code only)


def finish(events, code=0):
    events.emit(phase="finish")
    if WRITE_CACHE[0] and "taichi" in sys.modules:
        try:  # Taichi writes its offline cache of compiled kernels at reset (os._exit skips atexit);
            # Taichi's own reset: an original-format file's ti.reset is the grader's stand-in (headless.py)
            sys.modules["taichi.lang.misc"].reset()
        except Exception:
            pass
    events.emit(event="done")
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:
            pass
    os._exit(code)  # threads or atexit hooks a submission left behind must not keep us alive


def make_expected(events, reference_path, out_path):
    """Trusted mode (no submission): the reference's answers for every check, saved to an NPZ."""
    events.emit(phase="setup")
    from ..engine.units import load_units
    from . import expected
    from .checks import init_grading_taichi

    init_grading_taichi()
    expected.save(expected.compute(load_units(reference_path)), out_path)
    finish(events)


def main(argv=None):
    p = argparse.ArgumentParser()
    p.add_argument("--submission")
    p.add_argument("--events", required=True)
    p.add_argument("--reference", required=True, help="the solution file whose units fill in the others")
    p.add_argument("--expected", help="NPZ of the reference's answers (expected.py)")
    p.add_argument("--make-expected", metavar="OUT.npz", help="compute the reference's answers, grade nothing")
    p.add_argument("--memory-mb", type=int, default=4096)
    p.add_argument("--file-mb", type=int, default=64)
    p.add_argument("--todos", default="1,2,3,4,5,6,7")
    p.add_argument("--per-todo-trajectories", action="store_true")
    p.add_argument("--write-cache", action="store_true",
                   help="write Taichi's offline cache at the end (the grader keeps it: trusted code only)")
    p.add_argument("--format", choices=("project", "original"), default="project",  # original.detect.FORMATS
                   help="project: the TODO functions of rigid_body_dynamic.py; original: the course's "
                        "module-level script (original/)")
    p.add_argument("--file-name", default="the submitted file", help="the student's file name, for messages")
    p.add_argument("--renames", default="{}", metavar="JSON",
                   help="original format: {quoted path in the file: path to read instead} (meshes)")
    args = p.parse_args(argv)
    apply_limits(args.memory_mb, args.file_mb)
    events = Events(args.events)
    todos = [int(k) for k in args.todos.split(",") if k]
    WRITE_CACHE[0] = args.write_cache or bool(args.make_expected)
    if args.make_expected:
        make_expected(events, args.reference, args.make_expected)
    from . import attempts  # its hook goes in just before the submission's code first runs

    if args.format == "original":
        from .expected import Expected
        from .original.child import grade
        from .original.runner import FILE_NAME

        FILE_NAME[0] = args.file_name
        grade(events, args.submission, Expected(args.expected), todos, args.per_todo_trajectories,
              json.loads(args.renames), watch=lambda: attempts.install(events, (args.reference, args.expected)))
        finish(events)

    events.emit(phase="import")
    from .loader import import_submission, isolate_syntax_errors

    submission, syntax_errors = isolate_syntax_errors(args.submission)
    import numpy  # noqa: F401  (loaded before the hook: what they do at import is not the submission's)
    import taichi  # noqa: F401

    attempts.install(events, (args.reference, args.expected))
    module, problem = import_submission(submission, args.memory_mb)
    if problem:
        events.emit(event="import_failed", message=problem)
        finish(events)

    events.emit(phase="setup")
    # After the import: a submission that calls ti.init itself is overridden here.
    from ..engine.units import load_units
    from .checks import check_direct, check_trajectories, init_grading_taichi
    from .expected import Expected
    from .specs import TODOS

    init_grading_taichi()
    reference = load_units(args.reference)
    expected = Expected(args.expected)

    results = {}
    for k in todos:
        spec = TODOS[k]
        events.emit(phase="direct", todo=k)
        unit = getattr(module, spec.unit, None)
        if k in syntax_errors:
            result = dict(passed=False, message=syntax_errors[k])
        elif not callable(unit):
            result = dict(passed=False, message=f"TODO {k}: no function {spec.unit} in the file; "
                                                f"keep the handout's function names")
        else:
            result = check_direct(spec, unit, expected.direct(k))
        results[k] = result
        events.emit(event="direct", todo=k, **result)

    check_trajectories(events, module, reference, results, expected, args.per_todo_trajectories)
    finish(events)


if __name__ == "__main__":
    main()
