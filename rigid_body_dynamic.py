"""HKU Data-driven Computer Animation, Assignment 3: a rigid body simulator in Taichi.

A rigid body is a set of particles (the mesh's vertices) of equal mass m. The
state is Y = (x, q, P, L): centre of mass, orientation quaternion (scalar first
[s, vx, vy, vz]), linear and angular momentum. Each substep of Δt:

    forces on particles -> total force F and torque τ -> x, P -> q -> L, I⁻¹, ω

Your work is the 7 TODOs below, each a small Taichi function with its inputs as
arguments and its results returned; the engine in rigid/ calls them for every
particle and every substep. Run:

    python rigid_body_dynamic.py                      # a window (needs Vulkan)
    python rigid_body_dynamic.py --headless --frames 300 --export out.npz
    python rigid_body_dynamic.py --record out.mp4 --frames 300
    python rigid_body_dynamic.py --help               # every option
    python rigid_body_dynamic.py --check              # grade your 7 TODOs before you submit

Useful Taichi calls: a.dot(b) (aᵀb), a.outer_product(b) (a bᵀ), a.cross(b)
(or ti.math.cross(a, b)), M @ v, M.transpose(), v.norm(),
ti.Matrix.identity(float, 3), and the quaternion helpers given below.
"""
from rigid.engine.rotation import quaternion_multiplication, quaternion_to_matrix  # noqa: F401 (given helpers)

import taichi as ti  # after rigid, which sets Taichi's environment (no version check, no banner)


@ti.func
def particle_inertia(particle_mass, r0):
    """Inertia of one particle about the centre of mass: a 3x3 matrix.

    r0 is the particle's offset from the centre of mass (body frame). The
    engine sums your result over all particles: I0 = Σ (your matrix).
    """
    # TODO 1: Compute the inertia tensor of the body
    # Hint: I0 = Σ m (r0ᵀ r0 E − r0 r0ᵀ), E the 3x3 identity.
    # Hint: r0.dot(r0) is r0ᵀ r0; r0.outer_product(r0) is r0 r0ᵀ;
    #       ti.Matrix.identity(float, 3) is E.
    inertia = particle_mass * (r0.dot(r0) * ti.Matrix.identity(float, 3) - r0.outer_product(r0))
    # END TODO 1
    return inertia


@ti.func
def gravity_force(particle_mass, gravity):
    """Force of gravity on one particle (a 3-vector, N). gravity is g, e.g. (0, -9.8, 0)."""
    # TODO 2: gravity
    # Hint: f = m g. The engine adds the contact forces of the box to it.
    force = particle_mass * gravity
    # END TODO 2
    return force


@ti.func
def total_force_term(particle_force):
    """What one particle's force adds to the total force F on the body."""
    # TODO 3: compute the force for rigid body
    # Hint: F = Σ fᵢ: return this particle's share; the engine does the sum.
    term = particle_force
    # END TODO 3
    return term


@ti.func
def torque_term(particle_position, body_position, rotation, r0, particle_force):
    """What one particle's force adds to the torque τ on the body, about its centre of mass.

    particle_position pᵢ and body_position x are world positions; rotation is R;
    r0 is the particle's body-frame offset, so pᵢ = x + R r0.
    """
    # TODO 4: compute the torque for rigid body
    # Hint: τ = Σ rᵢ × fᵢ with rᵢ the particle's world offset from the centre of mass.
    # Hint: use ti.math.cross(a, b) or a.cross(b); mind the order: r × f, not f × r.
    r = rotation @ r0
    term = r.cross(particle_force)
    # END TODO 4
    return term


@ti.func
def update_linear(position, momentum, force, mass, dt):
    """One explicit Euler step of the centre of mass x and linear momentum P.

    Returns (new x, new P). Explicit Euler uses the values at the start of the step.
    """
    # TODO 5: update the center of mass position and velocity
    # Hint: v = P / M;  x ← x + Δt v;  P ← P + Δt F.
    new_position = position + dt * momentum / mass
    new_momentum = momentum + dt * force
    # END TODO 5
    return new_position, new_momentum


@ti.func
def update_orientation(q, omega, dt):
    """One explicit Euler step of the orientation quaternion q (scalar first), renormalised.

    omega is the angular velocity ω (world frame) at the start of the step.
    """
    # TODO 6: update the rotation quaternion
    # Hint: dq/dt = ½ [0, ω] ⊗ q, with quaternion_multiplication(p, q) for p ⊗ q.
    # Hint: after the step divide q by its norm so that it stays a unit quaternion.
    dq = 0.5 * quaternion_multiplication(ti.Vector([0.0, omega[0], omega[1], omega[2]]), q)
    new_q = q + dt * dq
    new_q = new_q / new_q.norm()
    # END TODO 6
    return new_q


@ti.func
def update_angular(angular_momentum, torque, rotation, inertia_body_inv, dt):
    """Update the angular momentum L, then the world inverse inertia and ω.

    rotation is R of the already updated quaternion; inertia_body_inv is I0⁻¹.
    Returns (new L, I⁻¹, ω), all in the world frame.
    """
    # TODO 7: update, the angular momentum, inertia tensor and angular velocity
    # Hint: L ← L + Δt τ;  I⁻¹ = R I0⁻¹ Rᵀ;  ω = I⁻¹ L (with the new L).
    new_L = angular_momentum + dt * torque
    inertia_inv = rotation @ inertia_body_inv @ rotation.transpose()
    omega = inertia_inv @ new_L
    # END TODO 7
    return new_L, inertia_inv, omega


def main(argv=None):
    """Run the simulator with the units of this file (see --help); --check grades the 7 TODOs."""
    import sys

    if "--check" in (sys.argv[1:] if argv is None else argv):  # the grader's checks, against the answers file
        from rigid.grading.selfcheck import main as check

        return check(sys.modules[__name__], argv)
    from rigid.cli import main as run

    return run(argv, units=sys.modules[__name__])


if __name__ == "__main__":
    raise SystemExit(main())
