"""A scene's ``[[spring]]`` tables, checked and resolved to numbers (no Taichi here).

A spring joins a point of one body to a point of another (or of the world, body −1):

    bodies = [a, b]            scene order of the bodies (after ``count`` copies); −1 is the world
    points = [[x, y, z], ...]  each in its body's frame, relative to its centre of mass; a world
                               point for −1
    stiffness = k              N/m, >= 0
    damping = c                N s/m along the spring, >= 0 (default 0)
    rest_length = l0           m, >= 0 (default: the points' distance at the start)

The force on a's end is f = (k (|d| − l0) + c (v_b − v_a)·n) n, with d = p_b − p_a, n = d/|d|;
b's end gets −f. The engine applies it at the two points through TODO 3 and 4 (rigid.engine.forces).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import UserError
from .quaternion import quaternion_to_matrix_np

SPRING_KEYS = ("bodies", "points", "stiffness", "damping", "rest_length")
WORLD = -1


@dataclass(frozen=True)
class Spring:
    a: int  # body index, or WORLD
    b: int
    point_a: tuple  # body frame about the centre of mass (world frame for WORLD), m
    point_b: tuple
    stiffness: float
    damping: float
    rest_length: float

    def row(self) -> list:
        """The 16 numbers the kernels read (rigid.engine.forces: a, b, point a, point b, k, c, l0)."""
        return [self.a, self.b, *self.point_a, *self.point_b, self.stiffness, self.damping, self.rest_length,
                0.0, 0.0, 0.0, 0.0, 0.0]


def _where(i: int) -> str:
    return f"[[spring]] {i + 1}"


def _number(i, key, value, default=None) -> float:
    if value is None:
        if default is None:
            raise UserError(f"{_where(i)}: no '{key}'; give it, e.g. {key} = 100.0")
        return default
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) or value < 0:
        raise UserError(f"{_where(i)}: {key} = {value!r}; use a number >= 0")
    return float(value)


def _point(i, k, value) -> tuple:
    if (not isinstance(value, (list, tuple)) or len(value) != 3
            or not all(isinstance(c, (int, float)) and not isinstance(c, bool) and np.isfinite(c) for c in value)):
        raise UserError(f"{_where(i)}: point {k + 1} = {value!r}; use three numbers [x, y, z]")
    return tuple(float(c) for c in value)


def check_spring_tables(tables) -> tuple:
    """The [[spring]] tables' keys and shapes (before the bodies are known): one line for a bad one."""
    if not isinstance(tables, (list, tuple)) or not all(isinstance(t, dict) for t in tables):
        raise UserError("'spring' must be [[spring]] tables (bodies, points, stiffness, damping, rest_length)")
    for i, table in enumerate(tables):
        unknown = sorted(set(table) - set(SPRING_KEYS))
        if unknown:
            raise UserError(f"{_where(i)}: unknown key {unknown[0]!r}; spring keys: {', '.join(SPRING_KEYS)}")
        bodies, points = table.get("bodies"), table.get("points")
        if (not isinstance(bodies, (list, tuple)) or len(bodies) != 2
                or not all(isinstance(b, int) and not isinstance(b, bool) for b in bodies)):
            raise UserError(f"{_where(i)}: bodies = {bodies!r}; use two body indices, e.g. bodies = [0, 1] "
                            f"(-1 is the world)")
        if not isinstance(points, (list, tuple)) or len(points) != 2:
            raise UserError(f"{_where(i)}: points = {points!r}; give two points, one for each end, "
                            f"e.g. points = [[0, 0.1, 0], [0, 0, 0]]")
        for k, p in enumerate(points):
            _point(i, k, p)
        _number(i, "stiffness", table.get("stiffness"))
        _number(i, "damping", table.get("damping"), 0.0)
        if table.get("rest_length") is not None:
            _number(i, "rest_length", table["rest_length"])
    return tuple(dict(t) for t in tables)


def resolve_springs(tables, positions: np.ndarray, orientations: np.ndarray) -> list[Spring]:
    """The springs of a scene whose bodies (in scene order) start at ``positions`` (B, 3) with
    ``orientations`` (B, 4): indices checked against B, missing rest lengths measured."""
    B = len(positions)
    springs = []
    for i, table in enumerate(check_spring_tables(tables)):
        ends = []
        for k, (body, point) in enumerate(zip(table["bodies"], table["points"])):
            if not WORLD <= body < B:
                raise UserError(f"{_where(i)}: body {body} does not exist: the scene has {B} bodies "
                                f"(0 to {B - 1}; -1 is the world)")
            p = _point(i, k, point)
            ends.append((body, p, _world_point(body, p, positions, orientations)))
        if ends[0][0] == ends[1][0]:
            raise UserError(f"{_where(i)}: both ends are on body {ends[0][0]}; a spring joins two bodies "
                            f"(or a body and the world, -1)")
        rest = table.get("rest_length")
        rest = float(np.linalg.norm(ends[1][2] - ends[0][2])) if rest is None else float(rest)
        springs.append(Spring(ends[0][0], ends[1][0], ends[0][1], ends[1][1], _number(i, "stiffness", table["stiffness"]),
                              _number(i, "damping", table.get("damping"), 0.0), rest))
    return springs


def _world_point(body: int, point, x, q) -> np.ndarray:
    """Where ``point`` (body ``body``'s frame about its centre of mass; a world point for WORLD) is
    in the world, for bodies at ``x`` (..., B, 3) and ``q`` (..., B, 4): float64 (..., 3)."""
    p, x, q = (np.asarray(a, np.float64) for a in (point, x, q))
    if body == WORLD:
        return np.broadcast_to(p, x.shape[:-2] + (3,))
    R = np.array([quaternion_to_matrix_np(qq) for qq in q[..., body, :].reshape(-1, 4)])
    return x[..., body, :] + (R @ p).reshape(x.shape[:-2] + (3,))


def spring_ends(springs: list[Spring], x: np.ndarray, q: np.ndarray) -> np.ndarray:
    """(2 S, 3) world positions of each spring's two ends, for bodies at ``x`` (B, 3), ``q`` (B, 4)."""
    ends = [_world_point(body, point, x, q) for s in springs for body, point in ((s.a, s.point_a), (s.b, s.point_b))]
    return np.array(ends).reshape(-1, 3)


def spring_energy(springs: list[Spring], x: np.ndarray, q: np.ndarray) -> np.ndarray:
    """½ k (|d| − l0)² summed over the springs, for each row of bodies' states ``x`` (F, B, 3),
    ``q`` (F, B, 4): float64 (F,)."""
    energy = np.zeros(len(x))
    for s in springs:
        stretch = np.linalg.norm(_world_point(s.b, s.point_b, x, q) - _world_point(s.a, s.point_a, x, q),
                                 axis=1) - s.rest_length
        energy += 0.5 * s.stiffness * stretch * stretch
    return energy
