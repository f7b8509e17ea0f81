"""``rigid.fit``: the scene keys that make a run reproduce observed rows, by least squares.

The loss is L = ½ Σ w (simulated − observed)² over the chosen row keys, frames and bodies;
its gradient is one backward pass (rigid.diff.passes), which is what L-BFGS-B needs
(scipy.optimize.minimize). scipy's ``least_squares`` would want the Jacobian of every residual
(one backward pass per observed number), so the scalar loss and its gradient are used instead.
The keys are fitted at the top level (a scene with [[body]] tables is refused for fitting), in
units scaled by their starting size, so that metres, m/s and a restitution move alike.
"""
from __future__ import annotations

import numpy as np

from ..errors import UserError
from . import scope
from .gradient import ensure_taichi, gather, prepare
from .passes import Pass

BOUNDS = {"restitution": (0.0, 1.0), "friction": (0.0, None), "collision_stiffness": (1e-9, None),
          "velocity_damping_stiffness": (0.0, None), "particle_mass": (1e-12, None), "drag": (0.0, None)}


def observed_rows(observed, keys) -> dict:
    """Rows from a dict or an NPZ's path: (frames + 1, B, width) float64 per key (a lone body's
    NPZ rows (F, 3) get their body axis)."""
    if isinstance(observed, (str, bytes)) or hasattr(observed, "__fspath__"):
        with np.load(observed) as data:
            observed = {k: data[k] for k in data.files}
    out = {}
    for key in keys:
        if key not in scope.ROW_KEYS:
            raise UserError(f"keys: {key!r} is not a row; use keys among {', '.join(scope.ROW_KEYS)}")
        if key not in observed:
            raise UserError(f"observed has no {key!r} rows")
        array = np.asarray(observed[key], np.float64)
        out[key] = array[:, None, :] if array.ndim == 2 else array
    return out


def _set(problem, name: str, value) -> None:
    """The top-level key ``name`` = ``value`` into the problem's fields (every body, and the planes
    that take the top-level material)."""
    v = problem.values
    field = {"position": "x0", "orientation": "q0", "initial_velocity": "v0", "initial_angular_velocity": "w0",
             "particle_mass": "m", "drag": "drag", "restitution": "e_b", "friction": "mu_b",
             "collision_stiffness": "k", "velocity_damping_stiffness": "c_world", "gravity": "g"}[name]
    if name == "orientation":  # the scene normalises the key (rigid.config), the pass does too
        value = np.asarray(value, np.float64) / np.linalg.norm(value)
    if scope.WRT_KEYS[name] == "world":
        v[field] = np.asarray(value, np.float64).reshape(np.shape(v[field]))
        return
    v[field] = np.broadcast_to(np.asarray(value, np.float64), v[field].shape).copy()
    if name in ("restitution", "friction"):
        plane_field, column = ("e_p", 1) if name == "restitution" else ("mu_p", 0)
        top = problem.plane_from_top[:, column]
        v[plane_field] = v[plane_field].copy()
        v[plane_field][:len(top)][top] = float(value)


def fit(scene, observed, wrt, frames: int | None = None, keys=("x",), weights=None, steps: int = 100,
        units=None, tolerance: float = 1e-12):
    """Fit the top-level scene keys ``wrt`` so that the rows of ``scene`` match ``observed`` (a dict
    of rows as rigid.Simulator.advance gives them, or an NPZ's path) on ``keys``; ``weights``: a
    scalar or arrays broadcast against each key's rows; ``frames``: the observed rows' length − 1
    by default. Returns (the fitted scene, info) with info["loss"] the loss at each iteration,
    info["rows"] the fitted run's rows, info["values"] the fitted values, info["result"] scipy's."""
    from scipy.optimize import minimize

    rows_obs = observed_rows(observed, keys)
    frames = len(next(iter(rows_obs.values()))) - 1 if frames is None else frames
    problem, names, frames, units = prepare(scene, frames, wrt, units)
    if problem.config.bodies:
        raise UserError("rigid.fit takes top-level keys; a scene with [[body]] tables needs rigid.gradient")
    B = problem.num_bodies
    for key, array in rows_obs.items():
        if array.shape[1:] != (B, scope.ROW_KEYS[key]) or len(array) < frames + 1:
            raise UserError(f"observed {key!r} has shape {array.shape}; {frames + 1} rows of "
                            f"({B}, {scope.ROW_KEYS[key]}) are needed")
        rows_obs[key] = array[:frames + 1]
    w = {key: np.broadcast_to(np.asarray(1.0 if weights is None else (weights[key] if isinstance(weights, dict)
                                                                      else weights), np.float64), a.shape)
         for key, a in rows_obs.items()}
    config = problem.config
    start = [np.asarray(getattr(config, n), np.float64) for n in names]
    sizes = [a.size for a in start]
    x0 = np.concatenate([a.reshape(-1) for a in start])
    scale = np.concatenate([np.full(a.size, max(float(np.abs(a).max()), 1e-3)) for a in start])
    bounds = []
    for n, a in zip(names, start):
        lo, hi = BOUNDS.get(n, (None, None))
        bounds += [(lo, hi)] * a.size
    zbounds = [(None if lo is None else lo / s, None if hi is None else hi / s) for (lo, hi), s in zip(bounds, scale)]
    ensure_taichi()
    run = Pass(problem, units, frames)
    history, evaluations = [], []

    def split(theta):
        return {n: theta[o:o + s].reshape(a.shape) for n, a, o, s in zip(names, start, np.cumsum([0] + sizes), sizes)}

    def loss_and_gradient(z):
        values = split(z * scale)
        for n, value in values.items():
            _set(problem, n, value)
        run.tape.load(problem)
        rows = run.forward()
        cot = {key: w[key] * (rows[key] - rows_obs[key]) for key in rows_obs}
        loss = 0.5 * float(sum((w[key] * (rows[key] - rows_obs[key]) ** 2).sum() for key in rows_obs))
        grads = gather(problem, run.backward(cot), names)
        if "orientation" in grads:  # d(q / |q|)/dq = (I - q̂ q̂ᵀ) / |q|; gather has projected
            grads["orientation"] = grads["orientation"] / np.linalg.norm(values["orientation"])
        evaluations.append(loss)
        return loss, np.concatenate([np.asarray(grads[n]).reshape(-1) for n in names]) * scale

    first, _g = loss_and_gradient(x0 / scale)
    history.append(first)
    result = minimize(loss_and_gradient, x0 / scale, jac=True, method="L-BFGS-B", bounds=zbounds,
                      callback=lambda z: history.append(evaluations[-1]),
                      options=dict(maxiter=steps, ftol=tolerance, gtol=1e-12))
    values = split(result.x * scale)
    for n, value in values.items():
        _set(problem, n, value)
    run.tape.load(problem)
    rows = run.forward()
    fitted = config.replace(**{n: (float(v) if v.ndim == 0 else tuple(float(c) for c in v)) for n, v in values.items()})
    info = dict(loss=history, evaluations=len(evaluations), values=values, rows=rows, result=result,
                message=str(result.message), success=bool(result.success))
    return fitted, info
