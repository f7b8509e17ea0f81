"""The checks of a submission's TODOs, run inside the child process.

``check_direct(spec, unit, expected)`` calls the submission's unit on the
seeded inputs (specs.sample_inputs) and compares with the reference's answers
(expected.py) within diagnose.RTOL; it returns {"passed", "message", "form"}.
TODO 5 also passes in the velocity-first order (alternatives.py); "form"
records which order matched, so the trajectory check compares with a reference
run in the same order.

``check_trajectories`` then runs the engine once with every unit that passed
its direct check taken from the submission (the others from the reference)
and compares x, q, L with the reference run. Only if that run strays does it
halve the group until single units, so the blame lands on the TODOs that stray.
The reference runs are precomputed, so a submission usually compiles one
simulator, not seven.
"""
import types

import numpy as np

from .diagnose import agreement, close, diagnose_output, error
from .direct import make_direct_kernel
from .specs import TODOS, pack, sample_inputs, unpack
from . import trajectory


def init_grading_taichi() -> None:
    """The one Taichi set-up of every check, in the grader's children, when it prepares the
    reference's answers and in ``--check``: float64, and quick compiling (Taichi's advanced IR
    optimisations off: each file compiles its units into the engine and runs 480 substeps of
    ten particles, so compiling is nearly all the time). The same set-up everywhere, so the
    answers and a student's values agree to the last bit where the code is the same. For the
    same reason the engine compiles one block loop for every case (compact_block_loops)."""
    from ..engine.kernels import compact_block_loops
    from ..runtime import init_taichi

    init_taichi("cpu", fp64=True, quick_compile=True)
    compact_block_loops()


def evaluate(spec, unit, inputs: dict) -> dict:
    """name -> (K, *shape) outputs of ``unit`` on ``inputs``."""
    a = pack(spec, inputs)
    out = np.zeros((len(a), spec.width("outputs")), np.float64)
    make_direct_kernel(spec, unit)(a, out)
    return unpack(spec, out)


def check_direct(spec, unit, expected: dict) -> dict:
    """expected: form -> {output -> (K, *shape)}, from expected.py (one form, two for TODO 5)."""
    k = spec.number
    inputs = sample_inputs(k)
    try:
        sub = evaluate(spec, unit, inputs)
    except SystemExit as err:
        return dict(passed=False, message=f"TODO {k}: {spec.unit} calls sys.exit() (code {err.code}) "
                                          f"while Taichi compiles it; remove that call")
    except MemoryError:
        return dict(passed=False, message=f"TODO {k}: {spec.unit} ran out of memory while compiling")
    except Exception as err:  # a compile error of the student's code: any Taichi or Python exception
        return dict(passed=False, message=f"TODO {k}: {spec.unit} does not compile or run: {explain(err)} "
                                          f"(it must return {returns(spec)})")
    return judge(spec, sub, inputs, expected,
                 not_done=f"{spec.unit} still returns the handout's placeholder (zero or unchanged values)")


def judge(spec, sub: dict, inputs: dict, expected: dict, not_done: str) -> dict:
    """Compare outputs ``sub`` (name -> (K, ...)) with each accepted form of the reference's answers.

    Shared by both formats; ``not_done`` ends the message of untouched code (zero or unchanged outputs).
    """
    k = spec.number
    for form, ref in expected.items():
        if all(close(sub[name], ref[name]) for name, *_ in spec.outputs):
            worst = max(error(sub[name], ref[name]) for name, *_ in spec.outputs)
            note = f", {form} order" if len(expected) > 1 else ""
            return dict(passed=True, form=form,
                        message=f"TODO {k}: right on {len(sub[spec.outputs[0][0]])} random calls "
                                f"(to {agreement(worst)}{note})")
    if is_placeholder(spec, sub, inputs):
        return dict(passed=False, message=f"TODO {k}: not done — {not_done}")
    ref = min(expected.values(), key=lambda e: sum(error(sub[n], e[n]) for n, *_ in spec.outputs))
    problems = [diagnose_output(spec, name, sub[name], ref[name], inputs, sub)
                for name, *_ in spec.outputs if not close(sub[name], ref[name])]
    return dict(passed=False, message=f"TODO {k}: " + "; ".join(problems))


def returns(spec) -> str:
    kinds = {(): "a number", (3,): "a 3-vector", (4,): "a 4-vector", (3, 3): "a 3x3 matrix"}
    parts = [f"{kinds[shape]} ({label})" for _n, shape, label in spec.outputs]
    return parts[0] if len(parts) == 1 else "a tuple: " + ", ".join(parts)


def is_placeholder(spec, sub: dict, inputs: dict) -> bool:
    """Every output zero, or equal to the input it updates: what the handout's placeholders return."""
    updates = dict(spec.updates)
    return all(np.all(sub[name] == 0) or (name in updates and np.array_equal(sub[name], inputs[updates[name]]))
               for name, *_ in spec.outputs)


def mix(reference, module, todos, velocity_first=False):
    """A units object: the reference's units, those of ``todos`` from ``module``."""
    units = {spec.unit: getattr(module if k in todos else reference, spec.unit) for k, spec in TODOS.items()}
    if velocity_first and 5 not in todos:
        from .alternatives import update_linear_velocity_first

        units["update_linear"] = update_linear_velocity_first
    return types.SimpleNamespace(**units)


def check_trajectories(events, module, reference, results: dict, expected, per_todo: bool = False) -> None:
    """Emit one "trajectory" event per run (``expected``: an expected.Expected)."""
    passed = [k for k, r in results.items() if r["passed"]]
    if not passed:
        return
    velocity_first = results.get(5, {}).get("form") == "velocity-first"
    expected = expected.trajectory("velocity-first" if velocity_first else "position-first")
    groups = [[k] for k in passed] if per_todo else [passed]
    while groups:
        todos = groups.pop(0)
        events.emit(phase="trajectory", todos=todos)
        try:
            errors = trajectory.compare(trajectory.run(mix(reference, module, todos, velocity_first)), expected)
            ok = trajectory.passed(errors)
            message = trajectory.summary(errors) if ok else (
                f"right on single calls, but a simulation with it strays from the reference: "
                f"{trajectory.describe(errors)}")
        except Exception as err:
            ok, message = False, f"right on single calls, but the simulation with it fails: {explain(err)}"
            broken = engine_failure(reference, velocity_first)
            if broken:  # not the submission's fault: say so rather than blame a TODO
                events.emit(event="trajectory", todos=todos, passed=False,
                            message=f"not graded — the simulation fails with the reference's units too (a bug "
                                    f"in the engine or the grader): {broken}")
                continue
        if not ok and len(todos) > 1:  # find which unit strays: halve the group until single units
            half = len(todos) // 2
            groups = [todos[:half], todos[half:]] + groups
            continue
        events.emit(event="trajectory", todos=todos, passed=ok, message=message)


def engine_failure(reference, velocity_first) -> str:
    """'' if the engine runs the reference's own units, else why not (asked only after a run raised)."""
    try:
        trajectory.run(mix(reference, reference, [], velocity_first))
        return ""
    except Exception as err:
        return explain(err)


def explain(err: BaseException) -> str:
    """One line from a (Taichi) exception: the submission's line, if named, and the last line."""
    lines = [line.strip() for line in str(err).splitlines() if line.strip()]
    where = [line for line in lines if line.startswith("File ") and "rigid_body_dynamic" in line]
    last = lines[-1] if lines else type(err).__name__
    place = ""
    if where:
        parts = where[-1].split(", ")
        place = next((p for p in parts if p.startswith("line ")), "")
    text = f"{type(err).__name__}: {last}" + (f" ({place})" if place else "")
    return text[:300]
