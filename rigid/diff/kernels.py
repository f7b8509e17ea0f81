"""The kernels of the differentiable pass: the engine's substep, written time-indexed.

The physics is the engine's: the student's 7 TODO units (``u``), the contact law of
rigid.engine.contact (``plane_force``, or ``plane_force_sticking`` with the damper of
rigid.engine.materials.plane_damping when the scene sets materials), drag as
rigid.engine.forces.particle_force, the updates of rigid.engine.schemes written on the
step axis. What differs is only the schedule, so that Taichi can run each kernel backward:

- ``reach``  per particle: the planes within its radius at step s (near, and the pairs near listed),
  with materials the particles touching a plane, per body (count: the m_eff = M / n);
- ``contacts`` per pair near: the plane's force fc[s] and the sticking spring's step s + 1 (the
  other pairs' are zero, and neither written nor read);
- ``forces`` per particle: f = TODO 2 + Σ fc in plane order, into F[s], T[s] through TODO 3
  and 4 (atomic sums), then drag;
- ``update`` per body: explicit (TODO 5, 6, 7) or symplectic Euler from step s to s + 1;
- ``rows``   the row of step s (x, q, v = P/M, ω, P, L) at frame f.
``substep`` runs the four stages of one substep; ``advance`` runs a segment's substeps and rows
in one launch, and its adjoint is the backward's (``substep``'s where the loops run in parallel).
A contact is a thread of its own (the materials' damper is a table lookup whose adjoint is
long: unrolled over the planes in one particle's thread it took over a minute to compile), and
the per-particle sum over planes is unrolled (their count is a compile-time constant). Inside
``advance`` every stage is a loop below the top, so its mutable locals (that sum among them: the
planes' count + 2 values) live on Taichi's ad-stacks, sized by rigid.diff.passes's compile
settings. The engine skips planes out of a block's reach; a skipped plane's force is exactly zero,
so summing every plane gives the same force.
"""

import taichi as ti

from ..engine.contact import plane_force, plane_force_sticking
from ..engine.materials import pair_mu, pair_restitution, plane_damping, sticking_damping
from ..engine.matvec import matvec
from ..engine.rotation import quaternion_to_matrix


def _compiling_adjoint() -> bool:
    """Whether Taichi is now compiling a kernel's adjoint (read at compile time, in ti.static)."""
    from taichi.lang import impl
    from taichi.lang.enums import AutodiffMode

    return impl.get_runtime().current_kernel.autodiff_mode == AutodiffMode.REVERSE


def build(tape, units, scheme: str, materials: bool, num_planes: int, serial: bool = True):
    """The pass's kernels (a namespace) over ``tape``'s fields for these TODO units and scheme;
    ``serial``: run the substep's loops on the launching thread (at tens of particles handing a
    loop to the thread pool costs more than the loop)."""
    u, t = units, tape
    P = num_planes

    @ti.func
    def body_motion(s, b):
        """(x, R, v, ω) of body b at step s."""
        return t.x[s, b], quaternion_to_matrix(t.q[s, b]), t.P[s, b] / t.M[b], t.w[s, b]

    @ti.kernel
    def start(n: ti.i32, nb: ti.i32):
        # A run's start, three loops in one launch (and one for its adjoint, the loops reversed):
        # I0 = Σ TODO 1 per body; I0⁻¹ and M; then rigid.engine.schemes.init_body and store:
        # L = R I0 Rᵀ ω, P = M v, ω from TODO 7.
        ti.loop_config(serialize=serial)
        for i in range(n):
            b = t.particle_body[i]
            t.I0[b] += u.particle_inertia(t.m[b], t.r0_mass[i])
        ti.loop_config(serialize=serial)
        for b in range(nb):
            t.I0inv[b] = t.I0[b].inverse()
            t.M[b] = t.m[b] * t.body_count[b]
        ti.loop_config(serialize=serial)
        for b in range(nb):
            q = t.q0[b]
            R = quaternion_to_matrix(q)
            L = matvec(R, matvec(t.I0[b], matvec(R.transpose(), t.w0[b])))
            L_same, _inv, omega = u.update_angular(L, ti.Vector.zero(float, 3), R, t.I0inv[b], 0.0)
            t.x[0, b], t.q[0, b], t.P[0, b] = t.x0[b], q, t.M[b] * t.v0[b]
            t.L[0, b], t.w[0, b] = L_same, omega

    @ti.func
    def reach(s, i):
        # Per particle: near[s, i, j] = whether its sphere is within its radius of plane j, and the
        # pairs near listed in pairs[s] (beyond, the law gives no force and a spring of zero,
        # exactly; the margin keeps rounding out of the choice); with materials, count[s, b].
        b = t.particle_body[i]
        x, R, _v, _w = body_motion(s, b)
        p = x + matvec(R, t.r0[i])
        touching = 0
        for j in ti.static(range(P)):
            plane = t.plane[j]
            near = plane[3] - ti.Vector([plane[0], plane[1], plane[2]]).dot(p) >= -2.0 * t.radius[b]
            t.near[s, i, j] = ti.cast(near, ti.u8)
            if near:
                t.pairs[s, ti.atomic_add(t.pair_count[s], 1)] = i * P + j
            if ti.static(materials):
                if plane[3] + t.radius[b] - ti.Vector([plane[0], plane[1], plane[2]]).dot(p) > 0:
                    touching += 1
        if ti.static(materials):
            t.count[s, b] += touching

    @ti.func
    def contacts(s, slot, dt):
        # The pair near in slot ``slot`` of step s: the plane's force on the particle's sphere into
        # fc[s], its spring at s + 1 (Tape.spring reads a spring as zero where the pair was not near).
        pair = t.pairs[s, slot]
        i, j = pair // P, pair % P
        b = t.particle_body[i]
        x, R, v, omega = body_motion(s, b)
        r = matvec(R, t.r0[i])
        p = x + r
        pv = v + omega.cross(r)
        g, k, radius, plane = t.g[None], t.k[None], t.radius[b], t.plane[j]
        if ti.static(materials):  # rigid.engine.material_stages.block_forces
            m_eff = t.M[b] / ti.max(t.count[s, b], 1)
            normal = ti.Vector([plane[0], plane[1], plane[2]])
            slip = t.spring(s, i, j)
            c, memory = plane_damping(pair_restitution(t.e_b[b], t.e_p[j]), k, m_eff, dt, -g.dot(normal),
                                      normal.dot(slip), normal.dot(pv), plane[3] + radius - normal.dot(p),
                                      t.table, 0, t.c_world[None], True)
            mu = pair_mu(t.mu_b[b], t.mu_p[j], t.mu_world[None])
            fc, new_slip, touching = plane_force_sticking(p, pv, radius, plane, k, c,
                                                          sticking_damping(k, m_eff, dt), mu, slip, dt)
            t.fc[s, i, j] = fc
            t.slip[s + 1, i, j] = new_slip + (memory * touching) * normal
        else:  # rigid.engine.stages._block_loop
            fc, _e = plane_force(p, pv, radius, plane, k, t.c_world[None], t.mu_world[None])
            t.fc[s, i, j] = fc

    @ti.func
    def forces(s, i):
        # Per particle: f = TODO 2 + the planes' forces in plane order, then TODO 3 and 4, then drag.
        b = t.particle_body[i]
        x, R, v, omega = body_motion(s, b)
        r0 = t.r0[i]
        r = matvec(R, r0)
        p = x + r
        f = u.gravity_force(t.m[b], t.g[None])
        for j in ti.static(range(P)):
            if t.near[s, i, j] != 0:
                f += t.fc[s, i, j]
        t.F[s, b] += u.total_force_term(f)
        t.T[s, b] += u.torque_term(p, x, R, r0, f)
        drag = -t.drag[b] * (v + omega.cross(r))  # rigid.engine.forces.particle_force, summed apart as add_external does
        t.F[s, b] += u.total_force_term(drag)
        t.T[s, b] += u.torque_term(p, x, R, r0, drag)

    @ti.func
    def update(s, b, dt):
        x, q, Pm, L, omega = t.x[s, b], t.q[s, b], t.P[s, b], t.L[s, b], t.w[s, b]
        F, tau, M, inv0 = t.F[s, b], t.T[s, b], t.M[b], t.I0inv[b]
        if ti.static(scheme == "symplectic"):  # rigid.engine.schemes.symplectic_update
            zero = ti.Vector.zero(float, 3)
            _x, P_new = u.update_linear(x, Pm, F, M, dt)
            L_new, _i, omega_mid = u.update_angular(L, tau, quaternion_to_matrix(q), inv0, dt)
            x_new, _P = u.update_linear(x, P_new, zero, M, dt)
            q_new = u.update_orientation(q, omega_mid, dt)
            L_same, _i2, omega_new = u.update_angular(L_new, zero, quaternion_to_matrix(q_new), inv0, 0.0)
            t.x[s + 1, b], t.q[s + 1, b], t.P[s + 1, b] = x_new, q_new, P_new
            t.L[s + 1, b], t.w[s + 1, b] = L_same, omega_new
        else:  # rigid.engine.schemes.euler_update
            x_new, P_new = u.update_linear(x, Pm, F, M, dt)
            q_new = u.update_orientation(q, omega, dt)
            L_new, _inv, omega_new = u.update_angular(L, tau, quaternion_to_matrix(q_new), inv0, dt)
            t.x[s + 1, b], t.q[s + 1, b], t.P[s + 1, b] = x_new, q_new, P_new
            t.L[s + 1, b], t.w[s + 1, b] = L_new, omega_new

    @ti.kernel
    def substep(s: ti.i32, n: ti.i32, nb: ti.i32, dt: float):
        # The four stages as four top-level loops of one kernel: one launch a substep (and one for
        # its adjoint, which runs the loops' adjoints in reverse order). Each loop writes only step
        # s + 1 or the atomic sums of step s that a later loop reads, never what it read itself.
        # (Taichi's reverse mode takes a kernel of loops only: the stages are each loop's body.)
        if ti.static(not _compiling_adjoint()):  # its outputs are integers: no adjoint
            ti.loop_config(serialize=serial)
            for i in range(n):
                reach(s, i)
        ti.loop_config(serialize=serial)
        for slot in range(t.pair_count[s]):
            contacts(s, slot, dt)
        ti.loop_config(serialize=serial)
        for i in range(n):
            forces(s, i)
        ti.loop_config(serialize=serial)
        for b in range(nb):
            update(s, b, dt)

    @ti.func
    def row(s, frame, b):
        t.r_x[frame, b], t.r_q[frame, b], t.r_P[frame, b] = t.x[s, b], t.q[s, b], t.P[s, b]
        t.r_L[frame, b], t.r_w[frame, b], t.r_v[frame, b] = t.L[s, b], t.w[s, b], t.P[s, b] / t.M[b]

    @ti.kernel
    def advance(s0: ti.i32, s1: ti.i32, n: ti.i32, nb: ti.i32, dt: float, first: ti.i32, substeps: ti.i32,
                write_rows: ti.i32):
        # Substeps s0 .. s1 - 1 in one launch: a serial loop over the time index whose body runs
        # the four stages as inner loops, then the row of step s + 1 where it ends a frame
        # (``first``: the run's step at local step 0). Its rows and tape equal substep's bit for
        # bit. Taichi 1.7's reverse mode turns a loop around only below the top level (hence the
        # one-pass outer loop) and keeps sibling loops in their written order, so the adjoint is
        # compiled from the stages written last to first (reach, whose adjoint is nothing, is
        # left out of it).
        ti.loop_config(serialize=True)
        for _once in range(1):
            for s in range(s0, s1):
                if ti.static(not _compiling_adjoint()):
                    for i in range(n):
                        reach(s, i)
                    for slot in range(t.pair_count[s]):
                        contacts(s, slot, dt)
                    for i in range(n):
                        forces(s, i)
                    for b in range(nb):
                        update(s, b, dt)
                if write_rows != 0 and (first + s + 1) % substeps == 0:
                    for b in range(nb):
                        row(s + 1, (first + s + 1) // substeps, b)
                if ti.static(_compiling_adjoint()):
                    for b in range(nb):
                        update(s, b, dt)
                    for i in range(n):
                        forces(s, i)
                    for slot in range(t.pair_count[s]):
                        contacts(s, slot, dt)

    @ti.kernel
    def rows(s: ti.i32, frame: ti.i32, nb: ti.i32):
        ti.loop_config(serialize=serial)
        for b in range(nb):
            row(s, frame, b)

    @ti.kernel
    def clear(end: ti.i32, nb: ti.i32, n: ti.i32, mode: ti.i32):
        """Zero, over steps 0 .. end and the particles in use (not the whole tape): mode 0 the
        atomic sums (F, T, count, pair_count) before a run, 1 the adjoints before a segment's backward (per
        body every step; the springs' at step 0 only, the one step whose adjoint no store
        consumes: each store's adjoint zeroes what it reads, Tape.clean), 2 I0 and the sticking
        springs of step 0 (a run's start)."""
        zero = ti.Vector.zero(float, 3)
        ti.loop_config(serialize=serial)
        for s, b in ti.ndrange(end + 1, nb):
            if mode == 0:
                t.F[s, b], t.T[s, b], t.count[s, b], t.pair_count[s] = zero, zero, 0, 0
            elif mode == 1:
                t.F.grad[s, b], t.T.grad[s, b], t.x.grad[s, b], t.P.grad[s, b] = zero, zero, zero, zero
                t.L.grad[s, b], t.w.grad[s, b], t.q.grad[s, b] = zero, zero, ti.Vector.zero(float, 4)
            elif mode == 2:
                t.I0[b] = ti.Matrix.zero(float, 3, 3)
        if ti.static(materials):
            ti.loop_config(serialize=serial)
            for i, j in ti.ndrange(n, P):
                if mode == 1:
                    t.slip.grad[0, i, j] = zero
                elif mode == 2:
                    t.slip[0, i, j] = zero

    from types import SimpleNamespace

    return SimpleNamespace(start=start, clear=clear, substep=substep, advance=advance, rows=rows)
