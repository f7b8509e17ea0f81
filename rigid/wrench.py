"""The wrench (F, τ) on a body from its particles, summed block by block.

Every particle still goes through the TODO units: fᵢ = TODO 2 (+ contact),
F += TODO 3 (fᵢ), τ += TODO 4 (pᵢ, x, R, r0ᵢ, fᵢ). What the blocks (see
blocks.py) change is how much contact work a particle costs: a block whose
bounding sphere is clear of the box's five planes runs a loop without the
plane tests, because there every contact force would be exactly zero and
f + 0 = f. LLVM vectorises both loops (if-converting the plane tests, which then
cost the same whether or not a particle touches), so the skip is where the time
goes: a body in flight pays ~1/5 of the contact loop's cost per particle.

The clear test is conservative: the block's sphere is moved by (x, R) with R's
gain (an upper bound on |R r| / |r|, exactly 1 for a rotation, more if a TODO
unit lets q drift from unit length) and the radius is padded by a relative
margin (1e-5 of the coordinates' size, ~170 float32 ulps) that covers the
round-off of computing pᵢ = x + R r0ᵢ. A NaN anywhere fails the test and takes
the full loop.

Sums: F and τ of a block are summed over its particles in block order, then
the blocks' sums in block order, by one thread (serial path) or per block by
any thread then in block order (parallel.py): the same order either way.
"""
import taichi as ti

from .contact import box_force

CLEAR_MARGIN = 1e-5  # relative padding of the clear test (see the module docstring)


def make_wrench(model, params, blocks, units):
    """Return the ``ti.func``s ``particle_force``, ``rotation_gain``, ``block_wrench``, ``body_wrench``."""
    u, prm, bl = units, params, blocks

    @ti.func
    def particle_force(b, p, pv):
        """Force on one particle of body b at world position p, velocity pv; and its elastic energy."""
        f = u.gravity_force(model.particle_mass[b], prm.gravity[None])
        energy = 0.0
        if prm.walls[None]:
            fc, energy = box_force(p, pv, prm.floor[None], prm.wall[None],
                                   prm.collision_stiffness[None],
                                   prm.velocity_damping_stiffness[None],
                                   prm.friction_stiffness[None])
            f += fc
        return f, energy

    @ti.func
    def rotation_gain(R):
        """Upper bound on |R r| / |r|: sqrt of the largest Gershgorin row sum of RᵀR."""
        G = R.transpose() @ R
        bound = 0.0
        for i in ti.static(range(3)):
            bound = ti.max(bound, ti.abs(G[i, 0]) + ti.abs(G[i, 1]) + ti.abs(G[i, 2]))
        return ti.sqrt(bound)

    @ti.func
    def block_clear(k, x, R, gain):
        """True when no particle of block k can be behind the floor or a wall (or walls are off)."""
        clear = True
        if prm.walls[None]:
            floor, wall = prm.floor[None], prm.wall[None]
            centre, radius = bl.block_centre[k], bl.block_radius[k]
            c = x + R @ centre
            size = ti.abs(x).max() + gain * (ti.abs(centre).sum() + radius) + ti.abs(floor) + ti.abs(wall)
            reach = gain * radius + CLEAR_MARGIN * size
            clear = (c[1] - reach > floor and c[0] + reach < wall and c[0] - reach > -wall
                     and c[2] + reach < wall and c[2] - reach > -wall)
        return clear

    @ti.func
    def block_wrench(k, b, x, R, v, omega, gain):
        """F and τ (about x) on body b from the particles of its block k, summed in block order."""
        F = ti.Vector.zero(float, 3)
        tau = ti.Vector.zero(float, 3)
        start = bl.block_start[k]
        end = start + bl.block_count[k]
        if block_clear(k, x, R, gain):
            # Gravity only: particle_force's contact term would be exactly zero here.
            m, g = model.particle_mass[b], prm.gravity[None]
            for j in range(start, end):
                r0 = bl.r0[j]
                r = R @ r0
                f = u.gravity_force(m, g)
                F += u.total_force_term(f)
                tau += u.torque_term(x + r, x, R, r0, f)
        else:
            for j in range(start, end):
                r0 = bl.r0[j]
                r = R @ r0
                p = x + r
                f, _ = particle_force(b, p, v + omega.cross(r))
                F += u.total_force_term(f)
                tau += u.torque_term(p, x, R, r0, f)
        return F, tau

    @ti.func
    def body_wrench(b, x, R, v, omega):
        """Total force F (TODO 3) and torque τ about x (TODO 4) on body b at (x, R, v, ω), serial."""
        gain = rotation_gain(R)
        F = ti.Vector.zero(float, 3)
        tau = ti.Vector.zero(float, 3)
        first = bl.body_block_start[b]
        for k in range(first, first + bl.body_block_count[b]):
            F_k, tau_k = block_wrench(k, b, x, R, v, omega, gain)
            F += F_k
            tau += tau_k
        return F, tau

    return particle_force, rotation_gain, block_wrench, body_wrench
