"""The pair stage in parts (rigid.engine.pair_parts) and Taichi's workers pinned (threads.py).

- Its bodies cut into 1, 2 or 3 parts in space (part_cut.py) and run part after part, the sweep
  gives every particle the one-thread sweep's (pair_once.sweep) force and couple on a pile in
  contact: to round-off (the terms come in another order, and fast math may contract the two
  places a pair is computed differently). A pair lost at the cut would take a whole contact
  force away, one counted twice would add one: the largest differences are held to 1e-5 of the
  largest force. The test checks that pairs do cross the cut, so the collecting of the terms
  from other parts is what it exercises, and that the cut gives the parts equal body counts
  along the widest axis (against numpy's ordering of the centres).
- The forces of every pair cancel: each part's sum is antisymmetric too.
- The parallel schedule's runs stay bit-reproducible with the parts, run after run.
- The workers found by the probe are pinned to different CPUs (where there are two).
"""
import os

import numpy as np
import pytest

from conftest import ASSETS

# Thrown into a corner: hundreds of particles touch another body's (dropped, the spheres touching at
# their mesh settle with a few dozen). Symplectic: the many-body kernels most of the group's tests use.
PILE = dict(mesh=str(ASSETS / "sphere.obj"), count=64, scale=0.1, position=(0.0, -0.8, 0.0), sleep=False,
            initial_velocity=(1.5, 0.0, 1.0), integrator="symplectic")
_KERNELS: dict = {}


def _kernels():
    import taichi as ti

    from rigid.engine import pair_once, pair_parts, part_cut
    from rigid.engine.arrays import ModelArgs, ScratchArgs, StateArgs, WorldArgs

    if not _KERNELS:
        M, S, W, C = ModelArgs(), StateArgs(), WorldArgs(), ScratchArgs()

        @ti.kernel
        def sweep(model: M, state: S, world: W, scratch: C):
            ti.loop_config(serialize=True)
            for _ in range(1):
                pair_once.sweep(model, state, world, scratch, False)

        @ti.kernel
        def parts(model: M, state: S, world: W, scratch: C, count: ti.i32):
            ti.loop_config(serialize=True)
            for _ in range(1):
                part_cut.cut_bodies(model, state, scratch, count)
            ti.loop_config(serialize=True)
            for part in range(count):
                pair_parts.sweep_part(model, state, world, scratch, part, False)

        _KERNELS.update(sweep=sweep, parts=parts)
    return _KERNELS


def _expected_parts(x: np.ndarray, weights: np.ndarray, parts: int) -> np.ndarray:
    """part_cut.cut_bodies' groups by numpy: the bodies in (coordinate on the widest axis, index)
    order; group k ends with the first body at which the running weight reaches (k + 1) / parts
    of the total, and holds at least that body."""
    B = len(x)
    axis = int(np.argmax(x.max(0) - x.min(0)))
    order = np.lexsort((np.arange(B), x[:, axis]))
    running = np.cumsum(weights[order])
    groups, first = np.full(B, parts - 1), 0
    for k in range(parts - 1):
        end = first
        if first < B:
            reached = np.flatnonzero(running[first:] >= running[-1] * (k + 1) / parts)
            end = first + (int(reached[0]) if len(reached) else B - 1 - first) + 1
        groups[order[first:end]] = k
        first = end
    return groups


def _forces(sim):
    from rigid.engine.arrays import download

    return download(sim._scratch_arrays["particle_f"]).copy(), download(sim._scratch_arrays["particle_couple"]).copy()


def test_parts_give_the_sweeps_forces(sim_cache):
    from rigid.engine import broadphase, part_cut
    from rigid.engine.arrays import download
    from rigid.engine.broadphase_host import body_ints

    sim = sim_cache(**PILE)
    sim.schedule = "serial"
    sim.advance_frames(40)  # the pile formed: a hundred particles and more touch another body's
    k = _kernels()
    args = (sim.model.args, sim.state.args, sim.params.args, sim.scratch)
    k["sweep"](*args)
    f0, c0 = _forces(sim)
    scale = np.abs(f0).max()
    assert scale > 0 and np.count_nonzero(np.abs(f0).sum(1)) > 100
    counts = download(sim._scratch_arrays["nbr_count"])
    lists = download(sim._scratch_arrays["nbr_list"]).reshape(len(counts), -1)
    N = sim.num_particles
    for parts in (1, 2, 3):
        touches = body_ints(sim._scratch_arrays, broadphase.TOUCHES)  # the last parts' counts (none at first)
        weights = sim.model.body_count_np + part_cut.TOUCH_WEIGHT * touches
        k["parts"](*args, parts)
        f, c = _forces(sim)
        assert np.abs(f - f0).max() <= 1e-5 * scale, (parts, np.abs(f - f0).max())
        assert np.abs(c - c0).max() <= 1e-5 * np.abs(c0).max(), parts
        assert np.abs(f.sum(0)).max() <= 1e-4 * scale  # every pair's two forces cancel
        part = body_ints(sim._scratch_arrays, broadphase.PART)
        assert np.array_equal(part, _expected_parts(sim.snapshot()["x"].astype(np.float32), weights, parts)), parts
        of = part[sim.particle_bodies()]
        listed = np.arange(lists.shape[1])[None, :] < np.minimum(counts, lists.shape[1])[:, None]
        crossing = int(np.sum(listed & (of[np.clip(lists, 0, N - 1)] != of[:, None])))
        assert parts == 1 or crossing > 0  # pairs across the cut: collect_from_other_parts is exercised


def test_parallel_runs_repeat_bit_for_bit(sim_cache):
    runs = []
    for _ in range(2):
        sim = sim_cache(**PILE)
        sim.schedule = "parallel"
        sim.advance_frames(30)
        runs.append(sim.snapshot())
    for key in ("x", "q", "P", "L"):
        assert np.array_equal(runs[0][key], runs[1][key]), key


def test_workers_pinned_to_different_cpus(sim_cache):
    import taichi as ti

    from rigid.engine import threads

    cpus = sorted(os.sched_getaffinity(0))
    if len(cpus) < 2 or ti.lang.impl.current_cfg().cpu_max_num_threads < 2:
        pytest.skip("one CPU: nothing to pin")
    sim = sim_cache(**PILE)
    sim.schedule = "parallel"
    sim.step_frame()  # the parallel launches pin the workers
    pinned = threads.pin_workers()  # once per process: the same answer again
    assert len(pinned) == ti.lang.impl.current_cfg().cpu_max_num_threads
    assert len(set(pinned)) == len(pinned) and set(pinned) <= set(cpus)
    single = [t for t in os.listdir("/proc/self/task") if len(os.sched_getaffinity(int(t))) == 1]
    assert len(single) >= len(pinned)


def _sleepers_and_drifters(sim_cache, sleep: bool):
    """test_sleep's free-space row (three spheres that fall asleep, a fourth arriving to wake them)
    and ten more spheres drifting together far above it, awake and apart: 3 of 14 bodies
    sleep, fewer than one in pair_parts.MANY_ASLEEP, so the parts run with sleepers."""
    from rigid.engine import pair_parts

    row = tuple(dict(position=(0.45 * k, 0.0, 0.0)) for k in range(3)) + (
        dict(position=(-1.2, 0.0, 0.0), initial_velocity=(1.0, 0.0, 0.0), initial_angular_velocity=(0.0, 0.0, 2.0)),)
    drifting = tuple(dict(position=(0.5 * k - 2.0, 3.0, 0.0), initial_velocity=(0.0, 0.0, 0.5)) for k in range(10))
    assert 3 * pair_parts.MANY_ASLEEP < len(row + drifting)
    sim = sim_cache(mesh=str(ASSETS / "sphere.obj"), scale=0.15, particle_mass=0.01, velocity_damping_stiffness=12.0,
                    friction_stiffness=0.4, integrator="symplectic", bodies=row + drifting, gravity=(0.0, 0.0, 0.0),
                    walls=False, sleep=sleep)
    sim.schedule = "parallel"
    return sim


def test_parts_with_a_few_sleepers_wake_them_and_keep_the_bits(sim_cache):
    on, off = _sleepers_and_drifters(sim_cache, True), _sleepers_and_drifters(sim_cache, False)
    start = on.snapshot()
    P0 = start["P"].sum(axis=0)
    slept = False
    for _ in range(120):
        on.step_frame()
        off.step_frame()
        slept |= bool(on.asleep()[:3].all())
    assert slept and not on.asleep()[3:].any(), "the row never slept, or a drifter did: the test would prove nothing"
    a, b = on.snapshot(), off.snapshot()
    assert not on.asleep()[0] and np.abs(a["v"][:3]).max() > 0.1, "the struck sphere stayed asleep"
    np.testing.assert_allclose(a["P"].sum(axis=0), P0, atol=1e-5 * np.abs(start["P"]).sum())
    for key in ("x", "q", "P", "L"):  # the sleepers were exactly at rest: the same bits either way
        assert np.array_equal(a[key], b[key]), key


@pytest.mark.parametrize("bodies", [1, 2, 3, 7, 64, 257])
def test_the_cut_follows_the_weights_in_order_along_the_widest_axis(ti_cpu, bodies):
    """part_cut.cut_bodies against numpy (_expected_parts): centres drawn on a coarse grid (many
    ties, broken by the body's index), the widest axis found, and the groups of the running
    weight (particles, touching particles), for 1 to 7 parts, with equal weights (then equal
    counts) and with unequal ones (Hoare's selection must leave each group's keys between the
    cuts, whatever the order it found them in)."""
    import taichi as ti

    from rigid.engine import broadphase, part_cut

    class Holder:  # the argument packs cut_bodies reads, as fields
        pass

    model, state, scratch = Holder(), Holder(), Holder()
    model.body_count = ti.field(ti.i32, shape=bodies)
    state.x = ti.Vector.field(3, float, shape=bodies)
    scratch.broadphase_body_floats = ti.field(float, shape=(bodies, broadphase.BODY_FLOATS))
    scratch.broadphase_body_ints = ti.field(ti.i32, shape=(broadphase.BODY_INTS, bodies + 1))

    @ti.kernel
    def cut(parts: ti.i32):
        ti.loop_config(serialize=True)
        for _ in range(1):
            part_cut.cut_bodies(model, state, scratch, parts)

    rng = np.random.default_rng(bodies)
    for trial in range(4):
        x = np.round(rng.normal(size=(bodies, 3)) * np.array([1.0, 3.0, 2.0])[np.roll(range(3), trial)], 1)
        x = x.astype(np.float32)
        counts = np.full(bodies, 42) if trial < 2 else rng.integers(1, 300, bodies)
        touches = np.zeros(bodies, np.int32) if trial % 2 == 0 else rng.integers(0, 40, bodies).astype(np.int32)
        state.x.from_numpy(x)
        model.body_count.from_numpy(counts.astype(np.int32))
        table = np.zeros((broadphase.BODY_INTS, bodies + 1), np.int32)
        table[broadphase.TOUCHES, :bodies] = touches
        weights = counts + part_cut.TOUCH_WEIGHT * touches
        for parts in range(1, 8):
            scratch.broadphase_body_ints.from_numpy(table)
            cut(parts)
            part = scratch.broadphase_body_ints.to_numpy()[broadphase.PART, :bodies]
            assert np.array_equal(part, _expected_parts(x, weights, parts)), (trial, parts)
            if trial == 0:  # equal weights: equal counts (to one)
                assert np.ptp(np.bincount(part, minlength=parts)) <= 1 or bodies < parts
