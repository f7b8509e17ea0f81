"""The one contact law: static planes on particles and particles of two bodies on each other.

With ``restitution`` / ``friction`` / [[plane]] / [[static]] in the scene, the same law takes
each contact's damper from its materials and friction sticks on the planes
(``plane_force_sticking`` on the planes, ``pair_contact_sticking`` between bodies: a
tangential spring per contact that slips at μ f_n; rigid.engine.materials says how, and
rigid.engine.pair_slip how each pair's spring is kept).

Every contact, wall or pair, is a penalty spring on the overlap δ of a particle's sphere
(radius r, the body's ``particle_radius``) with the other side, with
  f_n = max(0, k δ − k_d v_n)                 spring + damping of the approach speed, never pulling
  f_t = −min(μ f_n, k_d |v_t|) v_t / |v_t|    Coulomb friction, viscous (k_d) where it would stick
(k ``collision_stiffness``, k_d ``velocity_damping_stiffness``, μ ``friction_stiffness``;
v_n, v_t the normal and tangential parts of the relative velocity at the contact).

Why this law:
- The clamp f_n ≥ 0 keeps damping from gluing a separating particle to the wall.
- Friction's sticking regime is a viscous force capped at k_d: no stiffer than the normal
  damping, which the step already resolves (explicit Euler needs Δt k_d / m < 2). A
  coefficient that grows with the load (μ f_n / v_slip, this engine's old wall law) passes
  that limit under a stack (the lower bodies carry many times their weight) and tips it over.
- Spheres, not centres: two bodies' particles must touch before their centres meet, and a
  wall the same way, so the gap a body rests at is one rule for walls and pairs. The spheres
  sit inside the mesh, tangent to its faces (rigid.bodies.inset), so a body touches at its
  mesh's surface, alone or in company. A lone body has radius 0 unless ``particle_radius`` is
  set: its particles are the mesh's vertices, as on the slides, and the drawn mesh touches the
  floor.

A pair's force acts at the contact point c, in the middle of the overlap; the engine applies
it at the particle centre through TODO 3 and 4 and adds the couple (c − pᵢ) × fᵢ that moves it
to c, so the two equal and opposite forces change neither the total momentum nor the total
angular momentum. The engine evaluates each pair from its lower particle slot whichever side
asks (rigid.engine.pair_stages.pair_between), so the force j gets is exactly −fᵢ: the law
written from each side is antisymmetric on paper, but LLVM contracts its products into FMAs
differently for the two orders, and about half the pairs came out a few ulps apart.
"""
import taichi as ti

from .matvec import ZERO3, cross, dot, norm


@ti.func
def friction(fn, vt, mu, kd):
    """Coulomb friction against the tangential velocity vt, capped by viscous damping kd."""
    speed = norm(vt)
    force = ZERO3
    if speed > 0:
        force = (-ti.min(mu * fn, kd * speed) / speed) * vt
    return force


@ti.func
def plane_depth(p, radius, plane):
    """The plane {y : n·y = offset} (``plane`` = (n, offset), n into the free side) and a particle's
    sphere at p: (n, the overlap δ = offset + radius − n·p; positive where they touch)."""
    normal = ti.Vector([plane[0], plane[1], plane[2]])
    return normal, plane[3] + radius - dot(normal, p)


@ti.func
def plane_force(p, v, radius, plane, k, kd, mu):
    """The plane ``plane`` (``plane_depth``) on a particle's
    sphere at p moving at v: the force at its centre and the spring's energy ½ k δ²."""
    force = ZERO3
    energy = 0.0
    normal, depth = plane_depth(p, radius, plane)
    if depth > 0:
        vn = dot(normal, v)
        fn = ti.max(k * depth - kd * vn, 0.0)
        force = fn * normal + friction(fn, v - vn * normal, mu, kd)
        energy = 0.5 * k * depth * depth
    return force, energy


@ti.func
def plane_energy(p, radius, plane, k):
    """The spring energy ½ k δ² of ``plane_force``, by the same operations, without the force."""
    energy = 0.0
    _normal, depth = plane_depth(p, radius, plane)
    if depth > 0:
        energy = 0.5 * k * depth * depth
    return energy


@ti.func
def sticking_friction(slip, n, vt, step, k, ct, mu, fn):
    """Coulomb friction that sticks, for a contact of normal n carrying normal force fn: a
    tangential spring k whose stretch ``slip`` (world vec3, zero when the contact began) is
    projected onto the current tangent plane (the contact turns) and grows by the tangential
    velocity vt of the moving side over ``step``, damped by ct, slipping at μ fn (then
    re-anchored where the spring alone holds μ fn). Returns (the tangential force on the side
    moving at vt, the new stretch)."""
    s = slip - dot(n, slip) * n + step * vt
    ft = -k * s - ct * vt
    cap = mu * fn
    size = norm(ft)
    if size > cap:
        ft = (cap / size) * ft  # size > cap >= 0
        s = ZERO3
        if k > 0:
            s = (-1.0 / k) * ft
    return ft, s


@ti.func
def plane_force_sticking(p, v, radius, plane, k, c, ct, mu, slip, step):
    """The material contact with a plane (rigid.engine.materials): the normal law with the
    contact's own damper c, and Coulomb friction with sticking: a tangential spring k whose
    stretch ``slip`` (world vec3, zero when the contact begins) grows by v_t ``step`` (the time
    the force acts), damped by ct, slipping at μ f_n (then re-anchored where the spring alone
    holds μ f_n). Returns (force at the centre, the new slip, 1 if touching else 0)."""
    force = ZERO3
    new_slip = ZERO3
    touching = 0
    normal, depth = plane_depth(p, radius, plane)
    if depth > 0:
        touching = 1
        vn = dot(normal, v)
        fn = ti.max(k * depth - c * vn, 0.0)
        ft, new_slip = sticking_friction(slip, normal, v - vn * normal, step, k, ct, mu, fn)
        force = fn * normal + ft
    return force, new_slip, touching


@ti.func
def pair_force(p_i, p_j, r_a, r_b, x_a, v_a, w_a, x_b, v_b, w_b, k, kd, mu):
    """Particle j (body b) on particle i (body a): (force on i, its couple about p_i moving it to
    the contact point, half the pair's ½ k δ² (each pair is visited from both sides))."""
    return pair_force_damped(p_i, p_j, r_a, r_b, x_a, v_a, w_a, x_b, v_b, w_b, k, kd, kd, mu)


@ti.func
def pair_force_damped(p_i, p_j, r_a, r_b, x_a, v_a, w_a, x_b, v_b, w_b, k, kd, kt, mu):
    """``pair_force`` with the normal damper kd and the sticking friction's kt apart (materials)."""
    force, c, energy = pair_contact(p_i, p_j, r_a, r_b, x_a, v_a, w_a, x_b, v_b, w_b, k, kd, kt, mu)
    # Apart: zero force and c = 0, so a zero couple (its sign bits add nothing to a sum).
    return force, cross(c - p_i, force), energy


@ti.func
def lower_slot_first(i, j, p_i, r_i, x_i, v_i, w_i, p_j, r_j, x_j, v_j, w_j):
    """The two sides of the pair of slots i and j, the lower slot's first, and the sign that turns
    the force on the lower side into the force on i. Every pair is evaluated from its lower
    slot's side whichever side asks, so the two sides get exactly opposite forces (the same
    operations on the same numbers; LLVM contracts the law written from each side differently)."""
    lo_p, lo_r, lo_x, lo_v, lo_w = p_i, r_i, x_i, v_i, w_i
    hi_p, hi_r, hi_x, hi_v, hi_w = p_j, r_j, x_j, v_j, w_j
    sign = 1.0
    if j < i:
        lo_p, lo_r, lo_x, lo_v, lo_w = p_j, r_j, x_j, v_j, w_j
        hi_p, hi_r, hi_x, hi_v, hi_w = p_i, r_i, x_i, v_i, w_i
        sign = -1.0
    return lo_p, lo_r, lo_x, lo_v, lo_w, hi_p, hi_r, hi_x, hi_v, hi_w, sign


@ti.func
def _pair_overlap(p_i, p_j, r_a, r_b):
    """Two particles' spheres: (whether they overlap, d = p_j − p_i, |d|, the overlap δ); zeros past
    d when apart (or at one point, where no normal exists)."""
    touching = False
    dist = 0.0
    overlap = 0.0
    d = p_j - p_i
    dist2 = dot(d, d)
    reach = r_a + r_b
    if dist2 < reach * reach and dist2 > 0:
        touching = True
        dist = ti.sqrt(dist2)
        overlap = reach - dist
    return touching, d, dist, overlap


@ti.func
def _pair_frame(p_i, p_j, r_a, r_b, x_a, v_a, w_a, x_b, v_b, w_b):
    """Two particles' spheres: (whether they overlap, the normal n from i to j, the overlap δ, the
    contact point c in the middle of the overlap, j's velocity relative to i's at c); zeros
    when apart (``_pair_overlap``)."""
    n = ZERO3
    c = ZERO3
    v_rel = ZERO3
    touching, d, dist, overlap = _pair_overlap(p_i, p_j, r_a, r_b)
    if touching:
        n = d / dist
        c = 0.5 * (p_i + p_j) + (0.5 * (r_a - r_b)) * n
        v_rel = (v_b + cross(w_b, c - x_b)) - (v_a + cross(w_a, c - x_a))
    return touching, n, overlap, c, v_rel


@ti.func
def pair_contact(p_i, p_j, r_a, r_b, x_a, v_a, w_a, x_b, v_b, w_b, k, kd, kt, mu):
    """Particle j (body b) on particle i (body a): (force on i, the contact point c, half the
    pair's ½ k δ²); zeros when the spheres are apart. One evaluation serves both sides: j's
    force is −force, at the same c (rigid.engine.pair_once)."""
    force = ZERO3
    energy = 0.0
    touching, n, overlap, c, v_rel = _pair_frame(p_i, p_j, r_a, r_b, x_a, v_a, w_a, x_b, v_b, w_b)
    if touching:
        vn = dot(v_rel, n)
        fn = ti.max(k * overlap - kd * vn, 0.0)
        # The relative velocity is j's relative to i: friction on i acts along +v_t.
        force = -fn * n - friction(fn, v_rel - vn * n, mu, kt)
        energy = _half_pair_energy(k, overlap)
    return force, c, energy


@ti.func
def pair_contact_energy(p_i, p_j, r_a, r_b, k):
    """``pair_contact``'s energy alone: half the pair's ½ k δ² (zero when apart), by the same
    operations."""
    energy = 0.0
    touching, _d, _dist, overlap = _pair_overlap(p_i, p_j, r_a, r_b)
    if touching:
        energy = _half_pair_energy(k, overlap)
    return energy


@ti.func
def _half_pair_energy(k, overlap):
    """Half of a pair's spring energy ½ k δ² (each side of the pair holds half)."""
    return 0.25 * k * overlap * overlap


@ti.func
def pair_contact_sticking(p_i, p_j, r_a, r_b, x_a, v_a, w_a, x_b, v_b, w_b, k, c, ct, mu, slip, step):
    """``pair_contact`` with Coulomb friction that sticks (materials), as ``plane_force_sticking``
    on a plane: a tangential spring k whose stretch ``slip`` (world vec3: j's displacement
    relative to i since the contact began, zero then) grows by v_t ``step``, is projected onto
    the current tangent plane (the pair turns), damped by ct and slips at μ f_n, re-anchored
    where the spring alone holds μ f_n. Returns (force on i, the contact point, the new slip:
    zero when apart)."""
    force = ZERO3
    new_slip = ZERO3
    touching, n, overlap, point, v_rel = _pair_frame(p_i, p_j, r_a, r_b, x_a, v_a, w_a, x_b, v_b, w_b)
    if touching:
        vn = dot(v_rel, n)
        fn = ti.max(k * overlap - c * vn, 0.0)
        # On j: the spring pulls it back to where the contact began; i gets the opposite.
        ft, new_slip = sticking_friction(slip, n, v_rel - vn * n, step, k, ct, mu, fn)
        force = -fn * n - ft
    return force, point, new_slip


@ti.func
def box_force(p, v, radius, floor, wall, k, kd, mu):
    """The assignment's box (floor y = floor, walls x, z = ±wall) on one particle: the sum of its
    five planes in the engine's order (rigid.engine.state.Params.plane_list), and their energy."""
    force = ZERO3
    energy = 0.0
    for plane in ti.static(((0.0, 1.0, 0.0, 0), (1.0, 0.0, 0.0, 1), (-1.0, 0.0, 0.0, 1), (0.0, 0.0, 1.0, 1),
                            (0.0, 0.0, -1.0, 1))):
        offset = floor if ti.static(plane[3] == 0) else -wall
        f, e = plane_force(p, v, radius, ti.Vector([plane[0], plane[1], plane[2], offset]), k, kd, mu)
        force += f
        energy += e
    return force, energy
