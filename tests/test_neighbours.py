"""The neighbour lists (rigid.engine.neighbours) hold every overlapping pair of particles of
different bodies, checked against a k-d tree of the particles (scipy), frame after frame of a
falling pile: the lists are reused across substeps, so this tests the rebuild rule too."""
import numpy as np
from scipy.spatial import cKDTree

from conftest import ASSETS


def test_every_touching_pair_is_in_the_lists(sim_cache):
    sim = sim_cache(mesh=str(ASSETS / "sphere.obj"), count=27, scale=0.15, position=(0.0, -0.8, 0.0),
                    particle_mass=0.01, velocity_damping_stiffness=12.0, friction_stiffness=0.4,
                    integrator="symplectic", sleep=False)
    radius = sim.model.radius_np[sim.particle_bodies()]
    body = sim.particle_bodies()
    slot = sim.model.slot_of
    stride = sim._scratch_arrays["nbr_list"].shape[0] // sim.num_particles
    touching_total, builds0 = 0, sim.neighbour_builds
    for frame in range(40):
        sim.advance_frames(3)
        p = sim.particle_positions()
        pairs = cKDTree(p).query_pairs(2 * radius.max(), output_type="ndarray")
        d = np.linalg.norm(p[pairs[:, 0]] - p[pairs[:, 1]], axis=1)
        keep = (body[pairs[:, 0]] != body[pairs[:, 1]]) & (d < radius[pairs[:, 0]] + radius[pairs[:, 1]])
        counts = sim.neighbour_counts()
        lists = sim._scratch_arrays["nbr_list"].to_numpy().reshape(sim.num_particles, stride)
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
    off by round-off, and for arbitrary matrices (where it falls back to ‖R − R0‖_F)."""
    import taichi as ti
    from scipy.spatial.transform import Rotation

    from rigid.engine import neighbours

    sim_cache(count=2, sleep=False)  # a Taichi runtime, in float32 as the engine runs

    @ti.kernel
    def bound(R: ti.types.ndarray(), R0: ti.types.ndarray(), out: ti.types.ndarray()):
        for n in range(out.shape[0]):
            a = ti.Matrix.zero(float, 3, 3)
            b = ti.Matrix.zero(float, 3, 3)
            for r, c in ti.static(ti.ndrange(3, 3)):
                a[r, c] = R[n, r, c]
                b[r, c] = R0[n, r, c]
            out[n] = neighbours._turn_norm(a, b)

    rng = np.random.default_rng(1)
    n = 400
    base = Rotation.random(n, random_state=2).as_matrix()
    small = Rotation.from_rotvec(rng.normal(size=(n, 3)) * rng.uniform(1e-3, 0.3, size=(n, 1))).as_matrix()
    cases = {"rotations": (small @ base, base),
             "rotations off by 1e-5": (small @ base + 1e-5 * rng.normal(size=(n, 3, 3)), base),
             "any matrices": (rng.normal(size=(n, 3, 3)), rng.normal(size=(n, 3, 3))),
             "a reflection": (base * np.array([1.0, 1.0, -1.0]), base)}
    for name, (R, R0) in cases.items():
        out = np.zeros(n, np.float32)
        bound(R.astype(np.float32), R0.astype(np.float32), out)
        spectral = np.linalg.norm(R - R0, ord=2, axis=(1, 2))
        frob = np.linalg.norm(R - R0, axis=(1, 2))
        assert np.all(out >= spectral * (1 - 1e-5) - 1e-6), name
        assert np.all(out <= frob * (1 + 1e-5) + 1e-6), name
        if name == "rotations":
            np.testing.assert_allclose(out, frob / np.sqrt(2), rtol=2e-3, atol=1e-5)
