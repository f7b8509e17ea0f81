"""Per-TODO simulations of a file in the original format, against the same file with reference lines.

TODO k's simulation runs the student's file with the student's code in TODO k
(or a group of TODOs) and the reference lines in every other TODO region, and
compares the body's fields frame by frame with the file that has the reference
lines in all seven. Everything outside the TODOs (given code, parameters, mesh,
bonus terms, the loop) is the student's in both, so it costs no TODO points.
Both run twice: with the file's own parameters, and with PERTURBED ones (a
particle mass other than 1, another Δt, a throw with a spin), since the
handout's defaults hide mistakes. As in checks.py, the TODOs that passed their
direct check run together first, and a group that strays is halved until the
blame lands on single TODOs.

A parameter set whose reference run is not finite (the file's own Δt too large
for its stiffness, say) is left out with a note; if both are, the TODOs are not
graded (the file blows up whatever its TODO code).
"""
import numpy as np

from .runner import COLUMNS, FRAMES, run

RTOL = 1e-4  # float32 fields: equivalent code differs by ~1e-6 after half a second; mistakes by > 1e-2
COMPARED = {"body_cm_position": ("m", 1.0), "body_rotation_quaternion": ("", 1.0),
            "body_velocity": ("m/s", 1.0), "body_angular_velocity": ("rad/s", 1.0)}  # unit, floor of the scale


def errors(rows: np.ndarray, ref: np.ndarray) -> dict:
    """field -> largest difference over the frames, relative to the reference's size (at least the floor)."""
    if rows.shape != ref.shape:
        return {name: float("inf") for name in COMPARED}
    out = {}
    for name, (_unit, floor) in COMPARED.items():
        a, b = rows[:, COLUMNS[name]], ref[:, COLUMNS[name]]
        scale = max(float(np.max(np.linalg.norm(b, axis=1))), floor)
        out[name] = float(np.max(np.abs(a - b))) / scale if np.all(np.isfinite(a)) else float("inf")
    return out


def describe(errs: dict, label: str, frames: int) -> str:
    worst = {n: e for n, e in errs.items() if e > RTOL}
    parts = ", ".join(f"{n} by {e:.1e}" for n, e in worst.items())
    return f"with {label}, after {frames} frames {parts} (relative; allowed {RTOL:g})"


class Attribution:
    """The reference runs of one submission and the per-TODO runs against them."""

    def __init__(self, model, folder, form, param_sets, first_reference=None, frames=FRAMES):
        self.model, self.folder, self.form, self.frames = model, folder, form, frames
        self.sets = param_sets  # [(label, params or None)]
        self.refs, self.notes, self.count = {}, [], 0
        if first_reference is not None:
            self.refs[(form, None)] = first_reference

    def reference(self, label, params):
        key = (self.form, tuple(sorted(params.items())) if params else None)
        if key not in self.refs:
            variant = self.model.build((), self.form, params)
            self.refs[key] = run(variant, self._path("reference"), self.frames).rows
        rows = self.refs[key]
        if rows is None or not np.all(np.isfinite(rows)):
            note = f"with {label} the file does not run finitely even with the reference lines; that run is left out"
            if note not in self.notes:
                self.notes.append(note)
            return None
        return rows

    def usable(self) -> list:
        return [(label, params, ref) for label, params in self.sets
                if (ref := self.reference(label, params)) is not None]

    def check(self, todos, usable) -> tuple:
        """(passed, message) of the file with the student's code in ``todos`` only."""
        worst = 0.0
        for label, params, ref in usable:
            variant = self.model.build(set(todos), self.form, params)
            result = run(variant, self._path("todos_" + "_".join(map(str, todos))), self.frames)
            if result.rows is None:
                return False, f"the file with it fails when run: {result.error}"
            errs = errors(result.rows, ref)
            if any(e > RTOL for e in errs.values()):
                return False, "the file with it strays from the same file with the reference lines: " + \
                    describe(errs, label, self.frames)
            worst = max([worst, *errs.values()])
        labels = " and with ".join(label for label, *_ in usable)
        return True, f"{self.frames}-frame runs agree with the reference lines to {worst:.0e} (with {labels})"

    def _path(self, stem):
        self.count += 1
        return self.folder / f"{stem}_{self.count}.py"


def check_simulations(events, attribution, results: dict, per_todo: bool = False) -> None:
    """Emit one "trajectory" event per group of TODOs (the vocabulary of ../child.py)."""
    passed = [k for k, r in results.items() if r["passed"]]
    if not passed:
        return
    usable = []
    for label, params in attribution.sets:  # one stage per reference run: a failure there is not the student's
        events.emit(phase="trajectory", todos=[])
        ref = attribution.reference(label, params)
        if ref is not None:
            usable.append((label, params, ref))
    for note in attribution.notes:
        events.emit(event="note", message=note)
    if not usable:
        events.emit(event="trajectory", todos=passed, passed=False,
                    message="not graded — the file's simulation is not finite even with the reference lines "
                            "in every TODO (check its parameters and the code outside the TODOs)")
        return
    groups = [[k] for k in passed] if per_todo else [passed]
    while groups:
        todos = groups.pop(0)
        events.emit(phase="trajectory", todos=todos)
        ok, message = attribution.check(todos, usable)
        if not ok and len(todos) > 1:
            half = len(todos) // 2
            groups = [todos[:half], todos[half:]] + groups
            continue
        if not ok and results[todos[0]].get("accumulates"):
            message = (f"the force is accumulated across substeps: `+=` adds m g to the force of the previous "
                       f"substep, which nothing resets, so gravity grows every substep; assign, don't add "
                       f"(particle_force[i] = particle_mass * gravity); {message}")
        elif not ok and not results[todos[0]].get("simulation_only"):
            message = "right on single calls, but " + message
        events.emit(event="trajectory", todos=todos, passed=ok, message=message)
