"""Quaternion helpers, given to students in the handout (not TODOs).

Quaternions are scalar first: q = [s, vx, vy, vz]. Both helpers are pure
``ti.func``s; ``*_np`` twins in float64 numpy serve the tests and diagnostics.
"""
import numpy as np
import taichi as ti

from ..bodies.quaternion import quaternion_to_matrix_np  # noqa: F401 (the numpy twin)


@ti.func
def quaternion_multiplication(p, q):
    """Hamilton product p ⊗ q of two scalar-first quaternions (4-vectors)."""
    return ti.Vector([p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
                      p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
                      p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
                      p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0]])


@ti.func
def quaternion_to_matrix(q):
    """Rotation matrix R(q) of a unit quaternion (scalar first)."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    return ti.Matrix([[w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z]])


def quaternion_multiplication_np(p, q):
    p0, p1, p2, p3 = p
    q0, q1, q2, q3 = q
    return np.array([p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
                     p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
                     p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1,
                     p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0])


