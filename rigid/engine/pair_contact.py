"""Contact between two particles of different bodies (Harada, GPU Gems 3, ch. 29), at the contact point.

Particles i (body a, radius r_a) and j (body b, radius r_b) overlap by
δ = r_a + r_b − |p_j − p_i| > 0. With n = (p_j − p_i)/|p_j − p_i| and the contact
point c on the line between them, in the middle of the overlap,
  c = ½ (p_i + p_j) + ½ (r_a − r_b) n,
the relative velocity is that of the two bodies' material at c,
  v_rel = (v_b + ω_b × (c − x_b)) − (v_a + ω_a × (c − x_a)),   v_n = v_rel·n,
and the force on i is
  f_n = max(0, k δ − k_d v_n)                     spring on the overlap + damping, never pulling
  f_i = −f_n n + min(μ f_n, k_d |v_t|) v_t/|v_t|  v_t = v_rel − v_n n: Coulomb friction,
                                                  viscous (k_d) where it would stick
acting at c. The sticking regime differs from the single body's walls
(contact.py: μ f_n / v_slip): in a stack the lower bodies carry many times their
own weight, and a viscous coefficient μ f_n / v_slip that grows with the load
then passes explicit integration's stability limit (Δt c / m < 2), tipping the
stack over. Capped at k_d, the tangential damping is no stiffer than the normal
damping, which the step already resolves. Many-body walls use the same rule,
on each particle's sphere (``sphere_wall_force``). The engine applies f_i at the particle centre through TODO 3 and 4
and adds the couple (c − p_i) × f_i, which moves it to c: then the pair's two
forces, equal and opposite at one point, change neither the total momentum nor
the total angular momentum.

Every expression is antisymmetric in (i, j) operation by operation (c is
computed from a symmetric formula, a − b = −(b − a) exactly in IEEE arithmetic),
so the force j gets when it visits i is exactly −f_i, bit for bit.
"""
import taichi as ti



@ti.func
def friction(fn, vt, mu, kd):
    """Coulomb friction along the relative tangential velocity vt, capped by viscous damping kd."""
    speed = vt.norm()
    force = ti.Vector.zero(float, 3)
    if speed > 0:
        force = (ti.min(mu * fn, kd * speed) / speed) * vt
    return force


@ti.func
def sphere_wall_force(p, v, radius, normal, offset, k, kd, mu):
    """A plane {y : normal·y = offset} (normal into the box) on a particle's sphere of ``radius``:
    force at the centre and the spring's energy ½ k depth²."""
    force = ti.Vector.zero(float, 3)
    energy = 0.0
    depth = offset + radius - normal.dot(p)
    if depth > 0:
        vn = normal.dot(v)
        fn = ti.max(k * depth - kd * vn, 0.0)
        force = fn * normal - friction(fn, v - vn * normal, mu, kd)
        energy = 0.5 * k * depth * depth
    return force, energy


@ti.func
def pair_force(p_i, p_j, r_a, r_b, x_a, v_a, w_a, x_b, v_b, w_b, k, kd, mu):
    """(force on i, its couple about p_i moving it to the contact point, half the pair's ½ k δ²)."""
    force = ti.Vector.zero(float, 3)
    couple = ti.Vector.zero(float, 3)
    energy = 0.0
    d = p_j - p_i
    dist2 = d.dot(d)
    reach = r_a + r_b
    if dist2 < reach * reach and dist2 > 0:
        dist = ti.sqrt(dist2)
        n = d / dist
        overlap = reach - dist
        c = 0.5 * (p_i + p_j) + (0.5 * (r_a - r_b)) * n
        v_rel = (v_b + w_b.cross(c - x_b)) - (v_a + w_a.cross(c - x_a))
        vn = v_rel.dot(n)
        fn = ti.max(k * overlap - kd * vn, 0.0)
        vt = v_rel - vn * n
        force = -fn * n + friction(fn, vt, mu, kd)
        couple = (c - p_i).cross(force)
        energy = 0.25 * k * overlap * overlap  # each pair is visited from both sides
    return force, couple, energy
