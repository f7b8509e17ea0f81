"""``rigid.gradient``: ∂L/∂(scene keys) of a scalar loss L of the rows, by reverse mode.

The caller gives ∂L/∂rows (``cotangents``, shaped as rigid.Simulator.advance's rows), so any
loss written in numpy works: the pass runs forward, then backward once (rigid.diff.passes),
and the adjoints of its parameter fields are gathered into the scene's keys:

- a world key (gravity, collision_stiffness, velocity_damping_stiffness) has its own shape;
- a body key (position, orientation, initial_velocity, initial_angular_velocity,
  particle_mass, drag, restitution, friction) has the top level's shape, summed over the
  bodies (and, for restitution and friction, over the planes that take the top-level value,
  as a change of the top-level key changes them all); with [[body]] tables it has a body axis
  (B, ...) instead: each body's own value (a plane's material is then held fixed).
- orientation's gradient is tangent to the unit sphere (orthogonal to the quaternion): the scene
  normalises the key, so a change along q changes nothing (``tangent``).
"""
from __future__ import annotations

import numpy as np

from . import scope
from .passes import Pass
from .problem import build_problem

FIELD_OF = {"position": "x0", "orientation": "q0", "initial_velocity": "v0", "initial_angular_velocity": "w0",
            "particle_mass": "m", "drag": "drag", "restitution": "e_b", "friction": "mu_b",
            "collision_stiffness": "k", "velocity_damping_stiffness": "c_world", "gravity": "g"}
PLANE_FIELD = {"restitution": ("e_p", 1), "friction": ("mu_p", 0)}


def ensure_taichi() -> None:
    """Start Taichi in float64 on the CPU if this process has not started it (gradients are
    float64 by default); a process already started keeps its precision."""
    from .. import runtime

    if runtime._initialised is None:
        runtime.init_taichi("cpu", fp64=True)


def scene_config(scene):
    """A SimConfig from a scene TOML's path, a dict of scene keys (as rigid.scene takes them) or a
    SimConfig; a relative mesh is looked up in the working folder, then in the assets."""
    from pathlib import Path

    from ..config import SimConfig, load_scene, resolve_mesh

    if isinstance(scene, SimConfig):
        return scene.validate()
    if isinstance(scene, dict):
        keys = dict(scene)
        here = Path.cwd() / "scene.toml"
        if "mesh" in keys:
            keys["mesh"] = resolve_mesh(here, str(keys["mesh"]))
        if "bodies" in keys:
            keys["bodies"] = tuple({**b, **({"mesh": resolve_mesh(here, str(b["mesh"]))} if "mesh" in b else {})}
                                   for b in keys["bodies"])
        for key in ("position", "orientation", "initial_velocity", "initial_angular_velocity", "gravity", "planes"):
            if key in keys and not isinstance(keys[key], tuple):
                keys[key] = tuple(keys[key])
        return SimConfig(**keys).validate()
    return SimConfig(**load_scene(scene)).validate()


def prepare(scene, frames, wrt, units=None):
    """Checks (one line each, before any compile), then the Problem and a Pass ready to run."""
    from ..engine.units import check_units, default_units

    config = scene_config(scene)
    scope.check_scene(config)
    names = scope.check_wrt(config, wrt)
    frames = scope.check_frames(frames)
    problem = build_problem(config)
    units = default_units() if units is None else units
    check_units(units)
    return problem, names, frames, units


def gather(problem, grads: dict, names) -> dict:
    """The parameter fields' adjoints as the scene keys' gradients (see the module's docstring)."""
    B = problem.num_bodies
    per_body = bool(problem.config.bodies)
    out = {}
    for name in names:
        g = np.asarray(grads[FIELD_OF[name]], np.float64)
        if scope.WRT_KEYS[name] == "world":
            out[name] = g.reshape(np.shape(problem.values[FIELD_OF[name]]))
            continue
        g = g[:B]
        if name == "orientation":
            g = tangent(g, problem.values["q0"][:B])
        if per_body:
            out[name] = g
            continue
        total = g.sum(axis=0)
        if name in PLANE_FIELD:
            field, column = PLANE_FIELD[name]
            planes = len(problem.planes)
            total = total + np.asarray(grads[field])[:planes][problem.plane_from_top[:, column]].sum()
        out[name] = total
    return out


def tangent(g, q):
    """∂L/∂q with its part along q removed, per body: the scene's orientation is normalised (the
    config divides the key by its norm), so L depends on the key only through q / |q| and its
    gradient at a unit q is (I − q qᵀ) ∂L/∂q (for a key of norm r, that divided by r)."""
    q = np.asarray(q, np.float64) / np.linalg.norm(q, axis=-1, keepdims=True)
    return g - (g * q).sum(axis=-1, keepdims=True) * q


def gradient(scene, frames: int, cotangents: dict, wrt, units=None, checkpoint_frames: int | None = None) -> dict:
    """∂L/∂(each ``wrt`` key) for a loss L of the rows of ``frames`` frames of ``scene`` (a scene
    TOML's path, a dict of scene keys or a rigid.scene config), given ``cotangents`` = ∂L/∂rows:
    a dict with keys among x, v, q, omega, P, L, each shaped like advance(frames)'s rows
    ((frames + 1, B, 3), q (frames + 1, B, 4)). ``units``: the TODO units (default: the
    repository's solution). Starts Taichi in float64 on the CPU unless the process has started it."""
    problem, names, frames, units = prepare(scene, frames, wrt, units)
    cot = scope.check_cotangents(cotangents, frames, problem.num_bodies)
    ensure_taichi()
    run = Pass(problem, units, frames, **({} if checkpoint_frames is None else dict(checkpoint_frames=checkpoint_frames)))
    run.forward()
    return gather(problem, run.backward(cot), names)


def rows(scene, frames: int, units=None) -> dict:
    """The differentiable pass's forward rows of ``scene`` (for comparing with rigid.Simulator)."""
    problem, _names, frames, units = prepare(scene, frames, ["gravity"], units)
    ensure_taichi()
    return Pass(problem, units, frames).forward()
