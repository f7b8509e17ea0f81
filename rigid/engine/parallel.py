"""The parallel path for large bodies: threads over blocks, a fixed-order sum, a graph per frame.

One substep is one kernel of two tasks:
  1. parallel over the blocks k (blocks.py): partial_F[k], partial_τ[k] = the
     block's wrench, summed serially over its particles (wrench.block_wrench);
  2. one thread, per body b: F = Σ_k partial_F[k] over b's blocks in block
     order (τ the same), then the scheme's update from (F, τ) (integrate.py).
Each partial is computed by the same code from the same inputs whichever thread
runs it, and the partials are summed in a fixed order, so the result does not
depend on the number of threads at all: runs are bit-reproducible, and they
differ from the serial path (the same sums in the same order, run by one
thread) only where the compiler vectorises the two kernels differently.

Only a kernel's top-level loops run in parallel, and a loop over substeps
around them would make them serial, so a frame cannot be one kernel launch
with a runtime number of substeps. Instead a frame of n substeps is a Taichi
compute graph (``ti.graph``) that dispatches the substep kernel n times and
then the particle write: one call from Python per frame, no Python work per
substep, the kernel compiled once (a ``ti.static`` unroll would compile n
copies), one graph cached per n. Waking the worker threads for each
substep's parallel task costs 15-70 µs on this project's 2-vCPU machine, which
is why all but the largest bodies take the serial path
(integrate.parallel_threshold). rk4 has no parallel path: its four wrench
evaluations per substep would need four such tasks.
"""
import taichi as ti

from .graphs import RepeatedGraphs


class ParallelFrame:
    def __init__(self, model, state, params, blocks, block_wrench, update, write_particles):
        """``block_wrench(k, b, x, R, v, ω)``: wrench.py;
        ``update(b, dt, F, τ)``: the scheme's update; ``write_particles()``: stores the particle
        and drawn-vertex positions (its loops run in parallel at a kernel's top level)."""
        s, prm, bl = state, params, blocks
        num_blocks, num_bodies = blocks.num_blocks, model.num_bodies
        self.partial_F = partial_F = ti.Vector.field(3, float, shape=num_blocks)
        self.partial_tau = partial_tau = ti.Vector.field(3, float, shape=num_blocks)

        @ti.kernel
        def substep():
            for k in range(num_blocks):  # parallel: one block per iteration
                b = bl.block_body[k]
                F, tau = block_wrench(k, b, s.x[b], s.R[b], s.P[b] / model.body_mass[b], s.omega[b])
                partial_F[k] = F
                partial_tau[k] = tau
            ti.loop_config(serialize=True)
            for b in range(num_bodies):  # one thread: fixed-order sum, then the update
                F = ti.Vector.zero(float, 3)
                tau = ti.Vector.zero(float, 3)
                first = bl.body_block_start[b]
                for k in range(first, first + bl.body_block_count[b]):
                    F += partial_F[k]
                    tau += partial_tau[k]
                update(b, prm.dt[None], F, tau)

        @ti.kernel
        def write():
            write_particles()

        self.substep, self.write = substep, write
        self._graphs = RepeatedGraphs(repeated=[(substep, False)], then=[(write, False)])

    def advance(self, substeps: int):
        """n substeps of every body, then the particle positions: one graph launch."""
        self._graphs.run(substeps)
