"""Verlet neighbour lists: the pair candidates of every particle, reused across substeps.

Rebuilding the grid and walking 27 cells every substep cost most of a many-body substep (the
125-sphere pile: 14 candidates a particle, 74 % of them its own body's, 1.5 % in contact). So
each particle keeps a list of the other bodies' particles within r_a + r_b + skin of it, made
from the grid (grid.py, cells of the largest diameter + the skin) and reused until two
particles may have closed by more than the skin since the build: until then no pair can have
come from beyond reach + skin to within reach, so every pair in contact is in the
list (Verlet 1967; the classic rebuild test, here on relative motion bounded per body: note_motion). Own-body
candidates never enter the list. Only the particles with a candidate (the active list) are
placed and visited by the pair stage between builds; the others' pair force stays zero.

The list of particle i is nbr_list[i·K .. i·K + nbr_count[i]) (K = its length / N), sorted by
slot, so each sum over it has a fixed order whatever the threads did, and runs are
bit-reproducible; it is symmetric (each pair is tested once, from one side, and entered in
both lists). A particle with more than K candidates keeps only its count, and its sum walks
the build's grid again around the cell of its build position, testing the candidates' current
positions (a superset of its list: exact, in the walk's fixed order): no contact is dropped.

Scratch arrays (ScratchArgs): ``nbr_count`` [N] i32, ``nbr_list`` [N·K] i32 (particle slots),
``build_x`` [N] vec3 (world positions at the last build), ``active`` [N] i32 (the slots with a
candidate, first nbr_flags[2] of them), ``nbr_flags`` [4 + 2B] i32 (1: rebuild at the next
placement; builds so far; active particles; then per body b, [3 + b] = 1 when b sleeps and a
body that does not rest has it in its lists, and [3 + B + b] .. [3 + B + b + 1] its run of the
active list, on one thread: pair_once.py; one array, as the x64 backend takes at most 64
argument elements), ``grid_params`` [1], [2] = the skin, the relative motion allowed before a
rebuild (the skin less 2 % for round-off); per body [B]: ``build_pose`` = its x (3) and R
(9, row by row) at the last build and ρ_b, its largest |r0| (13 floats).
"""
import taichi as ti

from . import grid

NEIGHBOURS_PER_PARTICLE = 16  # list slots per particle; beyond, the particle walks the grid (exact)
SKIN_FRACTION = 0.5  # skin = this × the largest particle diameter
ROTATION_DEFECT = 1e-3  # _turn_norm: the orthogonality defect up to which R is taken for a rotation
ALLOWED_MOTION = 0.98  # × the skin: two particles' relative motion before a rebuild (less 2 % for round-off)


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
def _body_shift(scratch: ti.template(), state: ti.template(), b):
    """(Δx of body b since the last build, the bound _turn_norm(R, R_build) ρ_b)."""
    pose = scratch.build_pose[b]
    x, R = state.x[b], state.R[b]
    dx = ti.Vector([x[0] - pose[0], x[1] - pose[1], x[2] - pose[2]])
    R0 = ti.Matrix([[pose[3], pose[4], pose[5]], [pose[6], pose[7], pose[8]], [pose[9], pose[10], pose[11]]])
    return dx, _turn_norm(R, R0) * pose[12]


@ti.func
def note_motion(scratch: ti.template(), state: ti.template()):
    """Ask for a rebuild if two particles may have closed by more than the skin since the last
    build (run on one thread: a fixed-order sum). A particle of body b moved by
    Δx_b + ΔR_b r0, so for any common vector c, |Δpᵢ − Δpⱼ| <= e_a + e_b with
    e_b = |Δx_b − c| + ‖ΔR_b‖₂ ρ_b (ρ_b the body's largest |r0|; ‖ΔR_b‖₂ bounded by _turn_norm,
    for any matrix R, √2 tighter for rotations): the lists
    hold while the two largest e sum to at most the skin. Distances do not change when every
    body moves alike, so c is the middle of the bodies' Δx (per axis, halfway between the least
    and the largest): a pile falling as one rebuilds nothing, and while some bodies rest and
    others fall, each e is about half their relative motion (the mean Δx, used before, left
    nearly all of it to the fallers: 6-14 % more rebuilds in the benchmark piles). A NaN
    counts as moved."""
    B = state.x.shape[0]
    lo = ti.Vector([1e30, 1e30, 1e30], float)
    hi = -lo
    for b in range(B):
        dx, _turn = _body_shift(scratch, state, b)
        lo = ti.min(lo, dx)
        hi = ti.max(hi, dx)
    c = 0.5 * (lo + hi)
    first, second = 0.0, 0.0
    for b in range(B):
        dx, turn = _body_shift(scratch, state, b)
        e = (dx - c).norm() + turn
        if not (e <= 1e30):
            e = 1e30
        if e > first:
            second = first
            first = e
        elif e > second:
            second = e
    if not (first + second <= scratch.grid_params[2]):
        scratch.nbr_flags[0] = 1


@ti.func
def keep_build_pose(scratch: ti.template(), state: ti.template(), b):
    x, R = state.x[b], state.R[b]
    pose = scratch.build_pose[b]
    for c in ti.static(range(3)):
        pose[c] = x[c]
    for r, c in ti.static(ti.ndrange(3, 3)):
        pose[3 + 3 * r + c] = R[r, c]
    scratch.build_pose[b] = pose  # ρ_b (pose[12]) kept


@ti.func
def start_build(scratch: ti.template()):
    """Empty the active list if a build follows (a top-level statement: no loop)."""
    scratch.nbr_flags[2] *= 1 - scratch.nbr_flags[0]


@ti.func
def num_active(scratch: ti.template()):
    """Particles with a candidate at the last build (the pair stage visits only these)."""
    return scratch.nbr_flags[2]


@ti.func
def rebuild_gate(scratch: ti.template()):
    """1 when the lists must be rebuilt this substep, else 0: the build's loops run over
    ``n * gate`` items, so that in a parallel kernel they stay top-level loops."""
    return scratch.nbr_flags[0]


@ti.func
def clear_list(scratch: ti.template(), i):
    scratch.nbr_count[i] = 0


@ti.func
def _append(scratch: ti.template(), i, j, stride):
    n = ti.atomic_add(scratch.nbr_count[i], 1)
    if n < stride:
        scratch.nbr_list[i * stride + n] = j


@ti.func
def build_list(model: ti.template(), state: ti.template(), scratch: ti.template(), i):
    """Slot i's pairs from the freshly built grid, each pair found once (a half shell: the rows
    ahead of i's in z, then in y, and in i's own row only slots j > i) and appended to both
    lists; other bodies' particles within reach + skin. Then finish_list."""
    a = model.particle_body[i]
    p, r_a = state.particle_x[i], model.particle_radius[a]
    skin = scratch.grid_params[1]
    stride = list_stride(scratch, state)
    g = grid.cell_coords(scratch, p)
    for dz in range(0, 2):
        for dy in range(-1, 2):
            if dz == 1 or dy >= 0:
                own_row = dz == 0 and dy == 0
                for part in range(3):
                    lo, hi = grid.row_range(scratch, g[0], g[1] + dy, g[2] + dz, part)
                    for slot in range(lo, hi):
                        j = scratch.sorted_particle[slot]
                        b = scratch.sorted_body[slot]
                        if b != a and (j > i or not own_row):
                            d = scratch.sorted_x[slot] - p
                            reach = r_a + model.particle_radius[b] + skin
                            if d.dot(d) < reach * reach:
                                _append(scratch, i, j, stride)
                                _append(scratch, j, i, stride)
    scratch.build_x[i] = p


@ti.func
def finish_list(state: ti.template(), scratch: ti.template(), i):
    """Sort slot i's list by slot (the appends' order depends on the threads; sorted, the sums over
    it have one order), and enter it in the active list if it has a candidate."""
    stride = list_stride(scratch, state)
    n = ti.min(scratch.nbr_count[i], stride)
    base = i * stride
    for t in range(1, n):  # insertion sort: a few entries
        value = scratch.nbr_list[base + t]
        k = t - 1
        while k >= 0 and scratch.nbr_list[base + k] > value:
            scratch.nbr_list[base + k + 1] = scratch.nbr_list[base + k]
            k -= 1
        scratch.nbr_list[base + k + 1] = value
    if scratch.nbr_count[i] > 0:  # visited by the pair stage until the next build (in any order: each writes its own)
        scratch.active[ti.atomic_add(scratch.nbr_flags[2], 1)] = i
    else:  # never visited: no pair force until the next build
        scratch.particle_f[i] = ti.Vector.zero(float, 3)
        scratch.particle_couple[i] = ti.Vector.zero(float, 3)


@ti.func
def clear_flag(scratch: ti.template()):
    """After a build (or none): count it (nbr_flags[1], for benchmarks) and lower the flag."""
    scratch.nbr_flags[1] += scratch.nbr_flags[0]
    scratch.nbr_flags[0] = 0


@ti.func
def index_active_by_body(model: ti.template(), state: ti.template(), scratch: ti.template()):
    """After a build on one thread (the active list then ascends by slot, and a body's slots are
    contiguous): where each body's run of the active list starts, so that the one-thread stages
    walk bodies, passing over a sleeper at once, without testing every slot."""
    B = state.x.shape[0]
    n = num_active(scratch)
    t = 0
    for b in range(B):
        scratch.nbr_flags[3 + B + b] = t
        end = model.body_start[b] + model.body_count[b]
        while t < n and scratch.active[t] < end:
            t += 1
    scratch.nbr_flags[3 + 2 * B] = n


@ti.func
def body_active_range(state: ti.template(), scratch: ti.template(), b):
    """(first, end) of body b's run of the active list (index_active_by_body, one thread)."""
    B = state.x.shape[0]
    return scratch.nbr_flags[3 + B + b], scratch.nbr_flags[3 + B + b + 1]


@ti.func
def see_sleeper(scratch: ti.template(), b):
    scratch.nbr_flags[3 + b] = 1


@ti.func
def unsee_sleeper(scratch: ti.template(), b):
    scratch.nbr_flags[3 + b] = 0


@ti.func
def seen_sleeper(scratch: ti.template(), b):
    return scratch.nbr_flags[3 + b] != 0


@ti.func
def list_stride(scratch: ti.template(), state: ti.template()):
    return scratch.nbr_list.shape[0] // state.particle_x.shape[0]
