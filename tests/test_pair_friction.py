"""Coulomb static friction between bodies (rigid.engine.pair_slip, contact.pair_contact_sticking).

- a box on a box on a 30° [[plane]] ramp, μ = 0.9 > tan 30° = 0.58 everywhere: the upper box
  stays on the lower one (< 2 mm relative drift in 2.5 s; the viscous law it replaced let it
  creep 24 mm before it lodged between the lower box's particles). The lower box is three times
  as wide and heavier: a stack of two equal cubes tips over on 30° (its centre of mass, 0.2
  above the ramp, passes the downhill edge at tan θ > 0.1 / 0.2), which is not friction's
  business. Both boxes' particles share one spacing and lie in columns, so the upper one rests
  on sphere tops, where only the contacts' tangential springs hold it (in a pocket between
  four spheres it would be held by geometry, and the test could not fail);
- each pair's two copies of its spring (one in each particle's list) are bit for bit alike,
  and a rebuild of the lists carries every spring over: forcing a rebuild every frame gives
  the same bits as the run that rebuilt only when it had to;
- a box on a [[static]] box rests at the static mesh's faces (its spheres are inside it).
"""
import math

import numpy as np
import pytest

from conftest import ASSETS

BOX = str(ASSETS / "box.obj")
THETA = math.radians(30)
NORMAL = np.array([-math.sin(THETA), math.cos(THETA), 0.0])  # the ramp's: it rises toward -x
TURN = (math.cos(THETA / 2), 0.0, 0.0, math.sin(THETA / 2))  # a box turned to lie flat on it


@pytest.fixture(autouse=True)
def _taichi(units):
    """One Taichi runtime for the module (conftest)."""


def _sim(**keys):
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    return Simulator(SimConfig(**keys).validate())


def _stack_on_ramp(mu):
    """A 0.2 cube (grid 4) on a 0.6 cube (grid 12: the same 0.05 spacing, radius 0.025), centred
    on it, on the ramp, each started 10 µm clear of what it lands on."""
    gap = 1e-5
    bodies = (dict(position=tuple((0.3 + gap) * NORMAL), orientation=TURN, scale=0.6, grid=12),
              dict(position=tuple((0.7 + 2 * gap) * NORMAL), orientation=TURN, scale=0.2, grid=4))
    return _sim(mesh=BOX, bodies=bodies, particles="volume", friction=mu, restitution=0.3, walls=False,
                collision_stiffness=1e5, particle_mass=0.1, dt=2e-4,
                planes=(dict(point=(0.0, 0.0, 0.0), normal=tuple(NORMAL)),))


def test_box_on_a_box_on_a_30_degree_ramp_holds():
    sim = _stack_on_ramp(0.9)
    assert np.allclose(sim.model.radius_np, 0.025)
    sim.advance_frames(12)  # 0.2 s: settled
    a = sim.snapshot()
    sim.advance_frames(150)  # 2.5 s
    b = sim.snapshot()
    drift = np.linalg.norm((b["x"][1] - b["x"][0]) - (a["x"][1] - a["x"][0]))
    print(f"box on a box on 30°, mu 0.9: upper box moved {drift * 1e3:.4f} mm on the lower in 2.5 s, "
          f"lower {np.linalg.norm(b['x'][0] - a['x'][0]) * 1e3:.4f} mm on the ramp")
    assert drift < 2e-3
    assert np.linalg.norm(b["x"][0] - a["x"][0]) < 2e-3


def _pair_springs(sim):
    from rigid.engine.pair_slip import springs_by_pair

    return springs_by_pair(sim)


def test_both_copies_of_a_spring_agree_and_rebuilds_carry_them():
    from rigid.engine.broadphase import REBUILD
    from rigid.engine.broadphase_host import cell

    runs = []
    for forced in (False, True):
        sim = _stack_on_ramp(0.9)
        rebuild = cell(sim._scratch_arrays, REBUILD)
        for _ in range(20):
            if forced:
                rebuild.value = 1  # a rebuild at the next placement, whether or not anything moved
            sim.advance_frames(1)
        builds = sim.neighbour_builds
        runs.append((sim.snapshot(), _pair_springs(sim), builds))
    (s1, springs, builds1), (s2, _springs2, builds2) = runs
    stretched = [key for key, s in springs.items() if np.any(s != 0)]
    print(f"{len(springs)} list entries, {len(stretched)} springs stretched; builds {builds1} and {builds2}")
    assert len(stretched) >= 16, "the upper box's bottom layer holds by its springs"
    for i, j in stretched:
        assert np.array_equal(springs[i, j], springs[j, i]), (i, j)
    assert builds2 >= builds1 + 15
    for key in ("x", "v", "q", "omega"):
        assert np.array_equal(s1[key], s2[key]), key


def test_box_rests_at_a_static_boxs_face():
    """A 0.2 cube (corner spheres of radius 0.02 inside it) dropped 1 mm onto a 0.6 [[static]] cube
    whose top face is at y = 0.3: its centre rests 0.1 above that face, less the penalty sink
    (M g / (4 k) on its four lower corners: 20 µm), within 3 mm. With the static's spheres
    (radius h = 2.5 × 0.02) centred on its surface it rested h higher."""
    sim = _sim(mesh=BOX, scale=0.2, particle_radius=0.02, position=(0.0, 0.401, 0.0), restitution=0.3, friction=0.5,
               walls=False, collision_stiffness=1e5, particle_mass=0.1, dt=2e-4,
               statics=(dict(mesh=BOX, scale=0.6),))
    sim.advance_frames(30)
    y = sim.snapshot()["x"][0][1]
    sink = 8 * 0.1 * 9.8 / (4 * 1e5)
    print(f"box on a static box: centre {y:.5f}, faces touch at 0.4 (less the sink {sink:.5f})")
    assert abs(y - (0.4 - sink)) < 3e-3


def test_lists_that_grow_keep_their_springs():
    """Lists made twice as long while the upper box rests on its springs (what list_growth.py does
    after an overflow: pair_slip.grown lays the springs out anew, then the lists are rebuilt) give
    the bits of the run whose lists never grew."""
    from rigid.engine.broadphase import REBUILD
    from rigid.engine.broadphase_host import cell

    whole = _stack_on_ramp(0.9)
    whole.advance_frames(20)
    grown = _stack_on_ramp(0.9)
    grown.advance_frames(10)
    stretched = sum(np.any(s != 0) for s in _pair_springs(grown).values())
    grown._lists._grow(grown)
    grown._lists._copy = None
    cell(grown._scratch_arrays, REBUILD).value = 1
    assert grown._lists.stride(grown._scratch_arrays) == 32 and stretched >= 8
    grown.advance_frames(10)
    a, b = whole.snapshot(), grown.snapshot()
    for key in ("x", "v", "q", "omega"):
        assert np.array_equal(a[key], b[key]), key
