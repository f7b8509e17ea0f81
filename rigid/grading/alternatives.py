"""Right answers that differ from the reference units, accepted by the grader.

TODO 5 in the velocity-first (semi-implicit) order: P first, then x moves with
the new P. The assignment's later handout and Warp use it; the slides' explicit
Euler uses the old P. Both get full marks; the trajectory check compares a
velocity-first submission with a reference run in the same order.
"""
import taichi as ti


@ti.func
def update_linear_velocity_first(position, momentum, force, mass, dt):
    new_momentum = momentum + dt * force
    return position + dt * new_momentum / mass, new_momentum
