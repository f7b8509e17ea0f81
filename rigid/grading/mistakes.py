"""Known wrong answers of each TODO, in float64 numpy, to name a submission's mistake.

``MISTAKES[k]`` lists (output, message, predict) where ``predict(d)`` computes
from the inputs ``d`` (name -> (K, ...) arrays, see specs.py) what that output
would be with the mistake. The grader never passes or fails a TODO from this
table: pass/fail comes from the reference units; this table only says *what*
is wrong when an output matches one of these predictions. Right answers that
differ from the reference live in alternatives.py. The exact rotation
exp(½ Δt ω) ⊗ q for TODO 6 is listed here, not accepted: the assignment asks
for the explicit Euler step (accepting it would take a Taichi twin in alternatives.py).
"""
import numpy as np

from ..engine.rotation import quaternion_multiplication_np


def mv(A, v):
    return np.einsum("nij,nj->ni", A, v)


def mm(A, B):
    return np.einsum("nij,njk->nik", A, B)


def tr(A):
    return np.swapaxes(A, 1, 2)


def col(s):
    """(K,) -> (K, 1) for broadcasting against vectors."""
    return np.asarray(s)[:, None]


def qmul(p, q):
    return np.stack([quaternion_multiplication_np(a, b) for a, b in zip(p, q)])


def unit(q):
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def pure(omega, scalar_last=False):
    """[0, ω] as (K, 4) quaternions (or the slip [ω, 0])."""
    zero = np.zeros((len(omega), 1))
    return np.hstack([omega, zero] if scalar_last else [zero, omega])


def inertia_terms(d):
    m, r = d["m"], d["r0"]
    rr = np.einsum("ni,ni->n", r, r)[:, None, None] * np.eye(3)
    outer = np.einsum("ni,nj->nij", r, r)
    return m[:, None, None], rr, outer


def _exact_rotation(d):
    w, dt = d["omega"], d["dt"]
    angle = np.linalg.norm(w, axis=1) * dt
    axis = w / np.linalg.norm(w, axis=1, keepdims=True)
    rot = np.hstack([np.cos(angle / 2)[:, None], np.sin(angle / 2)[:, None] * axis])
    return qmul(rot, d["q"])


def _mistakes():
    m3 = lambda d: inertia_terms(d)  # noqa: E731
    g_fixed = np.array([0.0, -9.8, 0.0])
    r = lambda d: mv(d["R"], d["r0"])  # noqa: E731
    cross = np.cross
    x_step = lambda d, p: d["x"] + col(d["dt"]) * p  # noqa: E731
    v_first = lambda d: d["P"] + col(d["dt"]) * d["F"]  # noqa: E731
    q_step = lambda d, rate, w=None: d["q"] + col(d["dt"]) * rate * qmul(  # noqa: E731
        pure(d["omega"]) if w is None else w, d["q"])
    world_inv = lambda d: mm(mm(d["R"], d["I0_inv"]), tr(d["R"]))  # noqa: E731
    L_new = lambda d: d["L"] + col(d["dt"]) * d["tau"]  # noqa: E731
    return {
        1: [
            ("I", "does not scale with the particle mass: multiply by m",
             lambda d: m3(d)[1] - m3(d)[2]),
            ("I", "has the wrong sign: I0 = Σ m (r0ᵀr0 E − r0 r0ᵀ)",
             lambda d: m3(d)[0] * (m3(d)[2] - m3(d)[1])),
            ("I", "subtracts r0 r0ᵀ from a scalar: r0ᵀr0 must multiply the identity E "
                  "(r0.dot(r0) * ti.Matrix.identity(float, 3))",
             lambda d: m3(d)[0] * (np.trace(m3(d)[1], axis1=1, axis2=2)[:, None, None] / 3 - m3(d)[2])),
            ("I", "lacks the − r0 r0ᵀ term", lambda d: m3(d)[0] * m3(d)[1]),
            ("I", "lacks the r0ᵀr0 E term", lambda d: -m3(d)[0] * m3(d)[2]),
            ("I", "adds r0 r0ᵀ where it should subtract it", lambda d: m3(d)[0] * (m3(d)[1] + m3(d)[2])),
            ("I", "multiplies by the mass twice", lambda d: m3(d)[0] ** 2 * (m3(d)[1] - m3(d)[2])),
            ("I", "divides by the mass instead of multiplying", lambda d: (m3(d)[1] - m3(d)[2]) / m3(d)[0]),
        ],
        2: [
            ("f", "does not scale with the particle mass: f = m g", lambda d: d["g"]),
            ("f", "points against gravity: f = m g, not −m g", lambda d: -col(d["m"]) * d["g"]),
            ("f", "divides by the mass: f = m g", lambda d: d["g"] / col(d["m"])),
            ("f", "ignores the gravity argument (a fixed (0, −9.8, 0)?): use f = m g with the given g",
             lambda d: col(d["m"]) * g_fixed),
            ("f", "ignores the gravity argument and the mass: f = m g with the given m and g",
             lambda d: np.tile(g_fixed, (len(d["m"]), 1))),
        ],
        3: [
            ("F", "has the wrong sign: F = Σ fᵢ, so each particle adds its own fᵢ", lambda d: -d["f"]),
        ],
        4: [
            ("tau", "has the wrong sign: τ = r × f with r = pᵢ − x; check the order of the cross "
                    "product (r × f, not f × r) and the direction of r", lambda d: cross(d["f"], r(d))),
            ("tau", "uses the world position pᵢ as the lever arm; measure it from the centre of mass: "
                    "r = pᵢ − x (= R r0)", lambda d: cross(d["p"], d["f"])),
            ("tau", "uses the body-frame r0 without rotating it: r = R r0 (or pᵢ − x)",
             lambda d: cross(d["r0"], d["f"])),
            ("tau", "rotates r0 with Rᵀ; the world offset is R r0", lambda d: cross(mv(tr(d["R"]), d["r0"]), d["f"])),
            ("tau", "uses the centre of mass x as the lever arm; use r = pᵢ − x", lambda d: cross(d["x"], d["f"])),
            ("tau", "uses the lever arm pᵢ + x; use r = pᵢ − x", lambda d: cross(d["p"] + d["x"], d["f"])),
        ],
        5: [
            ("x_new", "does not depend on Δt: x ← x + Δt P/M", lambda d: d["x"] + d["P"] / col(d["M"])),
            ("x_new", "does not depend on Δt: x ← x + Δt P/M", lambda d: d["x"] + v_first(d) / col(d["M"])),
            ("x_new", "lacks the division by the mass: v = P/M, x ← x + Δt v", lambda d: x_step(d, d["P"])),
            ("x_new", "lacks the division by the mass: v = P/M, x ← x + Δt v", lambda d: x_step(d, v_first(d))),
            ("x_new", "multiplies by the mass: v = P/M", lambda d: x_step(d, d["P"] * col(d["M"]))),
            ("x_new", "moves the wrong way: x ← x + Δt P/M", lambda d: x_step(d, -d["P"] / col(d["M"]))),
            ("x_new", "uses Δt twice: x ← x + Δt P/M", lambda d: x_step(d, col(d["dt"]) * d["P"] / col(d["M"]))),
            ("x_new", "moves with the force instead of the momentum: x ← x + Δt P/M",
             lambda d: x_step(d, d["F"] / col(d["M"]))),
            ("P_new", "does not depend on Δt: P ← P + Δt F", lambda d: d["P"] + d["F"]),
            ("P_new", "divides the force by the mass; P is a momentum: P ← P + Δt F",
             lambda d: d["P"] + col(d["dt"]) * d["F"] / col(d["M"])),
            ("P_new", "multiplies the force by the mass: P ← P + Δt F",
             lambda d: d["P"] + col(d["dt"] * d["M"]) * d["F"]),
            ("P_new", "has the wrong sign of the force term: P ← P + Δt F", lambda d: d["P"] - col(d["dt"]) * d["F"]),
            ("P_new", "lacks the old momentum: P ← P + Δt F", lambda d: col(d["dt"]) * d["F"]),
        ],
        6: [
            ("q_new", "changes at twice the expected rate: dq/dt = ½ [0, ω] ⊗ q (the ½ is missing)",
             lambda d: unit(q_step(d, 1.0))),
            ("q_new", "is not renormalised: divide q by its norm after the step", lambda d: q_step(d, 0.5)),
            ("q_new", "changes at twice the expected rate (the ½ of dq/dt = ½ [0, ω] ⊗ q is missing) "
                      "and is not renormalised", lambda d: q_step(d, 1.0)),
            ("q_new", "multiplies in the wrong order: ω is in the world frame, so dq/dt = ½ [0, ω] ⊗ q, "
                      "not ½ q ⊗ [0, ω]",
             lambda d: unit(d["q"] + col(d["dt"]) * 0.5 * qmul(d["q"], pure(d["omega"])))),
            ("q_new", "does not depend on Δt: q ← q + Δt · ½ [0, ω] ⊗ q",
             lambda d: unit(d["q"] + 0.5 * qmul(pure(d["omega"]), d["q"]))),
            ("q_new", "rotates the wrong way: q ← q + Δt · ½ [0, ω] ⊗ q", lambda d: unit(q_step(d, -0.5))),
            ("q_new", "builds [0, ω] scalar-last; quaternions here are scalar-first: "
                      "ti.Vector([0.0, ω[0], ω[1], ω[2]])",
             lambda d: unit(q_step(d, 0.5, pure(d["omega"], scalar_last=True)))),
            ("q_new", "changes at half the expected rate: dq/dt = ½ [0, ω] ⊗ q (½ applied twice?)",
             lambda d: unit(q_step(d, 0.25))),
            ("q_new", "lacks the old q: q ← q + Δt · ½ [0, ω] ⊗ q", lambda d: unit(q_step(d, 0.5) - d["q"])),
            ("q_new", "applies the exact rotation exp(½ Δt ω) ⊗ q; the assignment asks for the explicit "
                      "Euler step q + Δt · ½ [0, ω] ⊗ q", _exact_rotation),
        ],
        7: [
            ("L_new", "does not depend on Δt: L ← L + Δt τ", lambda d: d["L"] + d["tau"]),
            ("L_new", "has the wrong sign of the torque term: L ← L + Δt τ",
             lambda d: d["L"] - col(d["dt"]) * d["tau"]),
            ("L_new", "lacks the old L: L ← L + Δt τ", lambda d: col(d["dt"]) * d["tau"]),
            ("I_inv", "has the rotations in the wrong order: I⁻¹ = R I0⁻¹ Rᵀ, not Rᵀ I0⁻¹ R",
             lambda d: mm(mm(tr(d["R"]), d["I0_inv"]), d["R"])),
            ("I_inv", "is not rotated into the world frame: I⁻¹ = R I0⁻¹ Rᵀ", lambda d: d["I0_inv"]),
            ("I_inv", "lacks the Rᵀ on the right: I⁻¹ = R I0⁻¹ Rᵀ", lambda d: mm(d["R"], d["I0_inv"])),
            ("I_inv", "lacks the R on the left: I⁻¹ = R I0⁻¹ Rᵀ", lambda d: mm(d["I0_inv"], tr(d["R"]))),
            ("I_inv", "must transpose the right-hand R: I⁻¹ = R I0⁻¹ Rᵀ",
             lambda d: mm(mm(d["R"], d["I0_inv"]), d["R"])),
            ("I_inv", "inverts I0⁻¹ again; the engine already passes the inverse I0⁻¹",
             lambda d: mm(mm(d["R"], np.linalg.inv(d["I0_inv"])), tr(d["R"]))),
            ("omega", "uses the old L; compute ω = I⁻¹ L with the updated L", lambda d: mv(world_inv(d), d["L"])),
            ("omega", "uses the body-frame I0⁻¹; ω = I⁻¹ L with I⁻¹ = R I0⁻¹ Rᵀ", lambda d: mv(d["I0_inv"], L_new(d))),
            ("omega", "has the rotations in the wrong order — check the order R I0⁻¹ Rᵀ",
             lambda d: mv(mm(mm(tr(d["R"]), d["I0_inv"]), d["R"]), L_new(d))),
        ],
    }


MISTAKES = _mistakes()

