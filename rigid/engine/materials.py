"""Restitution and friction a user sets: from e to each contact's damping, and the pair rules.

The contact is a spring k on the overlap δ and a damper c on the approach speed, never
pulling (contact.py: f_n = max(0, k δ − c v_n)). A coefficient of restitution e is turned
into c per contact, from the damped oscillator of that contact:

1. ζ(e), the damping ratio, by inverting the *clamped* oscillator's restitution. The closed
   form e = exp(−π ζ / √(1 − ζ²)) (ζ = −ln e / √(π² + ln² e)) assumes the damper may pull;
   ours may not, so the contact ends when k δ + c v_n first reaches 0, while the particle is
   still a little inside and still moving out: e is higher (0.45 instead of 0.37 at ζ = 0.3,
   0.135 instead of 0 at ζ = 1) and e < 0.135 needs ζ > 1. ``clamped_restitution`` is that
   oscillator's e(ζ) in closed form (the separation time solves a linear equation in
   tan or exp), ``damping_ratio`` inverts it by bisection on the host.
2. m_eff, the mass the contact moves. A body of mass M resting on n of its particles is n
   springs k and n dampers c in parallel on M, i.e. one spring n k and damper n c, whose
   ratio is n c / (2 √(n k M)) = c / (2 √(k M / n)): each contact must use m_eff = M / n.
   n is counted at run time, per body: its contacts with the static planes, counted before
   the forces of each evaluation, for a plane contact; for a pair of bodies the larger of the
   two bodies' pair-contact counts, as the last pair stage predicted them (the pairs touching
   or closing within a step: a count of those touching would be 0 on a contact's first
   substep and over-damp it, 19 % low at e = 0.1 for a volume ball), with m_eff = M_a M_b / (M_a + M_b) / n (a static body's mass is infinite:
   m_eff = M / n of the moving one). Rotation is ignored (a contact off the line through
   the centre of mass moves less than M); a body touching two things at once counts both
   (its damping per contact is then lower than asked: piles bounce a little more).
   Why counted and not fixed: a sphere lands on one vertex, a volume sphere on a flat layer
   of 4 to 12 particles, a box on a face of many; a fixed m_eff = M would over-damp the
   layer by √n (e 0.5 asked, 0.2 got for n = 9).
3. c = 2 ζ' √(k m_eff), where ζ' corrects for the scheme's own damping per step of
   h = ω Δt (ω = √(k / m_eff)): explicit Euler (the slides) grows an oscillator by
   1 + h² a step (at e = 1 it needs c ≈ k Δt to keep its energy), symplectic Euler damps a
   little, and both end a contact on a step. ζ'(e, h) is tabulated per scheme by running
   the scheme's own clamped oscillator on the host (``damping_table``, in WorldArgs.values from state.MATERIALS),
   read in the kernel by linear interpolation; RK4 takes ζ' = ζ.
4. The step's limit: explicit Euler's damper is stable for Δt < 2 m_eff / c. c is clamped
   to m_eff / Δt (half that, where one step removes the approach speed): an e the step
   cannot take (e = 0 asks for ζ = ∞; e < 0.1 with a large k m_eff) gets the deadest
   contact the step allows, a bounce a little higher than asked; a smaller dt fixes it.

Friction μ: Coulomb with sticking. Against the static planes each contact keeps a
tangential spring (k_t = k, the Cundall-Strack DEM spring) anchored where the particle
touched: it holds a body still on a slope below its friction angle (a viscous law creeps at
≈ g sin θ Δt / 2 at best, 5 mm in 2 s on a 30° ramp at Δt = 1 ms); it slips at μ f_n and
is then re-anchored at |k_t ξ| = μ f_n. Its damper is critical (c_t = 2 √(k m_eff), same
clamp). Between bodies, sticking stays viscous (c_t |v_t| capped at μ f_n): a pair has no
memory of its contacts.

Pair rules (contract: the README states them, as Box2D's b2MixRestitution / b2MixFriction):
e = max(e_a, e_b) (a bouncy ball bounces on any floor; ζ = min(ζ_a, ζ_b), ζ falling with e),
μ = √(μ_a μ_b) (equal values give themselves back; a frictionless side makes the pair so).
A side whose value is unset (no key on it nor at the top level; stored as −1) takes the other
side's: a [[plane]] without friction is as rough as the body on it. Both unset: the
restitution is ``velocity_damping_stiffness`` as c, the friction ``friction_stiffness``, read
at run time as before.
"""

import functools
import math

import numpy as np
import taichi as ti

UNSET = -1.0  # ζ or μ of a body or plane whose key is not set: the world's value at run time
ZETA_DEAD = 1e6  # e = 0: more damping than any step takes, i.e. the step's limit


def clamped_restitution(zeta: float) -> float:
    """e of a contact x'' = −ω² x − 2ζω x' whose force may not pull (ω = 1, entering at speed 1):
    the speed when ω² x + 2 ζ ω x' first reaches 0."""
    if zeta <= 0.0:
        return 1.0
    if zeta < 1.0:
        wd = math.sqrt(1.0 - zeta * zeta)
        # force ∝ e^{−ζt} [(1 − 2ζ²)/ωd sin φ + 2ζ cos φ], φ = ωd t: first zero in (0, π]
        phi = math.pi - math.atan2(2.0 * zeta * wd, 1.0 - 2.0 * zeta * zeta)
        t = phi / wd
        return -math.exp(-zeta * t) * (math.cos(phi) - zeta * math.sin(phi) / wd)
    zeta = max(zeta, 1.0 + 1e-9)
    s = math.sqrt(zeta * zeta - 1.0)
    r1, r2 = -zeta + s, -zeta - s  # x = (e^{r1 t} − e^{r2 t}) / 2s
    a, b = 1.0 + 2.0 * zeta * r1, 1.0 + 2.0 * zeta * r2  # force ∝ a e^{r1 t} − b e^{r2 t}
    t = math.log(b / a) / (r1 - r2)
    return -(r1 * math.exp(r1 * t) - r2 * math.exp(r2 * t)) / (2.0 * s)


def damping_ratio(e: float | None) -> float:
    """ζ whose clamped contact gives restitution e (UNSET for None, ZETA_DEAD for e = 0)."""
    if e is None:
        return UNSET
    e = float(e)
    if e >= 1.0:
        return 0.0
    if e <= 0.0:
        return ZETA_DEAD
    lo, hi = 0.0, 1.0
    while clamped_restitution(hi) > e:  # e(ζ) falls monotonically; e(1) = 0.135, e(5) = 0.009
        hi *= 2.0
        if hi > ZETA_DEAD:
            return ZETA_DEAD
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if clamped_restitution(mid) > e else (lo, mid)
    return 0.5 * (lo + hi)


def friction_value(value: float | None) -> float:
    """A material value for the kernels (μ or e): UNSET (−1) for None."""
    return UNSET if value is None else float(value)


@ti.func
def pair_restitution(e_a, e_b):
    """e = max(e_a, e_b); an unset side (−1) takes the other's (both unset: −1)."""
    return ti.max(e_a, e_b)


@ti.func
def pair_mu(mu_a, mu_b, mu_world):
    """μ = √(μ_a μ_b); an unset side (−1) takes the other's μ, both unset the world's
    friction_stiffness."""
    a, b = mu_a, mu_b
    if a < 0:
        a = b
    if b < 0:
        b = a
    if a < 0:
        a, b = mu_world, mu_world
    return ti.sqrt(a * b)


# The damping table: ζ' (the damper's ratio to ask of the scheme, within its limit 1 / (2h))
# for restitution E_GRID[i] at h = ω Δt = H_GRID[j], found by running the scheme's own clamped
# oscillator (``discrete_restitution``) on the host: explicit and symplectic Euler add or take
# damping of order h, and the contact ends on a step, so the continuous ζ(e) alone is off by
# 20 % (e = 0.1, h = 0.05, Euler). h = 0 is the continuous ζ(e); between nodes, linear.
NUM_E = 41  # e = 0, 0.025, ..., 1
H_GRID = (0.0, 0.005, 0.01, 0.02, 0.03, 0.05, 0.07, 0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 1.0)
NUM_H = len(H_GRID)


def discrete_restitution(zetas: np.ndarray, h: float, scheme: str) -> np.ndarray:
    """e of the clamped oscillator (ω = 1) stepped by ``scheme`` with step h, for each ζ'."""
    x = np.zeros_like(zetas)
    v = -np.ones_like(zetas)
    out = np.zeros_like(zetas)
    live = np.ones(zetas.shape, bool)
    for n in range(int(40.0 / h) + 2):
        inside = x < 0
        f = np.where(inside, np.maximum(-x - 2.0 * zetas * v, 0.0), 0.0)
        if scheme == "euler":
            x, v = x + h * v, v + h * f
        else:
            v = v + h * f
            x = x + h * v
        left = live & (v > 0) & ((x >= 0) | (f == 0))
        out[left] = v[left]
        live &= ~left
        if not live.any():
            break
    return out


@functools.lru_cache(maxsize=4)
def damping_table(scheme: str) -> np.ndarray:
    """(NUM_E, len(H_GRID)) ζ' per (e, h) for ``scheme`` (RK4: the continuous ζ(e) at every h)."""
    es = np.linspace(0.0, 1.0, NUM_E)
    continuous = np.array([min(damping_ratio(e), ZETA_DEAD) for e in es])
    table = np.repeat(continuous[:, None], len(H_GRID), axis=1)
    if scheme == "rk4":
        return np.minimum(table, np.array([1e6] + [0.5 / h for h in H_GRID[1:]]))
    for j, h in enumerate(H_GRID[1:], start=1):
        limit = 0.5 / h  # c <= m_eff / Δt
        zetas = np.concatenate([[0.0], np.geomspace(1e-4, limit, 400)])
        e_of = discrete_restitution(zetas, h, scheme)
        # e falls with ζ' (np.interp wants rising x): the smallest ζ' giving e, the limit if none does
        order = np.argsort(-e_of, kind="stable")
        e_sorted, z_sorted = -e_of[order], zetas[order]
        table[:, j] = np.where(es <= e_of.min(), limit, np.interp(-es, e_sorted, z_sorted))
    return table


@ti.func
def normal_damping(e, k, m_eff, dt, table: ti.template(), at: ti.template(), c_world):
    """The damper c of one contact of restitution e (−1: unset, ``c_world`` =
    velocity_damping_stiffness) moving m_eff: 2 ζ' ω m_eff, ζ' from the table (``table`` from
    index ``at``; steps 1-4)."""
    c = c_world
    if e >= 0 and k > 0:
        w = ti.sqrt(k / m_eff)
        h = w * dt
        u = ti.min(e, 1.0) * (NUM_E - 1)
        i = ti.min(ti.cast(u, ti.i32), NUM_E - 2)
        a = u - i
        j = 0
        for jj in ti.static(range(1, NUM_H - 1)):
            if h >= H_GRID[jj]:
                j = jj
        h0, h1 = 0.0, 0.0
        for jj in ti.static(range(NUM_H - 1)):
            if j == jj:
                h0, h1 = H_GRID[jj], H_GRID[jj + 1]
        b = ti.min((h - h0) / (h1 - h0), 1.0)
        n = NUM_H
        z0 = (1 - a) * table[at + i * n + j] + a * table[at + (i + 1) * n + j]
        z1 = (1 - a) * table[at + i * n + j + 1] + a * table[at + (i + 1) * n + j + 1]
        z = (1 - b) * z0 + b * z1
        c = ti.min(2.0 * z * w * m_eff, m_eff / dt)
    return c


@ti.func
def sticking_damping(k, m_eff, dt):
    """The tangential damper: critical for the contact's mass, within a quarter of the step's
    limit (a corner's tangential mass, with the body's rotation, is well below M / n)."""
    return ti.min(2.0 * ti.sqrt(k * m_eff), 0.25 * m_eff / dt)
