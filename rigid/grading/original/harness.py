"""Each TODO region alone in a kernel, called on the grader's seeded inputs (the direct check).

``source(regions, lines, fields)`` writes one kernel ``grader_todo{k}`` per
region, inserted into the reference version of the file (variants.py), so the
region's code runs on the file's own fields and helpers. Each call sets the
body's fields from one row of inputs (STATE), runs the region, and returns what
the TODO computes: the inertia (1), a particle's force (2), the total force (3)
and torque (4), the new x and v (5), the new quaternion, renormalised as the
given code does (6), the new L and ω (7). The body's original centre
``body_origin_cm_position`` is zero and particle 0's ``particle_origin_vertices``
is r0, so a lever arm written R (r_orig − x_orig), as the handout's particle
update does, or p − x, both read R r0. ``dt``, ``particle_mass`` and
``gravity`` are kernel arguments named like the file's globals, so inside the
region they take each call's values (specs.py draws them far from the handout's
1, 1 ms and -9.8 y). ``evaluate`` turns the results into the outputs of
specs.TODOS, so checks.judge compares them with the reference's answers and
names the mistake exactly as for the project's format. TODO 7's I⁻¹ is a
local of the region here, never seen: only L and ω are compared.

A region that reads a module-level name computed from dt, the mass or gravity
(``half_dt = 0.5 * dt``, or a helper function that reads dt) cannot be given
other values this way: ``blocked_by`` names it, and that TODO is graded by the
simulations alone.
"""
import ast
import re
from dataclasses import replace

import numpy as np

from ...engine.rotation import quaternion_to_matrix_np
from ..specs import TODOS, sample_inputs

PARAMS = ("dt", "particle_mass", "gravity")
STATE = (("x", 3), ("p0", 3), ("r0", 3), ("f0", 3), ("v", 3), ("w", 3), ("R", 9), ("q", 4), ("L", 3),
         ("I0_inv", 9), ("M", 1), ("shared", 3))
OFFSET = {name: sum(n for _, n in STATE[:i]) for i, (name, _) in enumerate(STATE)}
ZERO = "ti.Vector([0.0, 0.0, 0.0])"
RETURNS = {1: "ti.types.matrix(3, 3, ti.f64)", 5: "ti.types.vector(6, ti.f64)", 6: "ti.types.vector(4, ti.f64)",
           7: "ti.types.vector(6, ti.f64)"}


def _get(name: str) -> str:
    o, n = OFFSET[name], dict(STATE)[name]
    if n == 1:
        return f"grader_in[{o}]"
    if n == 9:
        return "ti.Matrix([" + ", ".join("[" + ", ".join(f"grader_in[{o + 3 * r + c}]" for c in range(3)) + "]"
                                         for r in range(3)) + "])"
    return "ti.Vector([" + ", ".join(f"grader_in[{o + c}]" for c in range(n)) + "])"


SETUP = (("body_cm_position", "x"), ("body_origin_cm_position", None), ("body_velocity", "v"),
         ("body_angular_velocity", "w"), ("body_rotation", "R"), ("body_rotation_quaternion", "q"),
         ("body_angular_momentum", "L"), ("body_origin_inverse_inertia", "I0_inv"), ("body_mass", "M"))
PARTICLES = (("particle_vertices", "x", "p0"), ("particle_origin_vertices", None, "r0"),
             ("particle_velocities", None, None), ("particle_force", None, "f0"))


def _result(k: int, region) -> str:
    if k in (1, 3, 4):
        return region.shared
    if k == 2:
        return "particle_force[0]"
    if k == 6:
        return "body_rotation_quaternion[None]"
    x, v = ("body_cm_position", "body_velocity") if k == 5 else ("body_angular_momentum", "body_angular_velocity")
    return "ti.Vector([" + ", ".join(f"{f}[None][{c}]" for f in (x, v) for c in range(3)) + "])"


def _reindent(text: str, old: str, new: str) -> list:
    return [new + (line[len(old):] if line.startswith(old) else line.lstrip()) for line in text.splitlines()]


def kernel(k: int, model) -> list:
    """The source lines of kernel grader_todo{k} for a variants.FileModel."""
    region, lines, fields = model.regions[k], model.text.splitlines(), model.assignments
    out = ["@ti.kernel",
           f"def grader_todo{k}(dt: ti.f64, particle_mass: ti.f64, gravity: ti.types.vector(3, ti.f64),",
           f"                   grader_in: ti.types.ndarray(dtype=ti.f64, ndim=1)) -> {RETURNS.get(k, 'ti.types.vector(3, ti.f64)')}:",
           "    for grader_j in particle_vertices:"]
    out += [f"        {f}[grader_j] = {_get(v) if v else ZERO}" for f, v, _ in PARTICLES if f in fields]
    out += [f"    {f}[0] = {_get(v)}" for f, _, v in PARTICLES if v and f in fields]
    out += [f"    {f}[None] = {_get(v) if v else ZERO}" for f, v in SETUP if f in fields]
    body = "    "
    if k in (1, 3, 4) and region.loop_var:  # the local the given code declares before the loop (handout)
        out.append(f"    {region.shared} = {'ti.Matrix.zero(float, 3, 3)' if k == 1 else ZERO}")
    if region.loop_var:
        out.append(f"    {region.loop_header}")
        for statement in region.loop_context:
            out += _reindent(statement, region.indent, "        ")
        body = "        "
    else:
        for statement in region.context:
            out += _reindent(statement, region.indent, "    ")
    if k in (1, 3, 4) and not region.loop_var:
        out.append(f"    {region.shared} = {'ti.Matrix.zero(float, 3, 3)' if k == 1 else ZERO}")
    if k in (5, 7):  # the total force (TODO 3's local) or torque (TODO 4's) it reads
        name = model.shared[3 if k == 5 else 4] or ("body_force" if k == 5 else "body_torque")
        out.append(f"    {name} = {_get('shared')}")
    for line in region.code(lines):
        out += _reindent(line, region.indent, body) if line.strip() else [""]
    out.append(f"{body}pass")  # an empty region in a loop
    out.append(f"    return {_result(k, region)}")
    return [line + "\n" for line in out] + ["\n\n"]


def rows(k: int, particles: int) -> tuple:
    """(inputs of specs.sample_inputs, per-call kernel arguments (dt, m, g, row))."""
    d = sample_inputs(k)
    n = len(next(iter(d.values())))
    state = np.zeros((n, OFFSET["shared"] + 3))

    def put(name, value):
        state[:, OFFSET[name]:OFFSET[name] + dict(STATE)[name]] = np.asarray(value, np.float64).reshape(n, -1)

    put("R", np.tile(np.eye(3).ravel(), (n, 1)))
    put("I0_inv", np.tile(np.eye(3).ravel(), (n, 1)))
    put("q", np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)))
    dt, m, g = np.full(n, 0.03), np.full(n, 0.9), np.tile([0.0, -9.8, 0.0], (n, 1))
    values = {}  # state name -> (K, n) values of this TODO's inputs
    if k == 1:  # the other particles sit at the centre of mass: an identity term per particle sums to M E
        m = d["m"]
        values.update(p0=d["r0"], r0=d["r0"])
        d = dict(d, M_body=m * particles)
    elif k == 2:  # a force left from the previous substep: `particle_force[i] += m g` shows as such
        m, g = d["m"], d["g"]
        values.update(f0=leftover_force(n))
    elif k == 3:
        values.update(f0=d["f"])
    elif k == 4:
        values.update(x=d["x"], p0=d["p"], r0=d["r0"], f0=d["f"], R=d["R"],
                      q=[matrix_to_quaternion(R) for R in d["R"]])
    elif k == 5:
        dt, m = d["dt"], d["M"] / particles
        values.update(x=d["x"], v=d["P"] / d["M"][:, None], shared=d["F"], M=d["M"])
    elif k == 6:
        dt = d["dt"]
        values.update(q=d["q"], w=d["omega"], R=[quaternion_to_matrix_np(q) for q in d["q"]])
    else:
        dt = d["dt"]
        values.update(L=d["L"], shared=d["tau"], R=d["R"], I0_inv=d["I0_inv"],
                      q=[matrix_to_quaternion(R) for R in d["R"]])
    if k in (3, 4):  # a particle mass that varies from call to call, so an extra factor m is named as such
        m = 0.5 + 2.0 * (np.arange(n) % 7) / 6
        d = dict(d, m=m)
    for name, value in values.items():
        put(name, value)
    if k != 5:
        put("M", m * particles)
    return d, list(zip(dt, m, g, state))


def evaluate(k: int, module, particles: int) -> tuple:
    """(spec to judge with, inputs, outputs name -> (K, ...)) of the region of TODO k in ``module``."""
    import taichi as ti

    run = getattr(module, f"grader_todo{k}")
    d, calls = rows(k, particles)
    out = np.array([np.asarray(run(float(dt), float(m), ti.Vector(list(g)), np.ascontiguousarray(row)),
                               np.float64) for dt, m, g, row in calls])
    spec = TODOS[k]
    if k == 5:
        v = _kept(out[:, 3:], d["P"] / d["M"][:, None])
        sub = {"x_new": _kept(out[:, :3], d["x"]), "P_new": v * d["M"][:, None]}
    elif k == 6:
        norm = np.linalg.norm(out, axis=1, keepdims=True)
        sub = {"q_new": _kept(out, d["q"], out / np.where(norm > 0, norm, 1.0))}
    elif k == 7:
        sub = {"L_new": _kept(out[:, :3], d["L"]), "omega": out[:, 3:]}
        spec = replace(spec, outputs=tuple(o for o in spec.outputs if o[0] != "I_inv"))
    elif k == 2:  # the force left as it was (the handout's placeholder) reads as not done
        left = leftover_force(len(out))
        sub = {"f": np.where(np.all(out == left.astype(np.float32), axis=1, keepdims=True), 0.0, out)}
    else:
        sub = {spec.outputs[0][0]: out}
    labels = {1: "the inertia tensor", 3: "the total force"}
    if k in labels:
        spec = replace(spec, outputs=((spec.outputs[0][0], spec.outputs[0][1], labels[k]),))
    return spec, d, sub


def leftover_force(n: int) -> np.ndarray:
    """The particle's force before TODO 2 runs in its direct check: what the previous substep left."""
    return np.stack([np.linspace(-3.0, 2.0, n), np.linspace(1.5, -2.5, n), np.full(n, 0.75)], axis=1)


def _kept(out, given, changed=None):
    """Calls whose field still holds the given value (as float32) report that value exactly, so
    untouched code reads as 'unchanged' (the placeholder); the others report ``changed`` (default out)."""
    same = np.all(out == np.asarray(given, np.float32).astype(np.float64), axis=1, keepdims=True)
    return np.where(same, given, out if changed is None else changed)


def matrix_to_quaternion(R) -> np.ndarray:
    """A unit quaternion (scalar first) of the rotation matrix R."""
    R = np.asarray(R, np.float64).reshape(3, 3)
    w = np.sqrt(max(0.0, 1.0 + np.trace(R))) / 2
    x = np.copysign(np.sqrt(max(0.0, 1.0 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1.0 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1.0 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    return np.array([w, x, y, z])


def blocked_by(text: str, region_code: list):
    """A module-level name the region reads that depends on dt, the mass or gravity, or None."""
    tree = ast.parse(text)
    tainted, defs = set(PARAMS), {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            defs[node.name] = {n.id for n in ast.walk(node) if isinstance(n, ast.Name)}
        elif isinstance(node, ast.Assign):
            used = {n.id for n in ast.walk(node.value) if isinstance(n, ast.Name)}
            for target in node.targets:
                if isinstance(target, ast.Name) and target.id not in PARAMS:
                    defs[target.id] = defs.get(target.id, set()) | used
    changed = True
    while changed:
        changed = False
        for name, used in defs.items():
            if name not in tainted and used & tainted:
                tainted.add(name)
                changed = True
    read = {n for line in region_code for n in _names(line)}
    return next((n for n in sorted(read) if n in tainted and n not in PARAMS and n in defs), None)


def _names(line: str) -> set:
    code = line.split("#")[0]
    return set(re.findall(r"(?<![.\w])[A-Za-z_]\w*", code))
