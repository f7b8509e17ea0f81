"""Where a many-body substep's time goes: each stage timed alone, on one thread.

    python scripts/bench_many.py --profile     # the 125-sphere pile and 1,000 spheres

The scene runs to a state of interest (mid-fall, 1 s), then each stage of the substep runs
``reps`` times in a one-thread kernel of its own on that state: placement (and the motion
test of the neighbour lists), a rebuild (grid and lists, forced), the pair stage, the blocks'
forces and shares, the body sums and update. The rebuild's cost per substep is its cost
times the measured rebuild rate (lists built per substep over the run so far). Taichi's
kernel profiler does not split a serial kernel into its stages, hence kernels of one stage
each. Times are medians over repeats, on a shared machine: reported, never asserted.
"""

import statistics
import time


def _kernels(units):
    import taichi as ti

    from ..engine import broadphase, find_pairs, force_loop, grid, neighbours, pair_once, pair_stages, schemes, stages
    from ..engine.arrays import ModelArgs, ScratchArgs, StateArgs, WorldArgs

    M, S, W, C = ModelArgs(), StateArgs(), WorldArgs(), ScratchArgs()
    u = units

    @ti.kernel
    def place(model: M, state: S, scratch: C, reps: ti.i32):
        ti.loop_config(serialize=True)
        for _ in range(reps):
            find_pairs.note_motion(model, state, scratch, False, False, False)
            pair_stages.place_for_pairs(model, state, scratch, True, False)  # as the serial schedule with sleeping

    @ti.kernel
    def rebuild(model: M, state: S, scratch: C, reps: ti.i32):
        ti.loop_config(serialize=True)
        for _ in range(reps):
            grid.clear_and_count(scratch, model, state, 1)
            grid.finish_serial(scratch, model, state, 1)
            broadphase.put(scratch, broadphase.ACTIVE, 0)
            for i in range(state.particle_x.shape[0]):
                neighbours.clear_list(scratch, i)
            for i in range(state.particle_x.shape[0]):
                neighbours.build_list(model, state, scratch, i)
            for i in range(state.particle_x.shape[0]):
                neighbours.finish_list(state, scratch, i, False)
            neighbours.index_active_by_body(model, state, scratch)

    @ti.kernel
    def grid_only(model: M, state: S, scratch: C, reps: ti.i32):
        ti.loop_config(serialize=True)
        for _ in range(reps):
            grid.clear_and_count(scratch, model, state, 1)
            grid.finish_serial(scratch, model, state, 1)

    @ti.kernel
    def pairs(model: M, state: S, world: W, scratch: C, reps: ti.i32):
        ti.loop_config(serialize=True)
        for _ in range(reps):  # as the serial schedule runs it (sleeping compiled in)
            if pair_once.any_asleep(state):
                pair_once.mark_woken(model, state, world, scratch)
            pair_once.sweep(model, state, world, scratch, True)

    @ti.kernel
    def blocks(model: M, state: S, world: W, scratch: C, reps: ti.i32):
        ti.loop_config(serialize=True)
        for _ in range(reps):
            for k in range(model.block_start.shape[0]):
                force_loop.block_forces(u, model, state, world, scratch, k, True, False, False, 0.0, True)

    @ti.kernel
    def update(model: M, state: S, world: W, scratch: C, reps: ti.i32):
        # Δt = 0: the same work, the state unchanged.
        ti.loop_config(serialize=True)
        for _ in range(reps):
            for b in range(state.x.shape[0]):
                F, tau = stages.body_wrench(model, scratch, b)
                schemes.symplectic_update(u, model, state, b, 0.0, F, tau)

    return dict(place=place, rebuild=rebuild, grid=grid_only, pairs=pairs, blocks=blocks, update=update)


_CACHE: dict = {}


def _timed(fn, args, reps: int) -> float:
    import taichi as ti
    fn(*args, 1)
    ti.sync()
    out = []
    for _ in range(5):
        start = time.perf_counter()
        fn(*args, reps)
        ti.sync()
        out.append((time.perf_counter() - start) / reps)
    return statistics.median(out) * 1e6


def profile(sim, settle_frames: int = 60, reps: int = 100) -> dict:
    """Stage times (µs per substep, one thread) of ``sim`` after ``settle_frames`` frames, and the
    whole substep as the engine runs it (its own schedule), for comparison."""
    import taichi as ti

    from ..engine.broadphase_host import refreshes_so_far

    key = id(sim.units)
    if key not in _CACHE:
        _CACHE[key] = _kernels(sim.units)
    k = _CACHE[key]
    builds0, refreshes0 = sim.neighbour_builds, refreshes_so_far(sim)
    if settle_frames:
        sim.advance_frames(settle_frames)
    rate = (sim.neighbour_builds - builds0) / max(1, settle_frames * sim.substeps)
    refresh_rate = (refreshes_so_far(sim) - refreshes0) / max(1, settle_frames * sim.substeps)
    whole = []
    for _ in range(3):
        start = time.perf_counter()
        sim.advance_frames(2)
        ti.sync()
        whole.append((time.perf_counter() - start) / (2 * sim.substeps))
    m, s, w, c = sim.model.args, sim.state.args, sim.params.args, sim.scratch
    stage = dict(place=_timed(k["place"], (m, s, c), reps), rebuild=_timed(k["rebuild"], (m, s, c), max(1, reps // 10)),
                 grid=_timed(k["grid"], (m, s, c), max(1, reps // 10)),
                 pairs=_timed(k["pairs"], (m, s, w, c), reps), blocks=_timed(k["blocks"], (m, s, w, c), reps),
                 update=_timed(k["update"], (m, s, w, c), reps))
    counts = sim.neighbour_counts()
    active = int((counts > 0).sum())
    per_substep = dict(stage, rebuild=stage["rebuild"] * rate)
    del per_substep["grid"]  # part of the rebuild
    return dict(bodies=sim.num_bodies, particles=sim.num_particles, schedule=sim.schedule,
                settle_frames=settle_frames, whole_us=round(statistics.median(whole) * 1e6, 1),
                rebuilds_per_substep=round(rate, 4), refreshes_per_substep=round(refresh_rate, 4),
                neighbours_mean=round(float(counts.mean()), 2),
                neighbours_max=int(counts.max()), active_particles=active, stage_us={n: round(v, 1) for n, v in stage.items()},
                per_substep_us={n: round(v, 1) for n, v in per_substep.items()},
                sum_us=round(sum(per_substep.values()), 1))


def piles(units, quick: bool) -> dict:
    """The stage profile (``profile``) of the peers' 125 and 1,000 sphere piles at 1 s (27 for a smoke run)."""
    from rigid.engine.simulator import Simulator

    from .peers import scene
    out = {}
    for count in ((27,) if quick else (125, 1000)):
        config, bodies = scene(count)
        sim = Simulator(config.replace(sleep=False), units, bodies=bodies, schedule="serial")
        out[f"{count} spheres"] = profile(sim, settle_frames=6 if quick else 60, reps=5 if quick else 100)
        print(f"  {count} spheres: {out[f'{count} spheres']['per_substep_us']}", flush=True)
    return out
