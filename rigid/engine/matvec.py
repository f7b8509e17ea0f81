"""Matrix-vector products written out, for compile time.

Taichi builds ``M @ v`` through a generic helper whose Python-side AST
transformation costs ~8 ms more per call site than the nine products written
out (measured: 10 call sites 0.115 s vs 0.034 s), and every Simulator
re-transforms its kernels. The engine's own products use these; the TODO units
keep ``@``, as students write it. Same arithmetic, same order: Σ_j M[i, j] a[j].
"""
import taichi as ti


@ti.func
def matvec(M, a):
    """M a for a 3x3 matrix M and a 3-vector a."""
    return ti.Vector([M[0, 0] * a[0] + M[0, 1] * a[1] + M[0, 2] * a[2],
                      M[1, 0] * a[0] + M[1, 1] * a[1] + M[1, 2] * a[2],
                      M[2, 0] * a[0] + M[2, 1] * a[1] + M[2, 2] * a[2]])


@ti.func
def body_offset(model: ti.template(), i):
    """r0 of particle slot i (body frame, from the centre of mass), from its three columns."""
    return ti.Vector([model.r0_x[i], model.r0_y[i], model.r0_z[i]])
