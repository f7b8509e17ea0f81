"""The neighbour lists (rigid.engine.neighbours) hold every overlapping pair of particles of
different bodies, checked against a k-d tree of the particles (scipy), frame after frame of a
falling pile: the lists are reused across substeps, so this tests the rebuild rule too."""
import numpy as np
import pytest
from scipy.spatial import cKDTree

from conftest import ASSETS


@pytest.mark.parametrize("schedule", ["serial", "parallel"])
def test_every_touching_pair_is_in_the_lists(sim_cache, schedule):
    """... on both schedules; and the active list (the slots the pair stage visits) is exactly
    the slots with a candidate, ascending (the parallel build writes it by chunks)."""
    from rigid.engine.broadphase_host import active_list

    sim = sim_cache(mesh=str(ASSETS / "sphere.obj"), count=27, scale=0.15, position=(0.0, -0.8, 0.0),
                    particle_mass=0.01, velocity_damping_stiffness=12.0, friction_stiffness=0.4,
                    integrator="symplectic", sleep=False, initial_velocity=(1.5, 0.0, 1.0))  # thrown: many contacts
    sim.schedule = schedule
    radius = sim.model.radius_np[sim.particle_bodies()]
    body = sim.particle_bodies()
    slot = sim.model.slot_of
    stride = sim._scratch_arrays["nbr_list"].shape[0] // sim.num_particles
    touching_total, builds0 = 0, sim.neighbour_builds
    for frame in range(40):
        sim.advance_frames(3)
        stride = sim._scratch_arrays["nbr_list"].shape[0] // sim.num_particles  # (they may grow)
        p = sim.particle_positions()
        pairs = cKDTree(p).query_pairs(2 * radius.max(), output_type="ndarray")
        d = np.linalg.norm(p[pairs[:, 0]] - p[pairs[:, 1]], axis=1)
        keep = (body[pairs[:, 0]] != body[pairs[:, 1]]) & (d < radius[pairs[:, 0]] + radius[pairs[:, 1]])
        counts = sim.neighbour_counts()
        lists = sim._scratch_arrays["nbr_list"].to_numpy().reshape(sim.num_particles, stride)
        active = active_list(sim._scratch_arrays)
        assert np.array_equal(active, np.flatnonzero(counts > 0)), frame
        for i, j in pairs[keep]:
            for a, b in ((i, j), (j, i)):
                n = counts[slot[a]]
                assert n > stride or slot[b] in lists[slot[a], :n], (frame, a, b)
        touching_total += int(keep.sum())
    assert touching_total > 100, "the spheres barely touched: the test would prove nothing"
    builds = sim.neighbour_builds - builds0
    assert 0 < builds < 40 * 3 * sim.substeps, "the lists were rebuilt every substep (or never)"


def test_the_turn_bound_holds_for_any_matrix_and_is_sqrt2_tighter_for_rotations(sim_cache):
    """_turn_norm(R, R0) bounds the spectral norm of R − R0 (numpy's SVD), the most a unit
    offset moves: for rotations (where it is ‖R − R0‖_F / √2 up to round-off), for rotations
    off by round-off, and for arbitrary matrices (where it falls back to ‖R − R0‖_F); and
    1 + motion._defect(R) bounds ‖R‖₂, the most R stretches an offset (note_motion's reach of a body)."""
    import taichi as ti
    from scipy.spatial.transform import Rotation

    from rigid.engine import motion

    sim_cache(count=2, sleep=False)  # a Taichi runtime, in float32 as the engine runs

    @ti.kernel
    def bound(R: ti.types.ndarray(), R0: ti.types.ndarray(), out: ti.types.ndarray(), stretch: ti.types.ndarray()):
        for n in range(out.shape[0]):
            a = ti.Matrix.zero(float, 3, 3)
            b = ti.Matrix.zero(float, 3, 3)
            for r, c in ti.static(ti.ndrange(3, 3)):
                a[r, c] = R[n, r, c]
                b[r, c] = R0[n, r, c]
            out[n] = motion._turn_norm(a, b)
            stretch[n] = 1.0 + motion._defect(a)

    rng = np.random.default_rng(1)
    n = 400
    base = Rotation.random(n, random_state=2).as_matrix()
    small = Rotation.from_rotvec(rng.normal(size=(n, 3)) * rng.uniform(1e-3, 0.3, size=(n, 1))).as_matrix()
    cases = {"rotations": (small @ base, base),
             "rotations off by 1e-5": (small @ base + 1e-5 * rng.normal(size=(n, 3, 3)), base),
             "any matrices": (rng.normal(size=(n, 3, 3)), rng.normal(size=(n, 3, 3))),
             "a reflection": (base * np.array([1.0, 1.0, -1.0]), base)}
    for name, (R, R0) in cases.items():
        out, stretch = np.zeros(n, np.float32), np.zeros(n, np.float32)
        bound(R.astype(np.float32), R0.astype(np.float32), out, stretch)
        assert np.all(stretch >= np.linalg.norm(R, ord=2, axis=(1, 2)) * (1 - 1e-5)), name
        spectral = np.linalg.norm(R - R0, ord=2, axis=(1, 2))
        frob = np.linalg.norm(R - R0, axis=(1, 2))
        assert np.all(out >= spectral * (1 - 1e-5) - 1e-6), name
        assert np.all(out <= frob * (1 + 1e-5) + 1e-6), name
        if name == "rotations":
            np.testing.assert_allclose(out, frob / np.sqrt(2), rtol=2e-3, atol=1e-5)


def test_bodies_far_apart_rebuild_nothing_and_still_meet(sim_cache):
    """The rebuild rule looks only at pairs of bodies near enough to touch (close_pairs_moved):
    a sphere flying at another from afar moves many skins relative to it without a rebuild
    while their bounding spheres are apart, then the lists are rebuilt as they close and the
    head-on collision exchanges their velocities (equal masses, elastic enough: the spring
    law's restitution is well above 0)."""
    from rigid.engine import broadphase, broadphase_host

    sphere = str(ASSETS / "sphere.obj")
    sim = sim_cache(bodies=(dict(mesh=sphere, scale=0.15, position=(-0.7, 0.0, 0.0), initial_velocity=(3.0, 0.0, 0.0)),
                            dict(mesh=sphere, scale=0.15, position=(0.7, 0.0, 0.0))),
                    gravity=(0.0, 0.0, 0.0), particle_mass=0.01, velocity_damping_stiffness=1.0, friction_stiffness=0.0,
                    integrator="symplectic", sleep=False)
    skin = broadphase_host.float_value(sim._scratch_arrays, broadphase.SKIN)
    rho = np.linalg.norm(sim.model.r0_np, axis=1).max()
    reach = 2 * rho + 2 * sim.model.radius_np.max()
    sim.step_frame()
    builds0, x0 = sim.neighbour_builds, sim.snapshot()["x"]
    frames = 0
    while np.linalg.norm(np.diff(sim.snapshot()["x"], axis=0)) > reach + 0.1:
        sim.step_frame()
        frames += 1
    moved = np.linalg.norm((sim.snapshot()["x"] - x0)[0])
    assert moved > 20 * skin, "the sphere did not move far relative to the skin: the test would prove nothing"
    assert sim.neighbour_builds == builds0, "bodies far apart rebuilt the lists"
    sim.advance_frames(4)  # the collision (the second sphere reaches the wall 6 frames later)
    v = sim.snapshot()["v"]
    assert sim.neighbour_builds > builds0
    assert v[0, 0] < 0.3 and v[1, 0] > 2.0, v  # the first stopped (nearly), the second flies off


def test_a_particle_whose_list_overflows_loses_no_contact(sim_cache, monkeypatch):
    """A particle with more candidates than its list holds keeps only their count and walks the
    build's grid instead (neighbours.py): the same pairs, summed in another order. Lists of 1
    entry (most touching particles overflow) must give the pile of lists of 16 to round-off,
    on both schedules (the one-thread sweep gives an overflowing particle's pairs to both sides
    its own way, pair_once.py); a dropped contact would let spheres sink into each other."""
    from rigid.engine import list_growth, neighbours

    config = dict(mesh=str(ASSETS / "sphere.obj"), count=27, scale=0.15, position=(0.0, -0.8, 0.0),
                  particle_mass=0.01, velocity_damping_stiffness=12.0, friction_stiffness=0.4,
                  integrator="symplectic", sleep=False)
    runs = {}
    for schedule in ("serial", "parallel"):
        for k in (16, 1):
            monkeypatch.setattr(neighbours, "NEIGHBOURS_PER_PARTICLE", k)
            monkeypatch.setattr(list_growth, "MAX_NEIGHBOURS", k)  # the lists stay this short
            sim = sim_cache(**config)
            sim.schedule = schedule
            overflowing = 0
            for _ in range(10):
                sim.advance_frames(3)
                overflowing = max(overflowing, int((sim.neighbour_counts() > k).sum()))
            runs[schedule, k] = sim.snapshot()["x"], overflowing
    assert runs["serial", 1][1] > 50, "few lists overflowed: the test would prove nothing"
    assert runs["serial", 16][1] == runs["parallel", 16][1] == 0
    for schedule in ("serial", "parallel"):
        x16, x1 = runs[schedule, 16][0], runs[schedule, 1][0]
        assert np.abs(x1 - x16).max() < 1e-4, (schedule, np.abs(x1 - x16).max())
