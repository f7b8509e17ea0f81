"""A wrong inertia tensor in words: which of its terms differ, instead of a 3×3 dump.

I0 = Σ m (r0ᵀr0 E − r0 r0ᵀ). A student's inertia is fitted, over all the grader's calls at once, as
a·m (r0ᵀr0) E + b·m r0 r0ᵀ + c·W E, where W E is an identity term of the body's mass (``M_body``
in the inputs: the original format's harness, where the rest of the particles sit at the centre
of mass and add m E each when a student adds one per particle) or of the particle's (the project's
unit, one particle a call). When the fit is exact (the mistake is a mix of these terms), the
message names each coefficient that differs from the reference's a = 1, b = −1, c = 0.
"""
import numpy as np

FIT = 1e-6  # relative residual of an exact fit (float32 fields give ~1e-7)


def describe(out: np.ndarray, d: dict) -> str:
    """'' unless ``out`` (K, 3, 3) is exactly a mix of the three terms; then what differs, in words."""
    m, r = np.asarray(d["m"], np.float64), np.asarray(d["r0"], np.float64)
    eye = np.eye(3)
    dot = np.einsum("ni,ni->n", r, r)
    weight, whose = (np.asarray(d["M_body"]), "the body's mass M") if "M_body" in d else (m, "the mass m")
    basis = np.stack([(m * dot)[:, None, None] * eye, m[:, None, None] * np.einsum("ni,nj->nij", r, r),
                      weight[:, None, None] * eye]).reshape(3, -1).T
    coef, *_ = np.linalg.lstsq(basis, out.reshape(-1), rcond=None)
    residual = np.linalg.norm(basis @ coef - out.reshape(-1)) / (np.linalg.norm(out) + 1e-300)
    if residual > FIT:
        return ""
    a, b, c = (float(np.round(v, 4)) for v in coef)
    parts = []
    if b == 1:
        parts.append("adds m r0 r0ᵀ where it must subtract it (the sign of the r0 r0ᵀ term)")
    elif b == 0:
        parts.append("lacks the − m r0 r0ᵀ term")
    elif b != -1:
        parts.append(f"has {_times(-b)} the − m r0 r0ᵀ term")
    if a == 0:
        parts.append("lacks the m (r0ᵀr0) E term (r0.dot(r0) times the identity)")
    elif a != 1:
        parts.append(f"has {_times(a)} the m (r0ᵀr0) E term")
    if c:
        parts.append(f"has an extra identity term ({_times(c)}{whose} times E: an identity added on its own, "
                     f"not multiplied by r0ᵀr0)")
    if not parts:
        return ""
    return "differs from I0 = Σ m (r0ᵀr0 E − r0 r0ᵀ): it " + "; it ".join(parts)


def _times(value: float) -> str:
    if value == 1:
        return ""
    if value == -1:
        return "minus "
    return f"{value:g} times "
