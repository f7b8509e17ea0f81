"""The stages' building blocks that are not a loop of their own (substep.py runs the stages in
order, force_loop.py is stage 3b's loop): placing the particles (stage 1), the planes a block
may reach, a body's wrench from its blocks' shares (stage 4), going to sleep at rest, and the
frame's contact energy.

Every stage is a ``ti.func`` whose arguments say what it reads and writes: ``u`` the TODO
units, ``model`` ModelArgs (read), ``state`` StateArgs, ``world`` WorldArgs (read),
``scratch`` ScratchArgs. A stage's loops run in parallel where it sits at a kernel's top
level, serially inside a one-thread kernel (kernels.py); every sum has a fixed order either
way, so runs are bit-reproducible. A lone body is B = 1: no grid, no pairs.
"""
import taichi as ti

from . import pair_stages, schedule
from .contact import plane_energy
from .matvec import ZERO3, abs_max, body_offset, cross, dot, matvec, norm
from .state import DAMPING, FRICTION, GX, NUM_PLANES, STIFFNESS
from .static_faces import faced, on_face

# A block's reach test is padded by this fraction of the coordinates' size (~170 float32
# ulps), covering the round-off of pᵢ = x + R r0ᵢ: a skipped plane is exactly one no particle
# of the block touches, so its force would be exactly zero.
CLEAR_MARGIN = 1e-5


@ti.func
def contact_constants(world: ti.template()):
    """(k, k_d, μ): stiffness, damping, friction."""
    return world.values[STIFFNESS], world.values[DAMPING], world.values[FRICTION]


@ti.func
def gravity(world: ti.template()):
    return ti.Vector([world.values[GX], world.values[GX + 1], world.values[GX + 2]])


@ti.func
def num_planes(world: ti.template()):
    return ti.cast(world.values[NUM_PLANES], ti.i32)


@ti.func
def place_particle(model: ti.template(), state: ti.template(), i):
    b = model.particle_body[i]
    place_body_particle(model, state, i, state.R[b], state.x[b], state.v[b], state.omega[b])


@ti.func
def place_body_particle(model: ti.template(), state: ti.template(), i, R, x, v, w):
    """Slot i placed from its body's R, x, v, ω (which a caller walking a body's particles reads once)."""
    r = matvec(R, body_offset(model, i))
    state.particle_x[i] = x + r
    state.particle_v[i] = v + cross(w, r)


@ti.func
def set_at_rest(model: ti.template(), state: ti.template(), b):
    """Body b, falling asleep after its update, set exactly at rest and its particles placed at its
    final pose: a sleeper is not placed again until it wakes or the lists are rebuilt, and left
    where the substep began (a step behind), its particles would sit elsewhere until the next
    rebuild, so its neighbours' forces, and the run's bits, would depend on when the lists are
    rebuilt (the skin, the chunks: skin.py).

    At rest P = L = 0, so v = P / M = 0 and ω = I⁻¹ L = 0 (exactly +0: each row of I⁻¹ has a
    positive diagonal entry, whose product with +0 makes the row's sum +0); x, q, R and I⁻¹ stay
    what the update just stored. TODO 7 is not asked again for I⁻¹ L of a zero L: in the
    many-body kernels its code, matrix products and all, would be compiled a third time."""
    state.P[b], state.L[b], state.v[b], state.omega[b] = ZERO3, ZERO3, ZERO3, ZERO3
    R, x = state.R[b], state.x[b]
    for i in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
        place_body_particle(model, state, i, R, x, ZERO3, ZERO3)


@ti.func
def place_particles(model: ti.template(), state: ti.template()):
    """Every particle placed, block by block: a block's body is read once for its particles (read
    per particle, a big lone body's placing took several times as long), and the blocks are
    still many for a parallel loop (a 1M-particle body has ~16,000)."""
    for k in range(model.block_start.shape[0]):
        b = model.block_body[k]
        R, x, v, w = state.R[b], state.x[b], state.v[b], state.omega[b]
        for i in range(model.block_start[k], model.block_start[k] + model.block_count[k]):
            place_body_particle(model, state, i, R, x, v, w)


@ti.func
def planes_in_reach(model: ti.template(), state: ti.template(), world: ti.template(), k):
    """Bit j set where a particle's sphere of block k may touch plane j (a NaN sets every bit).

    A particle lies at p = c + R d with c = x + R c0 and d = r0 − c0 inside the block's box
    (|dₐ| <= hₐ) and sphere (|d| <= ρ), so on each world axis |pᵢ − cᵢ| <= eᵢ =
    min(Σₐ |Rᵢₐ| hₐ, |Rᵢ| ρ) (Rᵢ the matrix's row), and n·p >= n·c − |n|·e, for any matrix R:
    a rotation or not (a TODO unit may let q drift from unit length). The plane is skipped
    when even that bound leaves the sphere (radius r) clear of it, padded by CLEAR_MARGIN for
    round-off. Both bounds, as each is the tighter for some blocks: a torus at rest reaches
    the floor with 13 of its 32 blocks by their boxes, 31 by their spheres; a round block's
    sphere is up to √3 tighter than its box. Exact along a world axis (the box's planes)."""
    b = model.block_body[k]
    x, R = state.x[b], state.R[b]
    c0, bounds = model.block_centre[k], model.block_bounds[k]
    half, rho = ti.Vector([bounds[0], bounds[1], bounds[2]]), bounds[3]
    c = x + matvec(R, c0)
    A = ti.abs(R)
    extent = ti.min(matvec(A, half), rho * ti.Vector([norm(R[0, :]), norm(R[1, :]), norm(R[2, :])]))
    radius = model.particle_radius[b]
    a_max = A[0, 0]  # max |Rᵢⱼ|, row by row
    for r, col in ti.static(ti.ndrange(3, 3)):
        if ti.static(r + col > 0):
            a_max = ti.max(a_max, A[r, col])
    size = abs_max(x) + a_max * (abs_max(c0) + rho) + radius
    near = 0
    for j in range(num_planes(world)):
        plane = world.planes[j]
        n = ti.Vector([plane[0], plane[1], plane[2]])
        gap = dot(n, c) - plane[3] - radius - CLEAR_MARGIN * (size + ti.abs(plane[3]))
        if not (gap > dot(ti.abs(n), extent)):  # written so that a NaN is near
            near |= 1 << j
    return near


@ti.func
def wrench(F, tau):
    """(F, τ) as the six numbers of a block_wrench."""
    return ti.Vector([F[0], F[1], F[2], tau[0], tau[1], tau[2]])


@ti.func
def body_wrench(model: ti.template(), scratch: ti.template(), b):
    """Stage 4's sum: F and τ (about x) on body b, its blocks' shares in block order."""
    F = ZERO3
    tau = ZERO3
    blocks = model.body_blocks[b]
    for k in range(blocks[0], blocks[0] + blocks[1]):
        w = scratch.block_wrench[k]
        F += ti.Vector([w[0], w[1], w[2]])
        tau += ti.Vector([w[3], w[4], w[5]])
    return F, tau


@ti.func
def block_contact_energy(model: ti.template(), state: ti.template(), world: ti.template(),
                         scratch: ti.template(), k, pairs: ti.template()):
    """The springs' energy ½ k δ² of block k's particles (slot order): the static planes in reach
    (the others store none; a static mesh's faces as static_faces.on_face, and none on its own
    particles), and half of each pair's. Read at a frame's end, from the placed
    particles; energies only, no forces (contact.plane_energy, pair_stages.pair_energy): the
    frame kernels compile no second copy of the contact laws."""
    b = model.block_body[k]
    start = model.block_start[k]
    end = start + model.block_count[k]
    stiffness, _kd, _mu = contact_constants(world)
    radius = model.particle_radius[b]
    near = planes_in_reach(model, state, world, k)
    energy = 0.0
    for i in range(start, end):
        if near:
            for j in range(num_planes(world)):
                if near & (1 << j):
                    if on_face(world, j, state.particle_x[i]) and not faced(model, b):
                        energy += plane_energy(state.particle_x[i], radius, world.planes[j], stiffness)
        if ti.static(pairs):
            energy += pair_stages.pair_energy(model, state, world, scratch, i)
    return energy


ENERGY_CHUNK_BITS = 8  # 2**8 = 256 blocks one GPU thread sums for a frame's contact energy (sum_energy_chunks)
ENERGY_CHUNK = 1 << ENERGY_CHUNK_BITS


@ti.func
def _chunks(K):
    """How many chunks of ENERGY_CHUNK blocks cover K blocks: a shift, as SPIR-V (Vulkan, Metal)
    cannot compile an integer division in a loop's bound."""
    return (K + ENERGY_CHUNK - 1) >> ENERGY_CHUNK_BITS


@ti.func
def sum_energy_chunks(model: ti.template(), scratch: ti.template(), worlds):
    """Off a CPU, at a kernel's top level, one world: each chunk of ENERGY_CHUNK blocks' energies
    summed in order by a thread of its own, into the chunk's first slot (a GPU's one thread
    summing 20,000 blocks would wait on every load: by estimate, unmeasured); on a CPU, or with
    many worlds (each world's thread sums its own blocks), nothing (world_energy_total)."""
    if ti.static(not schedule.on_cpu()):
        K = model.block_start.shape[0]
        one_world = ti.cast(worlds == 1, ti.i32)  # (from the rows' shape: SPIR-V's scalarising pass
        # failed on the world table's vector load in this kernel beside world_energy_total's)
        for c in range(_chunks(K) * one_world):
            total = 0.0
            for k in range(c * ENERGY_CHUNK, ti.min(K, (c + 1) * ENERGY_CHUNK)):
                total += scratch.block_energy[k]
            scratch.block_energy[c * ENERGY_CHUNK] = total


@ti.func
def world_blocks(model: ti.template(), w):
    """World w's blocks, first .. end − 1 (its bodies' blocks are consecutive, in body order)."""
    per_world = model.body_world[0][3]
    first_body, last_body = w * per_world, w * per_world + per_world - 1
    first = model.body_blocks[first_body][0]
    return first, model.body_blocks[last_body][0] + model.body_blocks[last_body][1]


@ti.func
def world_contact_energy(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
                         w, pairs: ti.template()):
    """World w's contact energy, its blocks' in block order (one thread)."""
    first, end = world_blocks(model, w)
    energy = 0.0
    for k in range(first, end):
        energy += block_contact_energy(model, state, world, scratch, k, pairs)
    return energy


@ti.func
def world_energy_total(model: ti.template(), scratch: ti.template(), w, worlds):
    """World w's contact energy from the blocks' (scratch.block_energy), in a fixed order: its
    blocks' on a CPU or with many worlds, else (one world off a CPU) the chunks' sums
    (sum_energy_chunks)."""
    total = 0.0
    if ti.static(schedule.on_cpu()):
        first, end = world_blocks(model, w)
        for k in range(first, end):
            total += scratch.block_energy[k]
    elif worlds > 1:
        first, end = world_blocks(model, w)
        for k in range(first, end):
            total += scratch.block_energy[k]
    else:
        for c in range(_chunks(model.block_start.shape[0])):
            total += scratch.block_energy[c * ENERGY_CHUNK]
    return total
