"""The largest stable Δt of a particle's wall contact, per integrator, and which term limits it.

While a particle of mass m is pressed into a wall, its depth obeys the damped spring
m x'' = −k x − c x' (k ``collision_stiffness``, c ``velocity_damping_stiffness``). With
ω² = k/m, γ = c/m and h = Δt, one step maps (x, v) by an amplification matrix A; the step
is stable when A's spectral radius is at most 1. By the Schur–Cohn test (both roots of
λ² − tr λ + det inside the unit circle iff |det| < 1 and |tr| < 1 + det):

- explicit Euler (``euler``, the slides): A = [[1, h], [−hω², 1 − hγ]], det = 1 − hγ + h²ω²,
  tr = 2 − hγ. det < 1 needs h < c/k: an undamped spring (c = 0) gains energy at every Δt.
  |tr| < 1 + det needs h²k − 2hc + 4m > 0, which fails first at h = 4m / (c + √(c² − 4km))
  when c² ≥ 4km (the other condition, det > −1, is then implied). So
  Δt* = c/k if c² < 4km (underdamped: the spring limits, the damper holds it),
  Δt* = 4m / (c + √(c² − 4km)) otherwise (overdamped: the damper limits; 2m/c as k → 0).
  Handout defaults (k 1e4, c 1e3, m 1): Δt* = 2.02 ms, not 2/√(k/m) = 20 ms.
- semi-implicit Euler (``symplectic``, v first): A = [[1 − h²ω², h(1 − hγ)], [−hω², 1 − hγ]],
  det = 1 − hγ, tr = 2 − hγ − h²ω², so Δt* = 4m / (c + √(c² + 4km)), below both 2/ω
  (the spring alone) and 2m/c (the damper alone).
- ``rk4``: A = P(hJ), P(z) = 1 + z + z²/2 + z³/6 + z⁴/24, J = [[0, 1], [−ω², −γ]]; Δt* is
  found numerically: the smallest h where |P(hλ)| > 1 for an eigenvalue λ of J.

These are exact for the linear model (tests/test_messages_stability.py checks them against
the spectral radius of A). They hold for a whole rigid body with any set of particles touching
the walls: its contact modes are the eigenvectors of G = J M⁻¹ Jᵀ (J the contacts' rows of the
particles' velocity Jacobian, M the body's 6×6 mass matrix = m JᵀJ over all particles), whose
eigenvalues are at most 1/m (J (JᵀJ)⁻¹ Jᵀ is a projection), so each mode is a damped spring of
mass 1/g ≥ m, and Δt* grows with the mass. The bound is reached when a contact moves a body
like its own particle (a flat face with every particle touching); a sphere on a vertex takes
far more (its 42 particles survive 3× Δt*). Between two bodies the contact acts on the
relative motion, g ≤ 1/m_a + 1/m_b for one pair: the bound of the reduced mass, m/2 for equal
particles (1.005 ms for explicit Euler at the defaults, 0.995 ms for semi-implicit: at the
default Δt), and less where a particle touches several others at once (n contacts with
similar normals act like n k and n c). Not covered: friction (viscous below 1 cm/s) and the
one-sided clamp f_n ≥ 0.
"""
from __future__ import annotations

import cmath
import math
from dataclasses import dataclass


@dataclass(frozen=True)
class StabilityBound:
    dt: float  # largest stable Δt (s); 0 when no Δt is stable
    term: str  # "damper" or "spring": the term whose change would raise dt the most
    formula: str  # how dt follows from k, c, m, for the message


def stable_dt(k: float, c: float, m: float, integrator: str = "euler") -> StabilityBound:
    """Δt* of m x'' = −k x − c x' under ``integrator`` (see the module docstring)."""
    if k <= 0 and c <= 0:
        return StabilityBound(math.inf, "spring", "no contact forces")
    if integrator == "euler":
        if c * c < 4 * k * m:
            return StabilityBound(c / k, "spring", "c/k (explicit Euler needs damping to hold a spring)")
        return StabilityBound(4 * m / (c + math.sqrt(c * c - 4 * k * m)), "damper",
                              "4m/(c + sqrt(c^2 - 4km)) ≈ 2m/c")
    if integrator == "symplectic":
        dt = 4 * m / (c + math.sqrt(c * c + 4 * k * m))
        if c * c > k * m:  # 2m/c < 2/ω: the damper alone would allow less than the spring alone
            return StabilityBound(dt, "damper", "4m/(c + sqrt(c^2 + 4km)) < 2m/c")
        return StabilityBound(dt, "spring", "4m/(c + sqrt(c^2 + 4km)) < 2/sqrt(k/m)")
    if integrator == "rk4":
        dt = _rk4_dt(k, c, m)
        spring, damper = _rk4_dt(k, 0.0, m), _rk4_dt(0.0, c, m)
        term = "damper" if damper < spring else "spring"
        return StabilityBound(dt, term, f"RK4's bound for the damped spring (the {term} alone: {min(spring, damper):.3g} s)")
    raise ValueError(f"unknown integrator {integrator!r}")


def _rk4_dt(k: float, c: float, m: float) -> float:
    """Smallest h with |P(hλ)| > 1 for an eigenvalue λ of [[0, 1], [−k/m, −c/m]] (inf if none)."""
    gamma, omega2 = c / m, k / m
    root = cmath.sqrt(gamma * gamma - 4 * omega2)
    eigen = [(-gamma + root) / 2, (-gamma - root) / 2]
    scale = max(abs(z) for z in eigen)
    if scale == 0:
        return math.inf

    def stable(h):
        return all(abs(1 + z + z * z / 2 + z ** 3 / 6 + z ** 4 / 24) <= 1 + 1e-12
                   for z in (h * lam for lam in eigen))

    # RK4's region reaches |z| <= 2.83 along every left-half-plane ray: scan, then bisect.
    step = 0.01 / scale
    h = step
    while stable(h) and h < 3.0 / scale:
        h += step
    lo, hi = h - step, h
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return lo


SCHEMES = {"euler": "explicit Euler", "symplectic": "semi-implicit Euler", "rk4": "RK4"}


def stability_message(dt: float, k: float, c: float, m: float, integrator: str, pairs: bool = False) -> str:
    """The fix for a blow-up at step ``dt``, naming the bound and the term that limits it. ``pairs``:
    the scene has contacts between bodies, whose two particles (mass m each) move against each
    other with the reduced mass m/2, so the bound is that of m/2."""
    bound = stable_dt(k, c, m / 2 if pairs else m, integrator)
    mass = f"m = particle_mass/2 = {m / 2:g} (two particles in contact)" if pairs else f"m = particle_mass = {m:g}"
    values = f"k = collision_stiffness = {k:g}, c = velocity_damping_stiffness = {c:g}, {mass}"
    contacts = ("a contact between two bodies' particles stable (less where a particle touches several)"
                if pairs else "the wall contacts stable, however many particles touch,")
    scheme = SCHEMES.get(integrator, integrator)
    if math.isinf(bound.dt):
        return f"try a smaller --dt (now {dt:g})"
    if bound.dt == 0:
        return (f"{scheme} gains energy on an undamped contact spring at every dt ({values}): "
                f"use a positive velocity_damping_stiffness (stable for dt < c/k) or --integrator symplectic")
    if bound.term == "damper":
        limit, also = "the normal damping limits it", "a lower velocity_damping_stiffness also helps"
    else:
        limit = "the contact spring limits it"
        also = "a lower collision_stiffness also helps" + (
            ", or a higher velocity_damping_stiffness, or --integrator symplectic" if integrator == "euler" else "")
    bound_text = f"dt < {bound.formula} with {values}"
    if dt < bound.dt:
        return (f"try a smaller --dt (now {dt:g}): it is within the {bound.dt:.3g} s that keeps {scheme}'s "
                f"contacts stable ({bound_text}), so the cause is elsewhere (friction, a fast spin)")
    return (f"try --dt {suggest_dt(bound.dt):g} (now {dt:g}): {scheme} keeps {contacts} for "
            f"dt < {bound.dt:.3g} s, and {limit}: {bound_text} ({also})")


def suggest_dt(bound: float) -> float:
    """A round step safely below ``bound``: the largest 1, 2 or 5 × 10^n at most 0.8 × bound."""
    target = 0.8 * bound
    exponent = math.floor(math.log10(target))
    return max(d * 10.0 ** exponent for d in (1, 2, 5) if d * 10.0 ** exponent <= target * (1 + 1e-12))
