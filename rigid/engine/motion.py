"""When the neighbour lists (neighbours.py) must be rebuilt: each body's motion since the last
build, bounded per body, and the pairs of bodies near enough to touch (stage 1a of a substep).

The lists hold every pair of other bodies' particles within reach + skin at the build, so
they stay exact while no pair of particles that may touch now has closed by more than the
skin. A particle of body b moved by Δx_b + ΔR_b r0; note_motion bounds that per body (e_b,
relative to a common shift) and, when the two largest bounds sum past the skin,
close_pairs_moved asks only the pairs of bodies whose bounding spheres overlap. The flag it
raises is broadphase.REBUILD (1 = rebuild at this placement; MAYBE while undecided; VIOLATED
when a pair moved too far, which refresh.settle turns into a partial or a full build); each
body's e_b and reach ρ'_b are its broadphase.MOTION and REACH (broadphase.py).
"""
import taichi as ti

from . import broadphase as bp
from .matvec import dot, norm

ROTATION_DEFECT = 1e-3  # _turn_norm: the orthogonality defect up to which R is taken for a rotation
MAYBE = 2  # broadphase.REBUILD while note_motion's rebuild is undecided (close_pairs_moved decides)
VIOLATED = 3  # close_pairs_moved found a pair that moved too far (refresh.settle: a refresh or a full build)


@ti.func
def _defect(M):
    """‖MᵀM − I‖_F: bounds the distance of M from the nearest orthogonal matrix (for singular
    values σ, √Σ(σ − 1)² <= √Σ(σ² − 1)²)."""
    total = 0.0
    for r, c in ti.static(ti.ndrange(3, 3)):
        dot = M[0, r] * M[0, c] + M[1, r] * M[1, c] + M[2, r] * M[2, c]
        total += (dot - (1.0 if ti.static(r == c) else 0.0)) ** 2
    return ti.sqrt(total)


@ti.func
def _turn_norm(R, R0):
    """A bound on ‖R − R0‖₂, the most a unit offset moved by the change of orientation.
    ‖R − R0‖_F holds for any matrices. For two rotations it is √2 times too large (R R0ᵀ − I
    has singular values 2 sin(θ/2) twice and 0), so where R and R0 are rotations up to δ, δ₀
    (_defect, and det > 0: the nearest orthogonal matrices are proper) the bound is
    (‖R − R0‖_F + δ + δ₀)/√2 + δ + δ₀ (each off its rotation by at most its δ in Frobenius)."""
    frob2 = 0.0
    for r, c in ti.static(ti.ndrange(3, 3)):
        frob2 += (R[r, c] - R0[r, c]) ** 2
    frob = ti.sqrt(frob2)
    off = _defect(R) + _defect(R0)
    bound = frob
    if off < ROTATION_DEFECT and R.determinant() > 0 and R0.determinant() > 0:
        bound = ti.min(frob, (frob + off) * (0.5 ** 0.5) + off)
    return bound


@ti.func
def body_dx(scratch: ti.template(), state: ti.template(), b):
    """Δx of body b since the last build (alone: the rotation's bound is not compiled in)."""
    return state.x[b] - bp.reference_x(scratch, b)


@ti.func
def body_shift(scratch: ti.template(), state: ti.template(), b):
    """(Δx of body b since the last build, the bound _turn_norm(R, R_build) ρ_b)."""
    return body_dx(scratch, state, b), _turn_norm(state.R[b], bp.reference_R(scratch, b)) * bp.body_radius(scratch, b)


@ti.func
def _bound(scratch: ti.template(), state: ti.template(), b, c):
    """e_b = |Δx_b − c| + ‖ΔR_b‖₂ ρ_b (note_motion), a NaN as 1e30 (moved: a rebuild at once)."""
    dx, turn = body_shift(scratch, state, b)
    e = norm(dx - c) + turn
    if not (e <= 1e30):
        e = 1e30
    return e


@ti.func
def note_motion(scratch: ti.template(), state: ti.template()):
    """Measure each body's motion since the last build and ask for a rebuild if two particles may
    have closed by more than the skin in total (run on one thread: a fixed-order sum). A
    particle of body b moved by Δx_b + ΔR_b r0, so for any common vector c,
    |Δpᵢ − Δpⱼ| <= e_a + e_b with e_b = |Δx_b − c| + ‖ΔR_b‖₂ ρ_b (ρ_b the body's largest
    |r0|; ‖ΔR_b‖₂ bounded by _turn_norm, for any matrix R, √2 tighter for rotations). Distances
    do not change when every body moves alike, so c is the middle of the bodies' Δx (per axis,
    halfway between the least and the largest): a pile falling as one rebuilds nothing, and
    while some bodies rest and others fall, each e is about half their relative motion (the mean
    Δx, used before, left nearly all of it to the fallers: 6-14 % more rebuilds in the benchmark
    piles). While the two largest e sum to at most the skin, no pair can have closed by more;
    else ``close_pairs_moved`` looks at the pairs of bodies near enough to touch. Each body's
    e is kept (broadphase.MOTION) for that test, and then only a bound on its particles'
    distance from its centre (REACH). A NaN counts as moved (a rebuild at once)."""
    B = state.x.shape[0]
    lo = ti.Vector([1e30, 1e30, 1e30], float)
    hi = -lo
    for b in range(B):
        dx = body_dx(scratch, state, b)
        lo = ti.min(lo, dx)
        hi = ti.max(hi, dx)
    c = 0.5 * (lo + hi)
    first, second = 0.0, 0.0
    for b in range(B):
        e = _bound(scratch, state, b, c)
        bp.set_body_float(scratch, b, bp.MOTION, e)
        if e > first:
            second = first
            first = e
        elif e > second:
            second = e
    if first >= 1e30:
        bp.put(scratch, bp.REBUILD, 1)
    elif first + second > bp.value(scratch, bp.ALLOWED) and bp.get(scratch, bp.REBUILD) == 0:
        bp.put(scratch, bp.REBUILD, MAYBE)  # close_pairs_moved decides, with each body's reach:
        for b in range(B):  # ‖R‖₂ <= 1 + ‖RᵀR − I‖_F (only then: most substeps end above)
            bp.set_body_float(scratch, b, bp.REACH, reach_now(scratch, state, b))


@ti.func
def note_motion_spread(scratch: ti.template(), state: ti.template()):
    """note_motion as top-level loops of a parallel kernel, for a GPU: there one thread's two
    passes over 10,000 bodies would wait on every load (milliseconds a substep by estimate; no
    GPU has measured it). The same decisions and e_b to round-off: the least and largest Δx,
    the largest e and the count of its ties are exact whatever the order (atomic min, max and
    add in broadphase.SHIFT_LO ... E_TIES), and the second largest is the largest below the first, or the
    first itself if it is tied (tests/test_gpu_pipeline.py)."""
    ti.loop_config(serialize=True)
    for _ in range(1):
        for k in ti.static(range(3)):
            bp.set_value(scratch, bp.SHIFT_LO[k], 1e30)
            bp.set_value(scratch, bp.SHIFT_HI[k], -1e30)
        for what in ti.static((bp.E_FIRST, bp.E_SECOND, bp.E_TIES)):
            bp.set_value(scratch, what, 0.0)
    for b in range(state.x.shape[0]):
        dx = body_dx(scratch, state, b)
        for k in ti.static(range(3)):
            bp.lower_value(scratch, bp.SHIFT_LO[k], dx[k])
            bp.raise_value(scratch, bp.SHIFT_HI[k], dx[k])
    for b in range(state.x.shape[0]):
        c = ti.Vector([0.5 * (bp.value(scratch, bp.SHIFT_LO[k]) + bp.value(scratch, bp.SHIFT_HI[k]))
                       for k in ti.static(range(3))])
        e = _bound(scratch, state, b, c)
        bp.set_body_float(scratch, b, bp.MOTION, e)
        bp.raise_value(scratch, bp.E_FIRST, e)
    for b in range(state.x.shape[0]):
        e = bp.body_float(scratch, b, bp.MOTION)
        if e == bp.value(scratch, bp.E_FIRST):
            bp.add_value(scratch, bp.E_TIES, 1.0)
        else:
            bp.raise_value(scratch, bp.E_SECOND, e)
    ti.loop_config(serialize=True)
    for _ in range(1):
        first, second = bp.value(scratch, bp.E_FIRST), bp.value(scratch, bp.E_SECOND)
        if bp.value(scratch, bp.E_TIES) >= 2.0:
            second = first
        if first >= 1e30:
            bp.put(scratch, bp.REBUILD, 1)
        elif first + second > bp.value(scratch, bp.ALLOWED) and bp.get(scratch, bp.REBUILD) == 0:
            bp.put(scratch, bp.REBUILD, MAYBE)
    for b in range(state.x.shape[0] * motion_undecided(scratch)):
        bp.set_body_float(scratch, b, bp.REACH, reach_now(scratch, state, b))


@ti.func
def reach_now(scratch: ti.template(), state: ti.template(), b):
    """ρ'_b >= the distance of body b's particles from its centre now: ρ_b (broadphase.RHO)
    stretched by R's orthogonality defect (‖R‖₂ <= 1 + ‖RᵀR − I‖_F) and a margin for round-off."""
    return bp.body_radius(scratch, b) * (1.0 + _defect(state.R[b])) * (1.0 + 1e-5)


@ti.func
def motion_undecided(scratch: ti.template()):
    """1 when note_motion left the rebuild to close_pairs_moved, else 0."""
    return ti.cast(bp.get(scratch, bp.REBUILD) == MAYBE, ti.i32)


@ti.func
def close_pairs_moved(model: ti.template(), state: ti.template(), scratch: ti.template(), a):
    """After note_motion: ask for a rebuild if body a and another body b that may now touch it
    have moved by more than the skin in total (e_a + e_b, note_motion). Only such a pair can
    hold two particles now within reach that were not within reach + skin at the build (so
    not in the lists); two bodies touch only if their centres are within
    ρ'_a + ρ'_b + r_a + r_b (ρ' a bound on |R r0|, note_motion). Each pair is tested from
    the side with the larger e (ties: the lower index), whose e then exceeds half the skin: so
    a body that moves alone, far from the others, rebuilds nothing, and a substep with no fast
    body costs one comparison a body. Any order (threads may run it): it only raises the flag."""
    allowed = bp.value(scratch, bp.ALLOWED)
    e_a = bp.body_float(scratch, a, bp.MOTION)
    if e_a > 0.5 * allowed and bp.get(scratch, bp.REBUILD) == MAYBE:  # (once raised, the others need not look)
        x_a, reach_a = state.x[a], bp.body_float(scratch, a, bp.REACH) + model.particle_radius[a]
        world = model.body_world[a]
        for b in range(world[2], world[2] + world[3]):  # a's world's bodies
            e_b = bp.body_float(scratch, b, bp.MOTION)
            if b != a and e_a + e_b > allowed and (e_b < e_a or (e_b == e_a and b > a)):
                d = state.x[b] - x_a
                reach = (reach_a + bp.body_float(scratch, b, bp.REACH) + model.particle_radius[b]) * (1.0 + 1e-5)
                if dot(d, d) < reach * reach:
                    bp.put(scratch, bp.REBUILD, VIOLATED)
