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

from .contact import box_force, floor_force
from .matvec import column_dot, matvec

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
        bound = 0.0
        for i in ti.static(range(3)):
            bound = ti.max(bound, ti.abs(column_dot(R, i, 0)) + ti.abs(column_dot(R, i, 1))
                           + ti.abs(column_dot(R, i, 2)))
        return ti.sqrt(bound)

    @ti.func
    def planes_in_reach(k, x, R, gain):
        """(floor, wall): whether a particle of block k may be behind the floor, behind a wall."""
        floor_near, wall_near = False, False
        if prm.walls[None]:
            floor, wall = prm.floor[None], prm.wall[None]
            centre, radius = bl.block_centre[k], bl.block_radius[k]
            c = x + matvec(R, centre)
            size = ti.abs(x).max() + gain * (ti.abs(centre).sum() + radius) + ti.abs(floor) + ti.abs(wall)
            reach = gain * radius + CLEAR_MARGIN * size
            # Written so that a NaN makes a plane near: comparisons with NaN are false.
            floor_near = not c[1] - reach > floor
            wall_near = not (c[0] + reach < wall and c[0] - reach > -wall
                             and c[2] + reach < wall and c[2] - reach > -wall)
        return floor_near, wall_near

    def particle_loop(planes: str):
        """A ti.func summing F, τ over particles [start, end) with contact from ``planes``:
        "none" (gravity only), "floor", or "box" (all five planes, as particle_force)."""

        @ti.func
        def loop(start, end, b, x, R, v, omega):
            F = ti.Vector.zero(float, 3)
            tau = ti.Vector.zero(float, 3)
            # Loaded once, so that LLVM vectorises the loop (the values are particle_force's).
            m, g = model.particle_mass[b], prm.gravity[None]
            floor, wall = prm.floor[None], prm.wall[None]
            k, kd, mu = prm.collision_stiffness[None], prm.velocity_damping_stiffness[None], prm.friction_stiffness[None]
            for j in range(start, end):
                r0 = bl.r0[j]
                r = matvec(R, r0)
                p = x + r
                f = u.gravity_force(m, g)
                if ti.static(planes == "floor"):
                    fc, _e = floor_force(p, v + omega.cross(r), floor, k, kd, mu)
                    f += fc
                elif ti.static(planes == "box"):
                    fc, _e = box_force(p, v + omega.cross(r), floor, wall, k, kd, mu)
                    f += fc
                F += u.total_force_term(f)
                tau += u.torque_term(p, x, R, r0, f)
            return F, tau

        return loop

    free_loop, floor_loop, box_loop = particle_loop("none"), particle_loop("floor"), particle_loop("box")

    @ti.func
    def block_wrench(k, b, x, R, v, omega, gain):
        """F and τ (about x) on body b from the particles of its block k, summed in block order."""
        start = bl.block_start[k]
        end = start + bl.block_count[k]
        floor_near, wall_near = planes_in_reach(k, x, R, gain)
        F = ti.Vector.zero(float, 3)
        tau = ti.Vector.zero(float, 3)
        if wall_near:
            F, tau = box_loop(start, end, b, x, R, v, omega)
        elif floor_near:  # the four walls' forces would be exactly zero
            F, tau = floor_loop(start, end, b, x, R, v, omega)
        else:  # all five would be
            F, tau = free_loop(start, end, b, x, R, v, omega)
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
