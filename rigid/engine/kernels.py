"""The engine's kernels, compiled once per process for a set of TODO units and a scheme.

Every kernel takes the data it works on as argument packs (arrays.py), so any number of
Simulators, of any scenes and sizes, share one compiled copy: ``engine_kernels(units,
scheme)`` builds them on first use and caches them (Taichi's offline cache keeps the machine
code between processes). Only code is captured: the TODO units and the scheme's name.

Two schedules run the same substep (substep.py: ``place``, then ``step``), chosen by schedule.py:
- serial: ``run_frames`` runs a chunk of frames (every substep of every frame, then the
  frame's row) as one launch on one thread: no thread wake-ups, no per-frame host work;
- parallel: ``substep`` runs one substep with each stage a top-level (parallel) loop (on a
  CPU, in parts that pass over the rebuild: split_substep.py), and ``finish_frame`` places
  the particles and writes the frame's row; the host launches them.
"""

import taichi as ti

from ..runtime import CSE_OFF, SettingsKernel
from . import schemes, sleep, split_substep, stages, substep
from .arrays import ModelArgs, RowArgs, ScratchArgs, StateArgs, SurfaceArgs, WorldArgs
from .matvec import body_offset, matvec
from .rows import write_row
from .state import DT

_CACHE: dict = {}
_COMPACT = [False]  # compact_block_loops()


def compact_block_loops(on: bool = True) -> None:
    """From now on in this process, compile one loop over a block's particles that tests every
    plane, not four chosen per block by the planes in reach: the same forces, ~17 % less to
    compile for a lone body, slower for big bodies near no wall. For processes that compile much
    and run little: the grader's children and --check (rigid.grading.checks)."""
    _COMPACT[0] = bool(on)


def engine_kernels(units, scheme: str, pairs: bool, materials: bool = False, refreshing: bool = True) -> "EngineKernels":
    """The kernels for ``units`` (an object with the 7 TODO ``ti.func``s), ``scheme`` ("euler",
    "symplectic", "rk4") and whether bodies collide with one another (``pairs``: the grid and
    pair stages are compiled only for scenes that need them, which halves a lone body's
    compile time), whether the scene sets materials or static colliders (``materials``:
    material_stages.py's force stages) and whether the lists may be refreshed in part
    (``refreshing``: refresh.worth_refreshing), compiled on first use in this process."""
    refreshing = bool(refreshing and pairs and not materials)
    key = (id(units), scheme, bool(pairs), bool(materials), _COMPACT[0], refreshing)
    entry = _CACHE.get(key)
    if entry is None or entry.units is not units:
        entry = _CACHE[key] = EngineKernels(units, scheme, bool(pairs), bool(materials), _COMPACT[0], refreshing)
    return entry


class EngineKernels:
    def __init__(self, units, scheme: str, pairs: bool, materials: bool = False, compact: bool = False,
                 refreshing: bool = True):
        self.units, self.scheme, self.pairs, self.materials, self.compact = units, scheme, pairs, materials, compact
        u = units
        plan = substep.make_plan(units, scheme, pairs, materials, compact, refreshing)
        M, S, W, C, Rw, Sf = ModelArgs(), StateArgs(), WorldArgs(), ScratchArgs(), RowArgs(), SurfaceArgs()
        rk4 = plan.rk4

        @ti.func
        def parallel_substep(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template()):
            """One substep of every body, for the parallel schedule: each loop at the kernel's top
            level is one parallel task (the tasks run in order), so RK4's stages are unrolled."""
            dt = world.values[DT]
            if ti.static(rk4):
                for b in range(state.x.shape[0]):
                    schemes.rk4_begin(state, scratch, b)
            for stage in ti.static(range(4 if rk4 else 1)):
                if ti.static(pairs):
                    substep.place(plan, model, state, scratch, True, 0)
                weight = ti.static(schemes.RK4_WEIGHTS[stage] / 6.0 if rk4 else 1.0)
                substep.step(plan, model, state, world, scratch, True, dt, stage, weight)
            if ti.static(rk4):
                for b in range(state.x.shape[0]):
                    substep.rk4_finish(plan, model, state, scratch, b, dt)

        @ti.func
        def serial_frame(model: ti.template(), state: ti.template(), world: ti.template(), scratch: ti.template(),
                         substeps):
            """One frame on one thread: its force evaluations (one per substep, four with RK4) as
            one loop, whose extra last turn only places the particles for the frame's row. So
            placement and the neighbour-list rebuild, and the force stages, are compiled once
            (two copies of each made the kernel twice as slow to compile)."""
            dt = world.values[DT]
            per_step = 4 if ti.static(rk4) else 1
            last = substeps * per_step
            for e in range(last + 1):
                if ti.static(pairs):
                    substep.place(plan, model, state, scratch, False, e == last)
                if e < last:
                    stage = e % per_step
                    if ti.static(rk4):
                        if stage == 0:
                            for b in range(state.x.shape[0]):
                                schemes.rk4_begin(state, scratch, b)
                        substep.step(plan, model, state, world, scratch, False, dt, stage,
                                     schemes.rk4_weight(stage) / 6.0)
                        if stage == 3:
                            for b in range(state.x.shape[0]):
                                substep.rk4_finish(plan, model, state, scratch, b, dt)
                    else:
                        substep.step(plan, model, state, world, scratch, False, dt, stage, 1.0)
            if ti.static(not pairs):
                stages.place_particles(model, state)

        @ti.kernel
        def run_frames(model: M, state: S, world: W, scratch: C, rows: Rw, frames: ti.i32, substeps: ti.i32):
            # One thread: ``frames`` frames of ``substeps`` substeps, a row after each frame.
            ti.loop_config(serialize=True)
            for frame in range(frames):
                serial_frame(model, state, world, scratch, substeps)
                for w in range(rows.contact_energy.shape[1]):
                    rows.contact_energy[frame, w] = stages.world_contact_energy(model, state, world, scratch, w, pairs)
                write_row(state, rows, frame)

        @ti.kernel
        def one_substep(model: M, state: S, world: W, scratch: C):
            parallel_substep(model, state, world, scratch)

        @ti.kernel
        def finish_frame(model: M, state: S, world: W, scratch: C, rows: Rw, slot: ti.i32):
            substep.place(plan, model, state, scratch, True, 1)
            for k in range(model.block_start.shape[0]):  # the blocks in parallel, summed in order below
                scratch.block_energy[k] = stages.block_contact_energy(model, state, world, scratch, k, pairs)
            worlds = rows.contact_energy.shape[1]
            stages.sum_energy_chunks(model, scratch, worlds)  # (off a CPU)
            for w in range(worlds):  # each world's on a thread of its own
                rows.contact_energy[slot, w] = stages.world_energy_total(model, scratch, w, worlds)
            write_row(state, rows, slot)

        @ti.kernel
        def init_bodies(model: M, state: S, x0: ti.types.ndarray(), q0: ti.types.ndarray(),
                        v0: ti.types.ndarray(), w0: ti.types.ndarray()):
            for b in range(state.x.shape[0]):
                schemes.init_body(u, model, state, b, ti.Vector([x0[b, 0], x0[b, 1], x0[b, 2]], float),
                                  ti.Vector([q0[b, 0], q0[b, 1], q0[b, 2], q0[b, 3]], float),
                                  ti.Vector([v0[b, 0], v0[b, 1], v0[b, 2]], float),
                                  ti.Vector([w0[b, 0], w0[b, 1], w0[b, 2]], float))
            stages.place_particles(model, state)

        @ti.kernel
        def apply_impulse(model: M, state: S, i: ti.i32, J: ti.types.vector(3, float)):
            ti.loop_config(serialize=True)
            for _ in range(1):
                schemes.impulse(u, model, state, i, J)
                sleep.wake(state, model.particle_body[i])
            stages.place_particles(model, state)

        @ti.kernel
        def sum_inertia(model: M):
            # I0 = Σ TODO 1 (m, r0ᵢ) per body, summed in slot order by one thread.
            ti.loop_config(serialize=True)
            for b in range(model.body_start.shape[0]):
                total = ti.Matrix.zero(float, 3, 3)
                for i in range(model.body_start[b], model.body_start[b] + model.body_count[b]):
                    total += u.particle_inertia(model.particle_mass[b], body_offset(model, i))
                model.inertia_body[b] = total

        @ti.kernel
        def place_surfaces(state: S, surface: Sf, out: ti.types.ndarray()):
            # The drawn meshes' vertices in the world, (V, 3), from the bodies' state.
            for k in range(out.shape[0]):
                b = surface.surface_body[k]
                p = state.x[b] + matvec(state.R[b], surface.surface_r0[k])
                for c in ti.static(range(3)):
                    out[k, c] = p[c]

        self.place_surfaces = place_surfaces
        # The parallel substep in parts the host launches, passing over the rebuild (split_substep.py).
        self.split = split_substep.make(plan) if pairs and not rk4 else None
        # The frame on one thread: the largest kernel, compiled without the whole-kernel CSE pass.
        self.run_frames = SettingsKernel(run_frames, CSE_OFF)
        self.substep, self.finish_frame = one_substep, finish_frame
        self.init_bodies, self.apply_impulse, self.sum_inertia = init_bodies, apply_impulse, sum_inertia
