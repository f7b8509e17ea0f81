"""What each TODO unit takes and returns, its default points, and its seeded test inputs.

Shapes below are per call; the grader stacks K calls along a first axis, so an
input of shape (3,) arrives as an array (K, 3), a matrix as (K, 3, 3), a scalar
as (K,). Frames: r0 is body frame; every other vector is world frame.
Mass and Δt are drawn far from 1 and 1e-3, so a missing factor cannot hide,
and Δt is large enough that an O(Δt²) slip (a wrong order of updates) shows.
"""
from dataclasses import dataclass

import numpy as np

from ..engine.rotation import quaternion_to_matrix_np
from ..engine.units import UNIT_NAMES

SAMPLES = 64  # random calls per unit
SEED = 20240531


@dataclass(frozen=True)
class TodoSpec:
    number: int
    unit: str  # function name in the assignment file
    title: str
    points: float  # default share of the 90
    inputs: tuple  # ((name, shape), ...) in call order
    outputs: tuple  # ((name, shape, label), ...) in return order
    updates: tuple = ()  # ((output, input), ...): the output is a new value of that input

    def columns(self, which: str) -> dict:
        """name -> (first column, shape) when the inputs or outputs are packed side by side."""
        cols, start = {}, 0
        for name, shape, *_ in (self.inputs if which == "inputs" else self.outputs):
            cols[name] = (start, shape)
            start += int(np.prod(shape, dtype=int))
        return cols

    def width(self, which: str) -> int:
        return sum(int(np.prod(s[1], dtype=int)) for s in (self.inputs if which == "inputs" else self.outputs))


V3, Q4, M33, S = (3,), (4,), (3, 3), ()

TODOS = {
    1: TodoSpec(1, "particle_inertia", "inertia tensor I0", 15, (("m", S), ("r0", V3)),
                (("I", M33, "the particle's inertia"),)),
    2: TodoSpec(2, "gravity_force", "gravity", 10, (("m", S), ("g", V3)),
                (("f", V3, "the force of gravity"),)),
    3: TodoSpec(3, "total_force_term", "total force", 10, (("f", V3),),
                (("F", V3, "the particle's share of the total force"),)),
    4: TodoSpec(4, "torque_term", "torque", 15, (("p", V3), ("x", V3), ("R", M33), ("r0", V3), ("f", V3)),
                (("tau", V3, "the torque"),)),
    5: TodoSpec(5, "update_linear", "update x and P", 10,
                (("x", V3), ("P", V3), ("F", V3), ("M", S), ("dt", S)),
                (("x_new", V3, "the new position x"), ("P_new", V3, "the new momentum P")),
                (("x_new", "x"), ("P_new", "P"))),
    6: TodoSpec(6, "update_orientation", "update q", 15, (("q", Q4), ("omega", V3), ("dt", S)),
                (("q_new", Q4, "the new quaternion q"),), (("q_new", "q"),)),
    7: TodoSpec(7, "update_angular", "update L, I⁻¹ and ω", 15,
                (("L", V3), ("tau", V3), ("R", M33), ("I0_inv", M33), ("dt", S)),
                (("L_new", V3, "the new angular momentum L"), ("I_inv", M33, "I⁻¹"),
                 ("omega", V3, "ω")),
                (("L_new", "L"),)),
}
assert tuple(t.unit for t in TODOS.values()) == UNIT_NAMES
DEFAULT_POINTS = {k: t.points for k, t in TODOS.items()}


def random_rotations(rng, n) -> np.ndarray:
    """(n, 3, 3) rotation matrices from uniformly random unit quaternions."""
    q = rng.normal(size=(n, 4))
    return np.stack([quaternion_to_matrix_np(qi) for qi in q])


def random_inverse_inertias(rng, n) -> np.ndarray:
    """(n, 3, 3) symmetric positive definite I0⁻¹ with unequal principal moments."""
    axes = random_rotations(rng, n)
    moments = rng.uniform(0.2, 3.0, size=(n, 3))
    return np.einsum("nij,nj,nkj->nik", axes, 1.0 / moments, axes)


def sample_inputs(todo: int, n: int = SAMPLES, seed: int = SEED) -> dict:
    """Seeded random inputs of one TODO: name -> array (n, *shape), float64."""
    rng = np.random.default_rng(seed + todo)
    mass = rng.uniform(0.3, 3.0, n)
    dt = rng.uniform(0.02, 0.06, n)
    vec = lambda scale: rng.normal(scale=scale, size=(n, 3))  # noqa: E731
    if todo == 1:
        return dict(m=mass, r0=vec(1.0))
    if todo == 2:
        return dict(m=mass, g=vec(5.0))
    if todo == 3:
        return dict(f=vec(5.0))
    if todo == 4:
        x, R, r0 = vec(2.0), random_rotations(rng, n), vec(1.0)
        return dict(p=x + np.einsum("nij,nj->ni", R, r0), x=x, R=R, r0=r0, f=vec(5.0))
    if todo == 5:
        M = rng.uniform(0.5, 4.0, n)
        return dict(x=vec(1.0), P=vec(3.0) * M[:, None], F=vec(20.0) * M[:, None], M=M, dt=dt)
    if todo == 6:
        q = rng.normal(size=(n, 4))
        return dict(q=q / np.linalg.norm(q, axis=1, keepdims=True), omega=vec(5.0), dt=dt)
    if todo == 7:
        return dict(L=vec(2.0), tau=vec(5.0), R=random_rotations(rng, n),
                    I0_inv=random_inverse_inertias(rng, n), dt=dt)
    raise ValueError(f"no TODO {todo}")


def pack(spec: TodoSpec, values: dict, which: str = "inputs") -> np.ndarray:
    """Stack named arrays into one (n, width) float64 array in the spec's column order."""
    items = spec.inputs if which == "inputs" else spec.outputs
    n = len(values[items[0][0]])
    return np.ascontiguousarray(np.concatenate([np.asarray(values[name], np.float64).reshape(n, -1)
                                                for name, *_ in items], axis=1))


def unpack(spec: TodoSpec, array: np.ndarray, which: str = "outputs") -> dict:
    """The inverse of pack: name -> (n, *shape)."""
    n = len(array)
    return {name: array[:, start:start + int(np.prod(shape, dtype=int))].reshape((n, *shape))
            for name, (start, shape) in spec.columns(which).items()}
