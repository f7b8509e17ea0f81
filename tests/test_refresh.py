"""Partial rebuilds of the neighbour lists (rigid.engine.refresh): the bodies that moved have their
lists made again, the rest keep theirs. The 27-sphere pile with a skin so thin that it is
outrun every few substeps: the run keeps the bits of one that always rebuilds in full, on both
schedules, and after refreshes every list holds exactly the pairs whose reference positions
(build_x) lie within reach + skin, as scipy's k-d tree finds them."""
import numpy as np
import pytest
from scipy.spatial import cKDTree

from conftest import ASSETS

PILE = dict(mesh=str(ASSETS / "sphere.obj"), count=27, scale=0.15, position=(0.0, -0.8, 0.0),
            particle_mass=0.01, velocity_damping_stiffness=12.0, friction_stiffness=0.4,
            integrator="symplectic", sleep=True)
THROWN = dict(PILE, initial_velocity=(1.5, 0.0, 1.0))  # thrown into the corner: many contacts, refreshes


def _thin_skin(monkeypatch):
    from rigid.engine import skin

    monkeypatch.setattr(skin, "SHRINK_ABOVE", 0.0)  # the skin halves after every frame, down to
    monkeypatch.setattr(skin, "MIN_FRACTION", 1e-2)  # a hundredth of a diameter


def _counts(sim):
    """(full builds, refreshes, bodies refreshed since the last full build)."""
    from rigid.engine.arrays import download

    from rigid.engine import broadphase

    flags = download(sim._scratch_arrays["broadphase_ints"])
    return int(flags[broadphase.BUILDS]), int(flags[broadphase.REFRESHES]), int(flags[broadphase.REFRESHED_BODIES])


@pytest.mark.parametrize("schedule", ["serial", "parallel"])
def test_refreshing_the_lists_keeps_the_bits_of_full_rebuilds(sim_cache, monkeypatch, schedule):
    from rigid.engine import refresh

    _thin_skin(monkeypatch)
    runs = []
    monkeypatch.setattr(refresh, "BUILD_COST", 1e3)  # a refresh always cheaper than a full build
    for fraction in (0.0, 1.0):  # never refresh (broadphase.MAX_REFRESHED, set with the skin), or always may
        monkeypatch.setattr(refresh, "REFRESH_FRACTION", fraction)
        sim = sim_cache(**PILE)
        sim.schedule = schedule
        for _ in range(80):  # the first bodies fall asleep at ~1.3 s
            sim.step_frame()
        runs.append(sim)
    (full, full_refreshes, _), (builds, refreshes, _) = _counts(runs[0]), _counts(runs[1])
    assert full_refreshes == 0 and refreshes > 100  # (each substep at most one)
    assert builds < full / 2
    assert 0 < runs[0].asleep().sum() < 27 and np.array_equal(runs[0].asleep(), runs[1].asleep())
    a, b = runs[0].snapshot(), runs[1].snapshot()
    for key in ("x", "q", "P", "L"):
        assert np.array_equal(a[key], b[key]), (key, np.abs(a[key] - b[key]).max())



def test_a_few_bodies_compile_no_refresh_and_keep_the_bits_of_refreshing(sim_cache, monkeypatch):
    """Below refresh.REFRESH_AT_LEAST bodies the kernels leave the refresh out (it is a quarter of
    their code to compile); the lists still hold every touching pair, so the run is the one that
    refreshes, bit for bit."""
    from rigid.engine import refresh

    _thin_skin(monkeypatch)
    monkeypatch.setattr(refresh, "BUILD_COST", 1e3)
    monkeypatch.setattr(refresh, "REFRESH_FRACTION", 1.0)
    few = dict(THROWN, count=8)
    runs = []
    for least in (refresh.REFRESH_AT_LEAST, 1):  # 8 bodies: without the refresh, then with it
        monkeypatch.setattr(refresh, "REFRESH_AT_LEAST", least)
        sim = sim_cache(**few)
        assert sim.kernels.split is None or (sim.kernels.split.refresh is not None) == (least == 1)
        for _ in range(40):
            sim.step_frame()
        runs.append(sim)
    assert _counts(runs[0])[1] == 0 and _counts(runs[1])[1] > 20
    a, b = runs[0].snapshot(), runs[1].snapshot()
    for key in ("x", "q", "P", "L"):
        assert np.array_equal(a[key], b[key]), (key, np.abs(a[key] - b[key]).max())

def _listed_pairs(sim) -> set:
    from rigid.engine.arrays import download

    count, lists = download(sim._scratch_arrays["nbr_count"]), download(sim._scratch_arrays["nbr_list"])
    stride = lists.shape[0] // count.shape[0]
    pairs = set()
    for i, n in enumerate(count):
        row = lists[i * stride:i * stride + n]
        assert n <= stride and np.all(np.diff(row) > 0), i  # in slot order, no repeats
        pairs.update((i, int(j)) for j in row)
    return pairs


def _near_at_references(sim, body, radius):
    """(pairs of other bodies' slots within reach + skin at their references, those at the edge)."""
    from rigid.engine import broadphase, broadphase_host
    from rigid.engine.arrays import download

    reference = download(sim._scratch_arrays["build_x"]).astype(np.float64)
    skin = broadphase_host.float_value(sim._scratch_arrays, broadphase.SKIN)
    near, doubtful = set(), set()
    for i, j in cKDTree(reference).query_pairs(2 * radius.max() + skin):
        if body[i] != body[j]:
            gap = np.linalg.norm(reference[i] - reference[j]) - (radius[i] + radius[j] + skin)
            if abs(gap) < 1e-5:  # float32 round-off at the edge: either way is right
                doubtful |= {(i, j), (j, i)}
            elif gap < 0:
                near |= {(i, j), (j, i)}
    return near, doubtful


@pytest.mark.parametrize("schedule", ["serial", "parallel"])  # parallel: the search side by side, apart
def test_after_refreshes_each_list_holds_exactly_the_pairs_near_at_their_references(sim_cache, monkeypatch, schedule):
    from rigid.engine import broadphase, broadphase_host
    from rigid.engine.arrays import download

    _thin_skin(monkeypatch)
    sim = sim_cache(**THROWN)
    sim.schedule = schedule
    model, B = sim.model, sim.num_bodies
    body = np.repeat(np.arange(B), model.body_count_np)  # slots run body after body
    radius = model.radius_np[body]
    both_refreshed = one_refreshed = 0
    while sim.frame < 150 and min(both_refreshed, one_refreshed) < 4:  # until near pairs of two refreshed
        sim.step_frame()  # bodies (each found the other) and of one (it entered itself in the other's list)
        refreshed = broadphase_host.body_ints(sim._scratch_arrays, broadphase.REFRESH_STATE) != 0
        near, doubtful = _near_at_references(sim, body, radius)
        both_refreshed = sum(1 for i, j in near if refreshed[body[i]] and refreshed[body[j]])
        one_refreshed = sum(1 for i, j in near if refreshed[body[i]] != refreshed[body[j]])
    assert both_refreshed >= 4 and one_refreshed >= 4, "no pairs of refreshed bodies to check"
    listed = _listed_pairs(sim)
    assert all((j, i) in listed for i, j in listed)  # symmetric
    assert near - listed == set()
    assert listed - near - doubtful == set()
    # and so every touching pair now is listed
    x = sim.particle_positions()[np.argsort(model.slot_of)]  # slot order
    touching = {(i, j) for i, j in cKDTree(x).query_pairs(2 * radius.max())
                if body[i] != body[j] and np.linalg.norm(x[i] - x[j]) < radius[i] + radius[j]}
    assert touching and touching <= listed
    active = broadphase_host.active_list(sim._scratch_arrays)
    count = download(sim._scratch_arrays["nbr_count"])
    assert np.array_equal(active, np.flatnonzero(count > 0))  # the pair stage visits exactly these


def test_a_full_build_replaces_refreshes_once_they_cost_more_and_no_bit_changes(sim_cache, monkeypatch):
    """refresh.BUILD_COST prices a full build in refreshed particles: priced low, the lists are rebuilt
    in full where a refresh would cost more than the substeps since did on average; the run keeps
    its bits either way."""
    from rigid.engine import refresh

    _thin_skin(monkeypatch)
    monkeypatch.setattr(refresh, "REFRESH_FRACTION", 1.0)  # the refreshed bodies' share never asks for one
    runs = []
    for cost in (1e3, 0.02):  # a build dearer than any refresh, or about one body's worth here
        monkeypatch.setattr(refresh, "BUILD_COST", cost)
        sim = sim_cache(**PILE)
        sim.schedule = "serial"
        for _ in range(40):
            sim.step_frame()
        runs.append(sim)
    (dear_builds, dear_refreshes, _), (cheap_builds, cheap_refreshes, _) = _counts(runs[0]), _counts(runs[1])
    assert cheap_builds > 10 * dear_builds and cheap_refreshes < 0.6 * dear_refreshes  # 233 > 7, 235 < 553
    a, b = runs[0].snapshot(), runs[1].snapshot()
    for key in ("x", "q", "P", "L"):
        assert np.array_equal(a[key], b[key]), (key, np.abs(a[key] - b[key]).max())
