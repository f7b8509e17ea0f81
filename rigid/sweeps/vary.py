"""``--vary KEY=START:STOP:N`` and ``--vary KEY=a,b,c``: which scene keys vary, over which values.

A range is ``numpy.linspace(START, STOP, N)`` (both ends included), each value rounded to 12
significant digits so that the run, its file and index.csv all hold the value as written
(0.3, not 0.30000000000000004). A list is the values as given. A vector key varies one
component at a time: ``initial_velocity.x``, ``gravity.y``.

The runs are the product of the varied values, times ``--seeds N`` (the scene's seed, +1, ...,
innermost), numbered in that order: run-0000, run-0001, ... Every run's config is built and
validated here, so a bad value is one line before anything runs.
"""
from __future__ import annotations

import difflib
import itertools
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from ..config import BODY_KEYS, SimConfig, resolve_mesh
from ..errors import UserError

# Keys that are not one value per run, and what to do instead.
FIXED = {
    "frames": "--frames sets every run's",
    "seed": "use --seeds N (the scene's seed, +1, ...)",
    "arch": "every worker starts Taichi once, on one backend: set it in the scene file",
    "fp64": "every worker starts Taichi once, in one precision: set it in the scene file",
    "resolution": "set it in the scene file (the videos' size)",
    "camera": "set the [camera] table in the scene file",
    "orientation": "a quaternion is renormalised as a whole: write one scene file per orientation",
    "bodies": "tables do not vary: write one scene file per variant",
    "planes": "tables do not vary: write one scene file per variant",
    "statics": "tables do not vary: write one scene file per variant",
    "springs": "tables do not vary: write one scene file per variant",
}
VECTORS = ("position", "initial_velocity", "initial_angular_velocity", "gravity")
AXES = "xyz"
FLOAT_OR_NONE = ("particle_radius", "restitution", "friction")  # None by default, numbers when set


@dataclass(frozen=True)
class Vary:
    key: str  # a scene key, or VECTOR.x|y|z
    values: tuple


@dataclass(frozen=True)
class Run:
    name: str  # run-0000, ...: the file names under runs/ and the index's first column
    values: dict  # varied key -> value
    seed: int
    config: SimConfig


def parse_vary(spec: str) -> Vary:
    """One ``KEY=START:STOP:N`` or ``KEY=a,b,c``."""
    key, sep, text = str(spec).partition("=")
    key, text = key.strip(), text.strip()
    if not sep or not key or not text:
        raise UserError(f"--vary {spec}: use KEY=START:STOP:N or KEY=a,b,c, e.g. --vary restitution=0.2:0.8:4")
    kind = key_kind(key, spec)
    if ":" in text:
        return Vary(key, _range(key, kind, text, spec))
    return Vary(key, tuple(_value(key, kind, item.strip(), spec) for item in text.split(",")))


def as_varies(vary) -> list[Vary]:
    """The API's ``vary``: {KEY: [values] or "START:STOP:N" or "a,b,c"}, or ["KEY=SPEC", ...]."""
    if isinstance(vary, dict):
        specs = [f"{k}={v}" if isinstance(v, str) else f"{k}=" + ",".join(map(str, v)) for k, v in vary.items()]
    elif isinstance(vary, str):
        specs = [vary]
    else:
        specs = list(vary or ())
    varies = [parse_vary(s) for s in specs]
    seen = set()
    for v in varies:
        if v.key in seen:
            raise UserError(f"--vary {v.key} is given twice; give its values once, e.g. --vary {v.key}=a,b,c")
        seen.add(v.key)
    return varies


def key_kind(key: str, spec: str) -> str:
    """"float", "int", "bool" or "str" for a key that may vary; one line for one that may not."""
    base, dot, axis = key.partition(".")
    names = {f.name for f in fields(SimConfig)}
    if base not in names:
        close = difflib.get_close_matches(base, names - set(FIXED), n=1)
        hint = f"did you mean {close[0]!r}?" if close else "see docs/scenes.md for the scene keys"
        raise UserError(f"--vary {spec}: unknown scene key {base!r}; {hint}")
    if base in FIXED:
        raise UserError(f"--vary {spec}: {base} cannot vary; {FIXED[base]}")
    if base in VECTORS:
        if not dot or axis not in AXES:
            raise UserError(f"--vary {spec}: {base} is a vector; vary one component: {base}.x, {base}.y or {base}.z")
        return "float"
    if dot:
        raise UserError(f"--vary {spec}: {base} is not a vector; write --vary {base}=...")
    default = getattr(SimConfig(), base)
    if base in FLOAT_OR_NONE or isinstance(default, float):
        return "float"
    if isinstance(default, bool):
        return "bool"
    return "int" if isinstance(default, int) else "str"


def _range(key: str, kind: str, text: str, spec: str) -> tuple:
    parts = text.split(":")
    if len(parts) != 3 or kind in ("bool", "str"):
        want = "a list a,b,c" if kind in ("bool", "str") else "START:STOP:N, e.g. 0.2:0.8:4"
        raise UserError(f"--vary {spec}: {key} takes {want}")
    try:
        start, stop = float(parts[0]), float(parts[1])
        count = int(parts[2])
    except ValueError:
        raise UserError(f"--vary {spec}: START and STOP must be numbers and N a whole number, "
                        f"e.g. {key}=0.2:0.8:4") from None
    if not (np.isfinite(start) and np.isfinite(stop)) or count < 1 or (count == 1 and start != stop):
        raise UserError(f"--vary {spec}: use finite START and STOP and N >= 2 values (N = 1 only when START = STOP)")
    values = [float(f"{v:.12g}") for v in np.linspace(start, stop, count)]
    if kind == "int":
        if any(v != round(v) for v in values):
            raise UserError(f"--vary {spec}: {key} takes whole numbers, and this range gives "
                            f"{next(v for v in values if v != round(v)):g}; pick START, STOP and N that step by whole numbers")
        values = [int(round(v)) for v in values]
    if len(set(values)) != len(values):
        raise UserError(f"--vary {spec}: the range repeats values; use fewer values (N)")
    return tuple(values)


def _value(key: str, kind: str, item: str, spec: str):
    try:
        if kind == "float":
            value = float(item)
            if not np.isfinite(value):
                raise ValueError
            return float(f"{value:.12g}")
        if kind == "int":
            return int(item)
    except ValueError:
        word = "a whole number" if kind == "int" else "a finite number"
        raise UserError(f"--vary {spec}: {item!r} is not {word}; {key} takes numbers, e.g. {key}=1,2,3") from None
    if kind == "bool":
        if item.lower() not in ("true", "false"):
            raise UserError(f"--vary {spec}: {key} takes true or false, e.g. {key}=true,false")
        return item.lower() == "true"
    if not item:
        raise UserError(f"--vary {spec}: an empty value; write the values between commas, e.g. {key}=a,b")
    return item


def plan_runs(base: SimConfig, varies: list[Vary], seeds: int = 1) -> list[Run]:
    """Every run of the sweep, its config validated: one line for the first bad one."""
    if not isinstance(seeds, int) or isinstance(seeds, bool) or seeds < 1:
        raise UserError(f"--seeds {seeds}: use a whole number of seeds, 1 or more")
    for v in varies:
        _check_not_overridden(base, v.key)
        if len(set(v.values)) != len(v.values):
            raise UserError(f"--vary {v.key}: a value is given twice; give each once")
    combos = list(itertools.product(*(v.values for v in varies)))
    total = len(combos) * seeds
    width = max(4, len(str(total - 1)))
    runs = []
    for combo in combos:
        values = dict(zip((v.key for v in varies), combo))
        for s in range(seeds):
            seed = base.seed + s
            config = _config(base, values, seed)
            runs.append(Run(f"run-{len(runs):0{width}d}", values, seed, config))
    return runs


def _config(base: SimConfig, values: dict, seed: int) -> SimConfig:
    changes = {"seed": seed}
    for key, value in values.items():
        name, _, axis = key.partition(".")
        if axis:
            vector = list(changes.get(name, getattr(base, name)))
            vector[AXES.index(axis)] = value
            value = tuple(vector)
        elif name == "mesh":
            value = resolve_mesh(Path.cwd() / "scene.toml", value)  # as --mesh: the working folder, then assets/
        changes[name] = value
    try:
        return base.replace(**changes).validate()
    except UserError as err:
        shown = ", ".join(f"{k}={v}" for k, v in values.items())
        raise UserError(f"--vary: the run with {shown}: {err}") from None


def _check_not_overridden(base: SimConfig, key: str) -> None:
    """A top-level body key that every [[body]] table sets would change nothing."""
    name = key.partition(".")[0]
    if name in BODY_KEYS and base.bodies and all(name in table for table in base.bodies):
        raise UserError(f"--vary {key}: every [[body]] table of the scene sets {name}, so the top-level value "
                        f"changes nothing; vary another key, or remove {name} from a table")
