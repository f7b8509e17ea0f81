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
   tan or exp), ``damping_ratio`` inverts it by bisection on the host (damping_table.py).
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
3. c = 2 ζ' √(k m_eff), ζ' from the table ζ'(e, h, β) (damping_table.py, in WorldArgs.values
   from state.MATERIALS + MATERIAL_TABLE; read by trilinear interpolation, linear in √β):
   - h = ω Δt, ω = √(k / m_eff): explicit Euler (the slides) grows an oscillator by 1 + h² a
     step (at e = 1 it needs c ≈ k Δt to keep its energy), symplectic Euler damps a little, and
     both end a contact on a step; RK4 takes the continuous ζ.
   - β = γ / e, γ = g_n / (ω v0): the load. Gravity keeps pressing a body on a floor during
     the contact, so with ζ(e) alone a dropped ball leaves slower than e v0 (rise / drop 0.0076
     instead of 0.01 at e = 0.1, γ = 0.01). g_n is gravity's part into the plane (−g·n; a
     ceiling's is taken as 0: a ball thrown up at it leaves a little faster than e v0), v0 the
     approach speed at the contact's first touch, which each (particle, plane) contact keeps
     in the normal part of its sticking spring (``impact_memory``): +v0 going in, −v0 going
     out, and once it goes back in without having left it rests and is damped without load.
     β beyond BETA_MAX (1: a bounce rising less than half the static sag g / ω²) is damped
     without load too, so resting contacts (v0 → 0) are damped exactly as before.
   - With the Euler schemes, on a plane contact's first evaluation the damper acts for the part
     of the step since the touch only (``plane_damping``), as the table's oscillator touches a
     step before; RK4, whose table is the continuous oscillator, damps its stages in full.
   Between two free bodies uniform gravity does not change their relative motion: pairs use
   β = 0. A static mesh (a body of infinite mass) is met through the pair contacts, which keep
   no memory: its contacts use β = 0 too, so a ball dropped into a bowl rises a little less
   than e² of its drop (as planes did before).
4. The step's limit: explicit Euler's damper is stable for Δt < 2 m_eff / c. c is clamped
   to m_eff / Δt (half that, where one step removes the approach speed): an e the step
   cannot take (e = 0 asks for ζ = ∞; e < 0.1 with a large k m_eff) gets the deadest
   contact the step allows, a bounce a little higher than asked; a smaller dt fixes it.

Friction μ: Coulomb with sticking. Against the static planes each contact keeps a
tangential spring (k_t = k, the Cundall-Strack DEM spring) anchored where the particle
touched: it holds a body still on a slope below its friction angle (a viscous law creeps at
≈ g sin θ Δt / 2 at best, 5 mm in 2 s on a 30° ramp at Δt = 1 ms); it slips at μ f_n and
is then re-anchored at |k_t ξ| = μ f_n. Its damper is critical (c_t = 2 √(k m_eff), same
clamp). Between bodies the same spring acts on each touching pair of particles, kept with the
pair in the neighbour lists (pair_slip.py); where a list overflowed it is viscous (c_t |v_t|
capped at μ f_n).

Pair rules (contract: the README states them, as Box2D's b2MixRestitution / b2MixFriction):
e = max(e_a, e_b) (a bouncy ball bounces on any floor; ζ = min(ζ_a, ζ_b), ζ falling with e),
μ = √(μ_a μ_b) (equal values give themselves back; a frictionless side makes the pair so).
A side whose value is unset (no key on it nor at the top level; stored as −1) takes the other
side's: a [[plane]] without friction is as rough as the body on it. Both unset: the
restitution is ``velocity_damping_stiffness`` as c, the friction ``friction_stiffness``, read
at run time as before.
"""

import taichi as ti

from .damping_table import BETA_MAX, NUM_B, NUM_E, NUM_H, H_GRID, ROOT_BETA, clamped_restitution, damping_ratio  # noqa: F401
from .damping_table import damping_table  # noqa: F401  (state.py's import)

UNSET = -1.0  # ζ or μ of a body or plane whose key is not set: the world's value at run time
REST = 1e-30  # m/s: a contact's approach speed once it rests (β beyond BETA_MAX: no load)


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


@ti.func
def _interval(grid: ti.template(), x):
    """(index j of the grid's interval holding x, the fraction of the way along it, in [0, 1])."""
    j = 0
    for jj in ti.static(range(1, len(grid) - 1)):
        if x >= grid[jj]:
            j = jj
    lo, hi = 0.0, 1.0
    for jj in ti.static(range(len(grid) - 1)):
        if j == jj:
            lo, hi = grid[jj], grid[jj + 1]
    return j, ti.min(ti.max((x - lo) / (hi - lo), 0.0), 1.0)


@ti.func
def normal_damping(e, k, m_eff, dt, load, v0, table: ti.template(), at: ti.template(), c_world):
    """The damper c of one contact of restitution e (−1: unset, ``c_world`` =
    velocity_damping_stiffness) moving m_eff, under a constant ``load`` (acceleration into the
    contact; 0 between free bodies) having come in at ``v0``: 2 ζ' ω m_eff, ζ' from the table
    (``table`` from index ``at``) at (e, h = ω Δt, β = load / (ω e v0)); steps 1-4."""
    c = c_world
    if e >= 0 and k > 0:
        w = ti.sqrt(k / m_eff)
        root_beta = 0.0  # β beyond BETA_MAX (a resting contact, v0 → 0): damped as without load
        if load > 0 and load < BETA_MAX * w * e * v0:
            root_beta = ti.sqrt(load / (w * e * v0))
        u = ti.min(e, 1.0) * (NUM_E - 1)  # e's nodes are evenly spaced
        i = ti.min(ti.cast(u, ti.i32), NUM_E - 2)
        a = u - i
        j, b = _interval(H_GRID, w * dt)
        l, g = _interval(ROOT_BETA, root_beta)
        zl = ti.Vector([0.0, 0.0])
        for dl in ti.static(range(2)):  # bilinear in (e, h) on two β layers (β = 0: as before the load, bit for bit)
            z0 = (1 - a) * table[at + (i * NUM_H + j) * NUM_B + l + dl] + a * table[at + ((i + 1) * NUM_H + j) * NUM_B + l + dl]
            z1 = (1 - a) * table[at + (i * NUM_H + j + 1) * NUM_B + l + dl] + a * table[at + ((i + 1) * NUM_H + j + 1) * NUM_B + l + dl]
            zl[dl] = (1 - b) * z0 + b * z1
        z = zl[0]
        if g > 0:
            z = (1 - g) * zl[0] + g * zl[1]
        c = ti.min(2.0 * z * w * m_eff, m_eff / dt)
    return c


@ti.func
def impact_memory(memory, vn):
    """A plane contact's memory of its impact after this evaluation (kept in the normal part of
    its sticking spring, which the tangential law never reads): 0 before its first touch, then
    +v0 (the approach speed then) while it goes in, −v0 once it moves out (vn > 0), and REST once
    it moves in again before leaving: it did not bounce, it rests, and is damped without load."""
    new = memory
    if memory == 0:
        new = ti.max(-vn, REST)
    elif memory > 0 and vn > 0:
        new = -memory
    elif memory < 0 and vn < 0:
        new = REST
    return new


@ti.func
def plane_damping(e, k, m_eff, dt, load, memory, vn, depth, table: ti.template(), at: ti.template(), c_world,
                  touch_part: ti.template()):
    """A plane contact's damper (``normal_damping`` with the load and its remembered v0) and its
    memory after this evaluation (``impact_memory``; ``memory`` the one before, ``vn`` the normal
    speed, ``depth`` the overlap). With ``touch_part`` (the Euler schemes), on the contact's first
    evaluation the damper acts only for the part of the last step since the touch (depth / (v0 Δt)
    of it): a full step's damping impulse there would make e depend on where in a step the ball
    touched (±6 % of e at e = 0.1, γ = 0.05, ω Δt = 0.03), as the table's oscillator touches
    exactly a step before. RK4 goes without: its table is the continuous oscillator, and its first
    evaluation inside is one of a step's four stages, so the rule would damp a quarter of a step
    (exit 0.1032 of the approach at e = 0.1, thrown, volume balls; 0.1011 without)."""
    new = impact_memory(memory, vn)
    v0 = ti.abs(new)
    c = normal_damping(e, k, m_eff, dt, load, v0, table, at, c_world)
    if ti.static(touch_part) and memory == 0 and e >= 0:
        c *= ti.min(ti.max(depth / (v0 * dt), 0.0), 1.0)
    return c, new


@ti.func
def sticking_damping(k, m_eff, dt):
    """The tangential damper: critical for the contact's mass, within a quarter of the step's
    limit (a corner's tangential mass, with the body's rotation, is well below M / n)."""
    return ti.min(2.0 * ti.sqrt(k * m_eff), 0.25 * m_eff / dt)
