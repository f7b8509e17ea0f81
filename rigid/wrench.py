"""The wrench (F, τ) on a body from its particles, summed block by block.

Every particle still goes through the TODO units: fᵢ = TODO 2 (+ contact),
F += TODO 3 (fᵢ), τ += TODO 4 (pᵢ, x, R, r0ᵢ, fᵢ). What the blocks (see
blocks.py) change is how much contact work a particle costs. Once per block
and substep, the block says which planes its particles may
be behind (its bounding box, moved by (x, R)), and one of three loops runs:
  "none"  (clear of all five planes)     gravity only
  "floor" (near the floor, no wall)      gravity + the floor's force
  "box"   (near a wall)                  gravity + box_force, as particle_force
The planes left out would give exactly zero force there, and f + 0 = f, so the
sums are those of the plain loop. LLVM vectorises all three loops, if-converting
the plane tests (a vectorised plane costs the same whether or not a particle
touches it), so leaving planes out is where the time goes: per particle, ~0.6 ns
in flight, ~2 ns on the floor, ~5 ns by a wall (one core, float32).

The reach test is exact up to a margin: the block's box, moved by (x, R),
extends Σ_j |R[a, j]| h_j along world axis a for any matrix R (a rotation, or
not, if a TODO unit lets q drift from unit length), padded by a relative
margin (1e-5 of the coordinates' size, ~170 float32 ulps) that covers the
round-off of computing pᵢ = x + R r0ᵢ. A NaN makes every plane near.

Sums: F and τ of a block are summed over its particles in block order, then
the blocks' sums in block order, by one thread (serial path) or per block by
any thread then in block order (parallel.py): the same order either way.
"""
import taichi as ti

from .contact import box_force, floor_force
from .matvec import matvec

CLEAR_MARGIN = 1e-5  # relative padding of the clear test (see the module docstring)


def make_wrench(model, params, blocks, units):
    """Return the ``ti.func``s ``particle_force``, ``planes_in_reach``, ``block_wrench``, ``body_wrench``."""
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
    def planes_in_reach(k, x, R):
        """(floor, wall): whether a particle of block k may be behind the floor, behind a wall."""
        floor_near, wall_near = False, False
        if prm.walls[None]:
            floor, wall = prm.floor[None], prm.wall[None]
            centre, half = bl.block_centre[k], bl.block_half[k]
            c = x + matvec(R, centre)
            # The box's extent along world axis a is exactly Σ_j |R[a, j]| h_j, for any matrix R.
            reach = matvec(ti.abs(R), half)
            size = ti.abs(x).max() + matvec(ti.abs(R), ti.abs(centre) + half).max() + ti.abs(floor) + ti.abs(wall)
            reach += CLEAR_MARGIN * size
            # Written so that a NaN makes a plane near: comparisons with NaN are false.
            floor_near = not c[1] - reach[1] > floor
            wall_near = not (c[0] + reach[0] < wall and c[0] - reach[0] > -wall
                             and c[2] + reach[2] < wall and c[2] - reach[2] > -wall)
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
    def block_wrench(k, b, x, R, v, omega):
        """F and τ (about x) on body b from the particles of its block k, summed in block order."""
        start = bl.block_start[k]
        end = start + bl.block_count[k]
        floor_near, wall_near = planes_in_reach(k, x, R)
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
        F = ti.Vector.zero(float, 3)
        tau = ti.Vector.zero(float, 3)
        first = bl.body_block_start[b]
        for k in range(first, first + bl.body_block_count[b]):
            F_k, tau_k = block_wrench(k, b, x, R, v, omega)
            F += F_k
            tau += tau_k
        return F, tau

    return particle_force, planes_in_reach, block_wrench, body_wrench
