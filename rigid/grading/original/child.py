"""Inside the sandboxed child: grade one file in the original handout's format.

Same events as ../child.py, so the parent (../grade_submission.py) restarts and
blames the same way: "import" covers reading the TODO regions and running the
file once with the reference lines in every TODO (plus the harness kernels);
its failure is the code outside the TODOs, and costs every TODO. Then
"direct" per TODO (harness.py: the region alone on seeded inputs, judged by
checks.judge against the reference's answers) and "trajectory" per group
(attribution.py). Notes (a mesh replaced, a perturbation that could not be
applied, a file without a window loop, ti.init called twice) go as
{"event": "note", "message": ...}.
"""
import ast
from pathlib import Path

import re

import numpy as np

from ..checks import judge
from ..diagnose import close
from . import given, harness
from .attribution import Attribution, check_simulations
from .regions import RegionError
from .runner import COLUMNS, FILE_NAME, FRAMES, describe, run
from .variants import FileModel


def init_taichi():
    """One runtime for every version of the file: the file's own ti.init calls are ignored (headless.py).

    Float32 by default and no debug checks, as the file would run; one CPU thread, so sums of
    float atomics come out the same in every run; Taichi's advanced IR optimisations off: every
    version of the file compiles its own kernels and runs them for 30 frames only, so compiling
    is nearly all the time (rigid.runtime.init_taichi's quick_compile).
    """
    import contextlib
    import sys

    import taichi as ti

    from . import fields, headless

    with contextlib.redirect_stdout(sys.stderr):
        ti.init(arch=ti.cpu, default_fp=ti.f32, debug=False, log_level=ti.ERROR, offline_cache=True,
                random_seed=0, cpu_max_num_threads=1, advanced_optimization=False)
    headless.install(ti)
    fields.install(ti)  # one set of fields for every version of the file


def perturbed_label(params: dict) -> str:
    parts = [f"{name} {params[name]:g}" for name in ("particle_mass", "dt") if name in params]
    if any(name in params for name in ("initial_velocity", "initial_angular_velocity")):
        parts.append("a throw with a spin")
    return ", ".join(parts)


def grade(events, path, expected, todos, per_todo=False, renames=None, watch=None):
    """Grade the file at ``path`` (the box is its folder); ``expected``: an expected.Expected.
    ``watch()`` is called just before the file's code first runs (attempts.install)."""
    events.emit(phase="import")
    path = Path(path)
    try:
        model = FileModel(path.read_text(encoding="utf-8", errors="replace"), renames)
    except RegionError as err:
        events.emit(event="import_failed", message=str(err))
        return
    for note in model.notes + [given.note(model.text, model.regions)]:
        if note:
            events.emit(event="note", message=note)
    init_taichi()
    folder = path.parent / "_grader"
    folder.mkdir(exist_ok=True)
    unparsable = {k: _syntax_error(model, k) for k in todos if k in model.regions}
    extra = [line for k in todos if k in model.regions and not unparsable[k] for line in harness.kernel(k, model)]
    guess = likely_form(model)
    variant = model.build(form=guess, extra=extra)
    if watch:
        watch()
    first = run(variant, folder / "reference_harness.py")
    for note in first.notes:
        events.emit(event="note", message=note)
    if first.rows is None:
        events.emit(event="import_failed", message=_does_not_run(model, folder, first.error))
        return
    events.emit(phase="setup")
    particles = int(first.module.particle_vertices.shape[0])
    results = {}
    for k in todos:
        events.emit(phase="direct", todo=k)
        if k in model.problems:
            results[k] = dict(passed=False, message=f"TODO {k}: not graded — {model.problems[k]}")
        elif unparsable[k]:
            results[k] = dict(passed=False, message=f"TODO {k}: {unparsable[k]}")
        else:
            results[k] = _direct(k, model, first.module, variant, folder, particles, expected)
        events.emit(event="direct", todo=k, **results[k])
    params, notes = model.perturbed()
    for note in notes:
        events.emit(event="note", message=note)
    sets = [("the file's parameters", None)] + ([(perturbed_label(params), params)] if params else [])
    form = results.get(5, {}).get("form", "position-first")
    attribution = Attribution(model, folder, form, sets, first.rows if form == guess else None)
    check_simulations(events, attribution, results, per_todo)
    if model.bonus and set(todos) == set(range(1, 8)):  # once per file: the first child grades all seven
        events.emit(event="note", message=bonus_note(events, model, folder))


def likely_form(model) -> str:
    """The order of TODO 5 the direct check will most likely find: "velocity-first" when the student's
    code there writes ``body_velocity`` before ``body_cm_position``, else "position-first" (also the
    reference's order when TODO 5 fails). The first version puts the reference lines in TODO 5 in
    this order, so that its run is also the reference run with the file's own parameters when the
    guess is right (the direct check decides; a wrong guess costs one more run, as before)."""
    region = model.regions.get(5)
    first = None
    for line in region.code(model.text.splitlines()) if region else []:
        found = re.match(r"\s*(body_velocity|body_cm_position)\s*\[[^]]*\]\s*(\[[^]]*\]\s*)?[-+*/]?=(?!=)",
                         line.split("#")[0])
        if found:
            first = found.group(1)
            break
    return "velocity-first" if first == "body_velocity" else "position-first"


def _does_not_run(model, folder, error: str) -> str:
    """Why nothing can be graded when the file with the reference lines fails: said of the student's file
    only when the student's own file fails too (else the grader's version is at fault: a TA grades it)."""
    own = run(model.build(range(1, 8)), folder / "as_submitted.py")
    if own.rows is None:
        return f"the file does not run: {own.error}"
    return (f"the file runs as submitted, but not with the grader's reference lines in its TODOs ({error}); "
            f"the grader cannot compare its TODOs: grade it by hand")


def bonus_note(events, model, folder) -> str:
    """What the file's bonus terms did: the file as it is, with its bonus parameters and without."""
    names = ", ".join(f"{name} = {value:g}" for name, value in model.bonus.items())
    lines = model.text.splitlines()
    where = []
    for i, line in enumerate(lines):
        code = line.split("#")[0]
        if any(re.search(rf"\b{re.escape(n)}\b", code) for n in model.bonus) and not re.match(
                rf"^({'|'.join(map(re.escape, model.bonus))})\s*=(?!=)", line):
            todo = next((k for k, r in model.regions.items() if r.start <= i < r.end), None)
            where.append(f"{i + 1}" + (f" (TODO {todo})" if todo else ""))
    head = (f"bonus terms: the TODOs were graded with the file's bonus parameters set to 0 ({names}; the slides' "
            f"model has no damping or friction), so they cost no TODO; read at line{'s' if len(where) > 1 else ''} "
            f"{', '.join(where)}")
    runs = []
    for keep in (True, False):
        events.emit(phase="bonus")  # a stage per run (grade_submission.py: a hang here costs nothing)
        runs.append(run(model.build(range(1, 8), keep_bonus=keep), folder / f"bonus_{int(keep)}.py"))
    if runs[0].rows is None:
        return f"{head}; with the file's own values the file fails when run: {runs[0].error}"
    if runs[1].rows is None or not np.all(np.isfinite(runs[0].rows)):
        return f"{head}; with the file's own values the simulation is not finite"
    (v1, w1), (v0, w0) = [(float(np.linalg.norm(r.rows[-1, COLUMNS["body_velocity"]])),
                           float(np.linalg.norm(r.rows[-1, COLUMNS["body_angular_velocity"]]))) for r in runs]
    return (f"{head}; with the file's values, after {FRAMES} frames the body moves at {v1:.3g} m/s and spins at "
            f"{w1:.3g} rad/s, against {v0:.3g} m/s and {w0:.3g} rad/s without them")


def _syntax_error(model, k) -> str:
    """'' if TODO k's code parses, else the message (the student's line)."""
    region = model.regions[k]
    code = region.code(model.text.splitlines())
    body = "".join("    " + (line[len(region.indent):] if line.startswith(region.indent) else line.lstrip()) + "\n"
                   for line in code)
    try:
        ast.parse(f"for _ in ():\n{body}    pass\n")
    except SyntaxError as err:
        line = region.start + (err.lineno or 1) - 1
        return f"{_where(region)} has a syntax error at line {line} of {FILE_NAME[0]}: {err.msg}"
    return ""


def _where(region) -> str:
    """The region in a message: by its comment, or by its lines when align.py found it without one."""
    if region.marker_text:
        return f"the code under '# TODO {region.k}:'"
    return f"TODO {region.k}'s code ({region.where()})"


def _direct(k, model, module, variant, folder, particles, expected) -> dict:
    where = _where(model.regions[k])
    blocked = harness.blocked_by(model.reference_text, model.regions[k].code(model.text.splitlines()))
    if blocked:
        return dict(passed=True, simulation_only=True,
                    message=f"TODO {k}: checked by simulation only ({where} reads {blocked}, which is computed "
                            f"from dt, the mass or gravity, so single calls cannot vary them)")
    try:
        spec, inputs, sub = harness.evaluate(k, module, particles)
    except Exception as err:  # a compile error in the student's region
        return dict(passed=False, message=f"TODO {k}: {where} does not compile or run: "
                                          f"{describe(err, variant, folder / 'reference_harness.py')}")
    answers = expected.direct(k)
    result = judge(spec, sub, inputs, answers, not_done=f"{where} leaves its result zero or unchanged")
    if k == 2 and not result["passed"] and any(close(sub["f"] - harness.leftover_force(len(sub["f"])), ref["f"])
                                               for ref in answers.values()):
        # it adds m g to the force already there: right only if the file resets the force elsewhere
        return dict(passed=True, accumulates=True, form=next(iter(answers)),
                    message=f"TODO 2: adds m g to the particle's force (`+=`), right where something resets "
                            f"that force every substep")
    return result
