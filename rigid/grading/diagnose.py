"""Compare a unit's outputs with the reference and say in words what is wrong.

All arrays are float64 with a first axis of K calls (see specs.py). An output
is right when it is within ``RTOL`` of the reference, relative to the size of
the reference output over all calls (round-off, float32 literals and any
equivalent algebra pass; every mistake we know differs by 1e-3 or more with
the grader's masses and Δt). A wrong output is named by the first of: it
follows from the submission's own other (wrong) outputs; a known mistake
(mistakes.py); an inertia as a mix of its terms (inertia_words.py); generic tests
(zero, unchanged, a constant, mass or Δt factor, right magnitude but wrong
direction, wrong components).
"""
import numpy as np

from .inertia_words import describe as describe_inertia
from .mistakes import MISTAKES, col, mm, mv, tr, unit

RTOL = 1e-5
COMPONENTS = {3: "xyz", 4: ("s", "x", "y", "z")}
HINTS = {  # appended to "right magnitude, wrong direction"
    "tau": " — check the lever arm r = R r0 and the order r × f",
    "omega": " — check the order R I0⁻¹ Rᵀ",
    "f": " — f = m g points along the given g",
}


def scale_of(ref: np.ndarray) -> float:
    """Typical size of one output: the RMS over calls of its norm."""
    flat = ref.reshape(len(ref), -1)
    return float(np.sqrt(np.mean(np.sum(flat ** 2, axis=1)))) + 1e-300


def error(out: np.ndarray, ref: np.ndarray) -> float:
    """Largest difference over calls, relative to the output's typical size (inf if not finite)."""
    if not np.all(np.isfinite(out)):
        return float("inf")
    return float(np.max(np.abs(out - ref))) / scale_of(ref)


ROUND_OFF = 1e-12  # float64 errors below this are round-off, whose last bits vary between machines


def agreement(worst: float) -> str:
    """How closely outputs agree, for a message: the error, or "round-off (< 1e-12)" below
    ROUND_OFF (its digits depend on the CPU that made the answers: vector width, FMA)."""
    return f"{worst:.0e}" if worst >= ROUND_OFF else f"round-off (< {ROUND_OFF:.0e})"


def close(out, ref) -> bool:
    return error(out, ref) <= RTOL


def diagnose_output(spec, name: str, out: np.ndarray, ref: np.ndarray, inputs: dict, sub: dict) -> str:
    """One phrase (no TODO prefix) saying what is wrong with output ``name``."""
    label = next(lbl for n, _s, lbl in spec.outputs if n == name)
    if not np.all(np.isfinite(out)):
        return f"{label} is NaN or infinite"
    derived = _follows_from_other_outputs(spec.number, name, out, inputs, sub)
    if derived:
        return f"{label} {derived}"
    for output, message, predict in MISTAKES[spec.number]:
        if output == name and close(out, predict(inputs)):
            return f"{label} {message}"
    if spec.number == 6:
        norm = np.linalg.norm(out, axis=1)
        if not np.allclose(norm, 1.0, atol=1e-6) and np.all(norm > 0):
            inner = diagnose_output(spec, name, unit(out), ref, inputs, sub)
            if close(unit(out), ref):
                return f"{label} is not renormalised: divide q by its norm after the step"
            return f"{inner}; it is also not renormalised (|q| ≠ 1)"
    if spec.number == 1:
        words = describe_inertia(out, inputs)
        if words:
            return f"{label} {words}"
    old = dict((o, i) for o, i in spec.updates).get(name)
    return f"{label} {_generic(name, out, ref, inputs, inputs[old] if old else None)}"


def _follows_from_other_outputs(todo, name, out, d, sub) -> str:
    """A wrong output that is right given the submission's own wrong inputs to it."""
    if todo == 7 and name == "omega":
        if "I_inv" in sub and close(out, mv(sub["I_inv"], sub["L_new"])):
            return "= I⁻¹ L is right for your I⁻¹ and L; fix those"
        if "I_inv" in sub and close(out, mv(sub["I_inv"], d["L"])):
            return "uses the old L; compute ω = I⁻¹ L with the updated L"
        if "I_inv" not in sub and close(out, mv(mm(mm(d["R"], d["I0_inv"]), tr(d["R"])), sub["L_new"])):
            return "= I⁻¹ L is right for your new L; fix L"
    if todo == 5 and name == "x_new":
        if close(out, d["x"] + col(d["dt"]) * sub["P_new"] / col(d["M"])):
            return "is right for your new P (velocity-first order); fix P"
    return ""


def _generic(name, out, ref, d, old) -> str:
    update = old is not None
    if np.max(np.abs(out)) <= RTOL * scale_of(ref):
        return "is zero — is this still the handout's placeholder?"
    if update and close(out, old):
        return "does not change — is this still the handout's placeholder?"
    s, r = (out - old, ref - old) if update else (out, ref)
    factor = _factor(s, r, d, update)
    if factor:
        return factor
    if out.ndim == 2 and out.shape[1] in (3, 4):
        n_out, n_ref = np.linalg.norm(out, axis=1), np.linalg.norm(ref, axis=1)
        if np.allclose(n_out, n_ref, rtol=RTOL, atol=RTOL * scale_of(ref)):
            return "has the right magnitude but the wrong direction" + HINTS.get(name, "")
    wrong = np.max(np.abs(out - ref), axis=0) > RTOL * scale_of(ref)
    if not wrong.all():
        return f"is wrong in {_which(wrong)} (the rest is right)"
    return (f"differs from the expected value in every component (largest relative difference "
            f"{error(out, ref):.2g}; first call: {_show(out[0])} where {_show(ref[0])} is expected)")


def _show(value) -> str:
    """A vector or matrix of one call, to 3 significant digits."""
    value = np.asarray(value)
    if value.ndim == 0:
        return f"{float(value):.3g}"
    if value.ndim == 1:
        return "(" + ", ".join(f"{v:.3g}" for v in value) + ")"
    return "[" + "; ".join(" ".join(f"{v:.3g}" for v in row) for row in value) + "]"


def _factor(s, r, d, update: bool) -> str:
    """The change (or value) s = c r with c constant, or c ∝ Δt or the mass: say which."""
    flat_s, flat_r = s.reshape(len(s), -1), r.reshape(len(r), -1)
    rr = np.sum(flat_r ** 2, axis=1)
    if np.any(rr == 0):
        return ""
    c = np.sum(flat_s * flat_r, axis=1) / rr
    residual = np.linalg.norm(flat_s - c[:, None] * flat_r, axis=1) / np.sqrt(rr)
    if np.max(residual) > 1e-4:
        return ""
    if np.ptp(c) <= 1e-4 * np.max(np.abs(c)):
        c0 = float(np.mean(c))
        phrases = (("changes in the wrong direction (a sign)", "changes at twice the expected rate",
                    "changes at half the expected rate") if update else
                   ("has the wrong sign", "is twice as large as expected", "is half as large as expected"))
        for value, phrase in zip((-1, 2, 0.5), phrases):
            if abs(c0 - value) < 1e-4:
                return phrase
        return f"{'changes' if update else 'is'} off by a constant factor {c0:.4g}"
    for key, who in (("dt", "Δt"), ("m", "of the mass"), ("M", "of the mass")):
        if key not in d:
            continue
        for power, words in ((-1, f"lacks a factor {who}"), (1, f"has an extra factor {who}"),
                             (2, f"has an extra factor {who}²"), (-2, f"lacks a factor {who}²")):
            k = c * d[key] ** (-power)
            if np.ptp(k) <= 1e-4 * np.max(np.abs(k)):
                return words
    return ""


def _which(wrong: np.ndarray) -> str:
    if wrong.ndim == 1:
        names = COMPONENTS.get(len(wrong), range(len(wrong)))
        parts = [f"{names[i]}" for i in np.flatnonzero(wrong)]
        return ("its " + ", ".join(parts) + " component" + ("s" if len(parts) > 1 else ""))
    entries = [f"({i},{j})" for i, j in zip(*np.nonzero(wrong))]
    return "entr" + ("ies " if len(entries) > 1 else "y ") + ", ".join(entries)
