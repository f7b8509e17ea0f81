"""Quaternion to rotation matrix in float64 numpy (scalar first), for host-side poses.

The one numpy copy of the formula: ``rigid.engine.rotation`` re-exports it beside the
handout's ``ti.func`` twin, and placement uses it without importing scipy (slow to import at start-up).
"""
import numpy as np


def quaternion_to_matrix_np(q):
    w, x, y, z = np.asarray(q, dtype=np.float64) / np.linalg.norm(q)
    return np.array([[w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z]])
