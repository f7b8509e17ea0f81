"""The reference's answers, computed once per grader version in a trusted process.

``compute(reference)`` calls the reference units on every TODO's seeded inputs
(and, for TODO 5, the accepted velocity-first unit too) and runs the reference
trajectory in both orders; ``save``/``load`` keep them in an NPZ beside the
warm kernel cache. Children compare against these numbers, so no submission
ever runs in the process that produced them, and a child compiles one
simulator (the submission's) instead of two.

Keys: ``direct/{k}/{form}/{output}`` (K, *shape) and ``trajectory/{form}``
(checkpoints, 10); form is "position-first" or, for TODO 5 and trajectories,
"velocity-first".
"""
import numpy as np

from . import trajectory
from .alternatives import update_linear_velocity_first
from .specs import TODOS, sample_inputs

FORMS = ("position-first", "velocity-first")


def compute(reference) -> dict:
    from .checks import evaluate, mix

    out = {}
    for k, spec in TODOS.items():
        units = {"position-first": getattr(reference, spec.unit)}
        if k == 5:
            units["velocity-first"] = update_linear_velocity_first
        for form, unit in units.items():
            for name, value in evaluate(spec, unit, sample_inputs(k)).items():
                out[f"direct/{k}/{form}/{name}"] = value
    for form in FORMS:
        out[f"trajectory/{form}"] = trajectory.run(mix(reference, reference, [], form == "velocity-first"))
    return out


def save(values: dict, path) -> None:
    np.savez(path, **values)


class Expected:
    def __init__(self, path):
        with np.load(path) as data:
            self.values = {key: data[key] for key in data.files}

    def direct(self, todo: int) -> dict:
        """form -> {output name -> (K, *shape)}"""
        forms = {}
        for key, value in self.values.items():
            kind, k, form, name = (key.split("/") + [None] * 4)[:4]
            if kind == "direct" and int(k) == todo:
                forms.setdefault(form, {})[name] = value
        return forms

    def trajectory(self, form: str) -> np.ndarray:
        return self.values[f"trajectory/{form}"]
