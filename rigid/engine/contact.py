"""Contact with the assignment's box: floor y = floor, walls x = ±wall, z = ±wall.

Each of the five planes pushes a particle that is ``depth`` > 0 behind it with
  f_n = max(0, k·depth − k_d·(v·n))           (penalty spring + normal damping)
  f_t = −μ f_n · v_t / max(|v_t|, v_slip)     (Coulomb friction, regularised)
where n is the plane's normal into the box, v_t = v − (v·n) n. The handout
declared k_d (``velocity_damping_stiffness``) and μ (``friction_stiffness``)
but never used them. Clamping f_n at zero keeps damping from gluing a
separating particle to the wall. Below ``V_SLIP`` the friction is viscous
instead of a sign flip, which an explicit integrator would turn into chatter.
"""
import taichi as ti

V_SLIP = 1e-2  # m/s; sliding slower than this is treated as sticking (viscous friction)


@ti.func
def plane_force(p, v, normal, offset, k, kd, mu):
    """Force and elastic energy from the plane {y : normal·y = offset}, normal into the box."""
    force = ti.Vector.zero(float, 3)
    energy = 0.0
    depth = offset - normal.dot(p)
    if depth > 0:
        vn = normal.dot(v)
        fn = ti.max(k * depth - kd * vn, 0.0)
        vt = v - vn * normal
        force = fn * normal - mu * fn * vt / ti.max(vt.norm(), V_SLIP)
        energy = 0.5 * k * depth * depth
    return force, energy


@ti.func
def floor_force(p, v, floor, k, kd, mu):
    """The floor's share of box_force (the engine calls it alone where no wall is near)."""
    return plane_force(p, v, ti.Vector([0.0, 1.0, 0.0]), floor, k, kd, mu)


@ti.func
def box_force(p, v, floor, wall, k, kd, mu):
    """Total contact force on a particle at p moving at v, and the springs' elastic energy."""
    f0, e0 = floor_force(p, v, floor, k, kd, mu)
    f1, e1 = plane_force(p, v, ti.Vector([1.0, 0.0, 0.0]), -wall, k, kd, mu)
    f2, e2 = plane_force(p, v, ti.Vector([-1.0, 0.0, 0.0]), -wall, k, kd, mu)
    f3, e3 = plane_force(p, v, ti.Vector([0.0, 0.0, 1.0]), -wall, k, kd, mu)
    f4, e4 = plane_force(p, v, ti.Vector([0.0, 0.0, -1.0]), -wall, k, kd, mu)
    return f0 + f1 + f2 + f3 + f4, e0 + e1 + e2 + e3 + e4
