"""Contact between two particles of different bodies (Harada, GPU Gems 3, ch. 29), at the contact point.

Particles i (body a, radius r_a) and j (body b, radius r_b) overlap by
δ = r_a + r_b − |p_j − p_i| > 0. With n = (p_j − p_i)/|p_j − p_i| and the contact
point c on the line between them, in the middle of the overlap,
  c = ½ (p_i + p_j) + ½ (r_a − r_b) n,
the relative velocity is that of the two bodies' material at c,
  v_rel = (v_b + ω_b × (c − x_b)) − (v_a + ω_a × (c − x_a)),   v_n = v_rel·n,
and the force on i is, as the walls' (contact.py),
  f_n = max(0, k δ − k_d v_n)                  spring on the overlap + damping, never pulling
  f_i = −f_n n + μ f_n v_t / max(|v_t|, v_slip)  v_t = v_rel − v_n n (Coulomb, regularised)
acting at c. The engine applies f_i at the particle centre through TODO 3 and 4
and adds the couple (c − p_i) × f_i, which moves it to c: then the pair's two
forces, equal and opposite at one point, change neither the total momentum nor
the total angular momentum.

Every expression is antisymmetric in (i, j) operation by operation (c is
computed from a symmetric formula, a − b = −(b − a) exactly in IEEE arithmetic),
so the force j gets when it visits i is exactly −f_i, bit for bit.
"""
import taichi as ti

from .contact import V_SLIP


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
        force = -fn * n + (mu * fn / ti.max(vt.norm(), V_SLIP)) * vt
        couple = (c - p_i).cross(force)
        energy = 0.25 * k * overlap * overlap  # each pair is visited from both sides
    return force, couple, energy
