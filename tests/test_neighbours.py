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
