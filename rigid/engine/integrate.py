"""The substep, built from the 7 TODO units, and the kernels that run whole frames.

``Integrator(model, state, params, units, scheme)`` compiles kernels that call
the TODO units (``units`` is any object with the 7 ``ti.func``s, e.g. the
module ``rigid_body_dynamic``); the engine never imports that module itself.

One substep, as on the slides (explicit Euler, scheme "euler"):
  for each particle i:  rᵢ = R r0ᵢ, pᵢ = x + rᵢ, vᵢ = v + ω × rᵢ
                        fᵢ = m g (TODO 2) + contact(pᵢ, vᵢ)
                        F += fᵢ (TODO 3),  τ += rᵢ × fᵢ (TODO 4)
  x, P ← x + Δt P/M, P + Δt F            (TODO 5, old P)
  q    ← normalise(q + Δt ½ [0, ω] ⊗ q)   (TODO 6, old ω)
  R    ← R(q)
  L, I⁻¹, ω ← L + Δt τ, R I0⁻¹ Rᵀ, I⁻¹ L  (TODO 7, new R)
Particle positions are never stored per substep: the force loop computes them
from (x, R), and ``write_particles`` stores them once per frame.

"symplectic" (semi-implicit Euler) updates P and L first, then moves x and q
with the new v and ω; it reuses the same units. "rk4" lives in rk4.py.

Two paths run a frame (``advance``), chosen by particle count; ``advance_recorded``
runs frames in chunks, each frame followed by its row (frame_rows.py):
- serial (``advance_serial``): one launch, one thread, every substep of every
  body; the particle sum runs block by block (wrench.py, blocks.py); launched
  through a one-kernel ``ti.graph`` (1/6 of a Python kernel call's overhead);
- parallel (parallel.py), for bodies of ``parallel_threshold()`` particles or
  more (euler and symplectic; rk4 always runs serial): threads over blocks,
  partial sums added in a fixed order, one compute-graph launch per frame.
"""
import os

import taichi as ti

from .blocks import ParticleBlocks
from .frame_rows import ChunkGraphs, FrameRows, make_record_kernel
from .graphs import RepeatedGraphs
from .matvec import matvec
from .updates import make_updates
from .wrench import make_wrench

# The parallel path pays only for very large bodies on a CPU. Measured on this project's 2-vCPU
# machine (scripts/bench.py, "crossover"): waking the worker threads for each substep's parallel
# task costs 15-70 µs, and the particle loop of a body in flight is memory-bound (~0.7 ns per
# particle on one core), so two threads only break even near a million particles (faster in
# contact, slower in flight, by 10-30% either way). The threshold is that break-even for two
# threads, assumed to fall as 1/threads with more (not measured: no such machine here).
# RIGID_PARALLEL_MIN_PARTICLES overrides it.
PARALLEL_MIN_PARTICLES_TWO_THREADS = 1 << 20  # 1,048,576
# On a GPU the serial path runs on one GPU thread, so the parallel path is taken much earlier
# (a guess: no GPU was available to measure it).
PARALLEL_MIN_PARTICLES_GPU = 4096
PARALLEL_SCHEMES = ("euler", "symplectic")


def parallel_threshold() -> int:
    """Particles from which ``advance`` takes the parallel path on the current Taichi arch."""
    override = os.environ.get("RIGID_PARALLEL_MIN_PARTICLES")
    if override:
        return int(override)
    cfg = ti.lang.impl.current_cfg()
    if cfg.arch not in (ti.x64, ti.arm64):
        return PARALLEL_MIN_PARTICLES_GPU
    threads = cfg.cpu_max_num_threads
    return PARALLEL_MIN_PARTICLES_TWO_THREADS * 2 // threads if threads >= 2 else 1 << 62


class Integrator:
    def __init__(self, model, state, params, units, scheme: str = "euler", parallel=None, rows=None):
        """``parallel``: None chooses by particle count, True/False force a path (where the scheme has it);
        ``rows``: the FrameRows that ``advance_recorded`` writes (made here if None)."""
        self.model, self.state, self.params, self.scheme = model, state, params, scheme
        self.rows = FrameRows(model.num_bodies) if rows is None else rows
        self.blocks = ParticleBlocks(model)
        self.parallel = parallel
        self.largest_body = int(model.body_count.to_numpy().max())  # particles
        self.threshold = parallel_threshold()
        self._parallel_frame = None
        self._build(units)

    def _build(self, u):
        model, s, prm = self.model, self.state, self.params
        num_bodies = model.num_bodies
        scheme = self.scheme

        # Forces per particle through the TODO units, summed block by block (wrench.py).
        particle_force, _reach, _block_wrench, body_wrench = make_wrench(model, prm, self.blocks, u)

        store, euler_update, symplectic_update, init_body, impulse = make_updates(model, s, u)

        update = symplectic_update if scheme == "symplectic" else euler_update

        @ti.func
        def substep_one_step(b, dt):
            F, tau = body_wrench(b, s.x[b], s.R[b], s.P[b] / model.body_mass[b], s.omega[b])
            update(b, dt, F, tau)

        substep = substep_one_step
        if scheme == "rk4":
            from .rk4 import make_rk4_substep

            substep = make_rk4_substep(model, s, body_wrench, store, u)

        @ti.func
        def write_particles_serial():
            # Body by body, so that (x, R, v, ω) are loaded once and LLVM vectorises the loops.
            for b in range(num_bodies):
                x, R, v, omega = s.x[b], s.R[b], s.v[b], s.omega[b]
                start = model.body_start[b]
                for i in range(start, start + model.body_count[b]):
                    r = matvec(R, model.r0[i])
                    s.particle_x[i] = x + r
                    s.particle_v[i] = v + omega.cross(r)
            x0, R0 = s.x[0], s.R[0]
            for k in range(model.num_surface):
                s.surface_x[k] = x0 + matvec(R0, model.surface_r0[k])

        @ti.func
        def write_particles_parallel():
            # At a kernel's top level both loops run in parallel (parallel.py, after a frame).
            for i in range(model.num_particles):
                b = model.particle_body[i]
                r = matvec(s.R[b], model.r0[i])
                s.particle_x[i] = s.x[b] + r
                s.particle_v[i] = s.v[b] + s.omega[b].cross(r)
            for k in range(model.num_surface):
                s.surface_x[k] = s.x[0] + matvec(s.R[0], model.surface_r0[k])

        @ti.kernel
        def advance_serial(n: ti.i32):
            # One launch, one thread: n substeps of every body, then the particles once.
            ti.loop_config(serialize=True)
            for _ in range(1):
                dt = prm.dt[None]
                for _step in range(n):
                    for b in range(num_bodies):
                        substep(b, dt)
                write_particles_serial()

        @ti.kernel
        def init_state(x0: ti.types.vector(3, float), q0: ti.types.vector(4, float),
                       v0: ti.types.vector(3, float), w0: ti.types.vector(3, float)):
            ti.loop_config(serialize=True)
            for b in range(num_bodies):
                init_body(b, x0, q0, v0, w0)
            write_particles_serial()

        @ti.func
        def particle_energy(i):
            # Elastic energy ½ k depth² stored in particle i's contact springs.
            _f, e = particle_force(model.particle_body[i], s.particle_x[i], s.particle_v[i])
            return e

        @ti.kernel
        def apply_impulse(i: ti.i32, J: ti.types.vector(3, float)):
            ti.loop_config(serialize=True)
            for _ in range(1):
                impulse(i, J)  # updates.py
            write_particles_serial()

        self.advance_serial = advance_serial
        self._parallel_parts = (_block_wrench, update, write_particles_parallel)
        self.init_state = init_state
        self.apply_impulse = apply_impulse
        gpu = ti.lang.impl.current_cfg().arch not in (ti.x64, ti.arm64)
        self.record = make_record_kernel(self.rows, s, model.num_particles, particle_energy, parallel_energy=gpu)
        self.particle_energy = particle_energy  # ti.func of a particle index (tests build the GPU variant)
        self._chunks = ChunkGraphs(advance_serial, self.record)
        self._serial_frame = RepeatedGraphs(repeated=[(advance_serial, True)])

    @property
    def uses_parallel(self) -> bool:
        """Whether ``advance`` takes the parallel path (see the module docstring)."""
        if self.scheme not in PARALLEL_SCHEMES:
            return False
        if self.parallel is not None:
            return bool(self.parallel)
        return self.largest_body >= self.threshold

    def advance_recorded(self, substeps: int, frames: int):
        """``frames`` frames (at most ``self.rows.capacity``), each followed by its row, from row 0."""
        self.rows.rewind()
        if self.uses_parallel:
            for _ in range(frames):  # a frame on this path takes milliseconds
                self.advance(substeps)
                self.record()
        else:
            self._chunks.run(substeps, frames)

    def advance(self, substeps: int):
        """Advance every body by ``substeps`` substeps: one launch (serial) or one graph (parallel)."""
        if self.uses_parallel:
            if self._parallel_frame is None:
                from .parallel import ParallelFrame

                self._parallel_frame = ParallelFrame(self.model, self.state, self.params, self.blocks,
                                                     *self._parallel_parts)
            self._parallel_frame.advance(substeps)
        else:
            self._serial_frame.run(1, n=substeps)  # a one-kernel graph: ~2 µs to launch, a call ~12 µs
