"""Each TODO unit of the solution against numpy, on seeded random inputs.

Particle mass and Δt are far from 1 and 1e-3, so a missing factor cannot hide.
"""
import numpy as np
import taichi as ti

from rigid.engine.rotation import quaternion_multiplication_np, quaternion_to_matrix_np

K = 64  # random cases per unit
rng = np.random.default_rng(42)
MASS = rng.uniform(0.2, 3.0, K)
VEC_A = rng.normal(size=(K, 3))
VEC_B = rng.normal(size=(K, 3))
QUAT = rng.normal(size=(K, 4))
QUAT /= np.linalg.norm(QUAT, axis=1, keepdims=True)
DT = 0.0123


def _run(units, name, n_out_vec, *arrays):
    """Call unit ``name`` on every row of the input arrays inside one kernel."""
    unit = getattr(units, name)
    out = np.zeros((K, n_out_vec), np.float32)
    mats = [np.ascontiguousarray(a, np.float32) for a in arrays]

    @ti.kernel
    def k(m: ti.types.ndarray(), a: ti.types.ndarray(), b: ti.types.ndarray(), qa: ti.types.ndarray(),
          o: ti.types.ndarray(), width: ti.template()):
        for i in range(K):
            va = ti.Vector([a[i, 0], a[i, 1], a[i, 2]])
            vb = ti.Vector([b[i, 0], b[i, 1], b[i, 2]])
            qv = ti.Vector([qa[i, 0], qa[i, 1], qa[i, 2], qa[i, 3]])
            R = quaternion_to_matrix_ti(qv)
            res = ti.Vector.zero(float, 12)
            if ti.static(name == "particle_inertia"):
                res = flat(unit(m[i], va), 9)
            elif ti.static(name == "gravity_force"):
                res = flat(unit(m[i], va), 3)
            elif ti.static(name == "total_force_term"):
                res = flat(unit(va), 3)
            elif ti.static(name == "torque_term"):
                res = flat(unit(vb + R @ va, vb, R, va, va.cross(vb) + vb), 3)
            elif ti.static(name == "update_linear"):
                xn, pn = unit(va, vb, va + 2 * vb, m[i], DT)
                res = join(xn, pn)
            elif ti.static(name == "update_orientation"):
                res = flat(unit(qv, va, DT), 4)
            elif ti.static(name == "update_angular"):
                inv = ti.Matrix([[1 / m[i], 0.1, 0.0], [0.1, 2.0, 0.3], [0.0, 0.3, 0.5]])
                ln, ii, om = unit(va, vb, R, inv, DT)
                res = join(ln, om)
            for j in ti.static(range(width)):
                o[i, j] = res[j]

    k(mats[0], mats[1], mats[2], mats[3], out, n_out_vec)
    return out.astype(np.float64)


from rigid.engine.rotation import quaternion_to_matrix as quaternion_to_matrix_ti  # noqa: E402


@ti.func
def flat(value, n: ti.template()):
    res = ti.Vector.zero(float, 12)
    if ti.static(n == 9):
        for r, c in ti.static(ti.ndrange(3, 3)):
            res[r * 3 + c] = value[r, c]
    else:
        for j in ti.static(range(n)):
            res[j] = value[j]
    return res


@ti.func
def join(a, b):
    res = ti.Vector.zero(float, 12)
    for j in ti.static(range(3)):
        res[j] = a[j]
        res[3 + j] = b[j]
    return res


def call(units, name, width):
    return _run(units, name, width, MASS, VEC_A, VEC_B, QUAT)


def close(a, b, rtol=2e-5):
    np.testing.assert_allclose(a, b, rtol=rtol, atol=rtol * max(1.0, np.abs(b).max()))


def test_todo1_particle_inertia(units):
    expect = [m * (r @ r * np.eye(3) - np.outer(r, r)) for m, r in zip(MASS, VEC_A)]
    close(call(units, "particle_inertia", 9), np.reshape(expect, (K, 9)))


def test_todo2_gravity(units):
    close(call(units, "gravity_force", 3), MASS[:, None] * VEC_A)


def test_todo3_force_term(units):
    close(call(units, "total_force_term", 3), VEC_A)


def test_todo4_torque_about_centre_of_mass(units):
    R = np.array([quaternion_to_matrix_np(q) for q in QUAT])
    r = np.einsum("kij,kj->ki", R, VEC_A)
    close(call(units, "torque_term", 3), np.cross(r, np.cross(VEC_A, VEC_B) + VEC_B))


def test_todo5_explicit_euler_uses_old_momentum(units):
    force = VEC_A + 2 * VEC_B
    expect = np.hstack([VEC_A + DT * VEC_B / MASS[:, None], VEC_B + DT * force])
    close(call(units, "update_linear", 6), expect)


def test_todo6_quaternion_step_is_renormalised(units):
    out = call(units, "update_orientation", 4)
    expect = []
    for q, w in zip(QUAT, VEC_A):
        qn = q + DT * 0.5 * quaternion_multiplication_np(np.r_[0.0, w], q)
        expect.append(qn / np.linalg.norm(qn))
    close(out, np.array(expect))
    np.testing.assert_allclose(np.linalg.norm(out, axis=1), 1.0, atol=1e-6)


def test_todo7_angular_momentum_inertia_and_omega(units):
    out = call(units, "update_angular", 6)
    for i in range(K):
        R = quaternion_to_matrix_np(QUAT[i])
        inv = np.array([[1 / MASS[i], 0.1, 0.0], [0.1, 2.0, 0.3], [0.0, 0.3, 0.5]])
        L = VEC_A[i] + DT * VEC_B[i]
        close(out[i], np.r_[L, R @ inv @ R.T @ L], rtol=5e-5)

