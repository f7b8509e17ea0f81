"""Small vector algebra written out, for compile time.

Taichi builds ``M @ v``, ``a.dot(b)``, ``a.cross(b)``, ``a.norm()`` and ``ti.abs(v).max()``
through generic helpers (matrix_ops: shape checks, static loops, reductions) that its Python
front end transforms again at every call site, and every process transforms its kernels again
on start, warm cache or not. Written out, a call site is a few times smaller to transform (and
the kernel smaller for Taichi's passes, whose common-subexpression pass grows faster than the
kernel). The engine's own algebra uses these; the TODO units keep Taichi's operators, as
students write them. Same operations in the same order as Taichi's (sums in index order,
((a₀ + a₁) + a₂)), so the same bits.
"""
import taichi as ti


@ti.func
def matvec(M, a):
    """M a for a 3x3 matrix M and a 3-vector a."""
    return ti.Vector([M[0, 0] * a[0] + M[0, 1] * a[1] + M[0, 2] * a[2],
                      M[1, 0] * a[0] + M[1, 1] * a[1] + M[1, 2] * a[2],
                      M[2, 0] * a[0] + M[2, 1] * a[1] + M[2, 2] * a[2]])


@ti.func
def dot(a, b):
    """a · b for 3-vectors."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@ti.func
def cross(a, b):
    """a × b for 3-vectors."""
    return ti.Vector([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


@ti.func
def norm(a):
    """|a| for a 3-vector."""
    return ti.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@ti.func
def abs_max(a):
    """max |aᵢ| of a 3-vector."""
    return ti.max(ti.max(ti.abs(a[0]), ti.abs(a[1])), ti.abs(a[2]))


@ti.func
def body_offset(model: ti.template(), i):
    """r0 of particle slot i (body frame, from the centre of mass), from its three columns."""
    return ti.Vector([model.r0_x[i], model.r0_y[i], model.r0_z[i]])


ZERO3 = ti.Vector([0.0, 0.0, 0.0])  # (0, 0, 0) in the kernels' float type: a constant, no call to transform
