"""Taichi 1.7's ad-stack overhang, alone: why ``advance``'s adjoint drifted (docs/gradients.md).

An ad-stack (a mutable local in a loop of a reverse-mode kernel) is sized to the most values it
holds, but allocated with a 4-byte header where the runtime uses 8: a full stack's top adjoint
overhangs into the next local on the native stack. The explicit Euler update (TODO 6 renormalises
q: a full stack) in a loop two levels below the top, as in the fused adjoint, gives gradients that
depend on what the native stack held; with spare entries (as rigid.diff.passes compiles them), exact ones.
"""
import sys
from pathlib import Path

import numpy as np
import taichi as ti

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

# advanced_optimization=False (the suite's quick compile): a frame layout where it hits a live local
ti.init(arch=ti.cpu, default_fp=ti.f64, offline_cache=False, log_level=ti.WARN, cfg_optimization=False,
        advanced_optimization=False)

from rigid.runtime import compile_settings  # noqa: E402
from rigid.engine.rotation import quaternion_to_matrix  # noqa: E402
from rigid.engine.units import default_units  # noqa: E402

u = default_units()
S, NB = 4, 1  # steps, bodies
vec = lambda n: ti.Vector.field(n, ti.f64, shape=(S + 1, NB), needs_grad=True)  # noqa: E731
x, P, L, w, F, T = (vec(3) for _ in range(6))
q = vec(4)
M = ti.field(ti.f64, shape=NB, needs_grad=True)
I0inv = ti.Matrix.field(3, 3, ti.f64, shape=NB, needs_grad=True)
junk = ti.field(ti.f64, shape=4096)


@ti.func
def update(s, b, dt):  # rigid.diff.kernels' explicit Euler update
    x_new, P_new = u.update_linear(x[s, b], P[s, b], F[s, b], M[b], dt)
    q_new = u.update_orientation(q[s, b], w[s, b], dt)
    L_new, _inv, w_new = u.update_angular(L[s, b], T[s, b], quaternion_to_matrix(q_new), I0inv[b], dt)
    x[s + 1, b], q[s + 1, b], P[s + 1, b], L[s + 1, b], w[s + 1, b] = x_new, q_new, P_new, L_new, w_new


def fused_kernel():
    @ti.kernel
    def fused(s0: ti.i32, s1: ti.i32, nb: ti.i32, dt: ti.f64):  # the time loop one level below the top
        ti.loop_config(serialize=True)
        for _once in range(1):
            for s in range(s0, s1):
                for b in range(nb):
                    update(s, b, dt)
    return fused


@ti.kernel
def one(s: ti.i32, nb: ti.i32, dt: ti.f64):  # top-level loops: the per-substep adjoint's shape
    for b in range(nb):
        update(s, b, dt)


@ti.kernel
def scribble(value: ti.f64):  # another kernel: leaves ``value`` in 512 doubles on the native stack
    ti.loop_config(serialize=True)
    for _once in range(1):
        v = ti.Vector.zero(ti.f64, 512)
        for i in range(4096):
            v[i % 512] = value + i
        for i in range(4096):
            junk[i] = v[(i * 7) % 512]


def adjoint(launch):
    for f in (x, P, L, w, F, T, q, M, I0inv):
        f.grad.fill(0)
    q.grad[S, 0], w.grad[S, 0], x.grad[S, 0] = (1.0, 2.0, 3.0, 4.0), (1.0, -1.0, 0.5), (1.0, -1.0, 0.5)
    launch()
    return np.concatenate([f.grad.to_numpy()[0].ravel() for f in (x, q, P, L, w)])


def main():
    rng = np.random.default_rng(0)
    M[0], I0inv[0] = 3.0, np.eye(3) * 2.0
    for f in (x, P, L, w, F, T):
        f.from_numpy(rng.normal(size=(S + 1, NB, 3)))
    q.from_numpy(np.tile(np.array([0.9, 0.1, 0.3, 0.2]) / np.linalg.norm([0.9, 0.1, 0.3, 0.2]), (S + 1, NB, 1)))
    dt = 1e-3
    _ = [one(s, NB, dt) for s in range(S)]
    reference = adjoint(lambda: [one.grad(s, NB, dt) for s in reversed(range(S))])
    for name, kernel, entries in (("sized by Taichi", fused_kernel(), 0), ("with spare entries", fused_kernel(), 8)):
        errors = []
        with compile_settings(ad_stack_size=entries):
            for value in (None, 1e100, -3.0):
                if value is not None:
                    scribble(value)
                errors.append(float(np.max(np.abs(adjoint(lambda: kernel.grad(0, S, NB, dt)) - reference))))
        print(f"fused adjoint, ad-stacks {name}: |error| fresh, after other kernels: {errors}")


if __name__ == "__main__":
    main()
