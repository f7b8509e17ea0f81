"""The collision surface is the mesh (rigid.bodies.inset): a body touches others at its mesh's
geometry, alone or in company, and a start the meshes do not overlap is never refused.

Without Taichi: every vertex sphere of the assets lies inside its mesh, tangent to it, and volume
particles stay inside, unmoved (distances to the triangles by brute force, trimesh's closest
points); a box's corner spheres sit r (1, 1, 1) in,
the radius is capped for thin meshes, and the issue's starts pass (a 5 x 5 x 5 lattice of spheres
6 cm apart, a box 3 mm above a [[plane]], count copies) while a 2 cm overlap is named.
With Taichi: a box rests at its faces plus the penalty sink M g / (n k) alone and in company, and
equal spheres meeting head-on come within 0.9-1.02 x 2R of each other.
"""
import numpy as np
import pytest

from conftest import ASSETS
from rigid.bodies.inset import _outward_normals, collision_centres, radius_cap
from rigid.bodies.mesh import read_mesh
from rigid.bodies.placement import scene_bodies, spacing_radius
from rigid.bodies.sampling import sample_volume
from rigid.config import SimConfig
from rigid.errors import UserError


def _depth_inside(vertices, faces, points):
    """Signed distance of each point to the mesh (positive inside), by brute force."""
    from trimesh.triangles import closest_point

    triangles, normals = vertices[faces], _outward_normals(vertices, faces)
    out = []
    for p in points:
        nearest = closest_point(triangles, np.repeat(p[None], len(faces), axis=0))
        d = np.linalg.norm(nearest - p, axis=1)
        k = int(d.argmin())
        out.append(d[k] if np.dot(nearest[k] - p, normals[k]) >= 0 else -d[k])
    return np.array(out)


@pytest.mark.parametrize("name, scale, grid", [("box", 0.2, 5), ("sphere", 0.15, 6), ("domino", 1.0, 10),
                                               ("t_handle", 0.3, 10), ("capsule", 0.25, 10)])
@pytest.mark.parametrize("mode", ["vertex", "volume"])
def test_every_collision_sphere_lies_inside_its_mesh(name, scale, grid, mode):
    mesh = read_mesh(ASSETS / f"{name}.obj", scale)
    particles = mesh.vertices if mode == "vertex" else sample_volume(mesh.vertices, mesh.faces, grid)
    r = min(spacing_radius(particles), radius_cap(mesh.vertices))
    centres = collision_centres(particles, mesh.vertices, mesh.faces, r)
    depth = _depth_inside(mesh.vertices, mesh.faces, centres)
    if mode == "vertex":  # inside, and tangent to the faces around it
        assert depth.min() >= 0.99 * r and np.allclose(depth, r, rtol=0.02), (depth / r).round(3)
    else:  # cell centres, unmoved: inside, each sphere out by at most its radius (half a cell)
        assert np.array_equal(centres, particles) and depth.min() > 0, depth.min() / r
        if name in ("box", "domino"):  # cells aligned with the faces: tangent to them
            assert depth.min() == pytest.approx(r, rel=1e-6)


def test_box_corner_spheres_sit_r_in_along_each_face_and_the_radius_is_capped():
    mesh = read_mesh(ASSETS / "box.obj", 0.2)  # side 0.2: 8 vertices 0.2 apart, spacing radius 0.1
    r = radius_cap(mesh.vertices)
    assert r == pytest.approx(0.05)  # a quarter of the side: the inset corners' spheres touch
    centres = collision_centres(mesh.vertices, mesh.vertices, mesh.faces, r)
    assert np.allclose(np.abs(centres), 0.1 - r)
    assert np.allclose(collision_centres(mesh.vertices, mesh.vertices, mesh.faces, 0.0), mesh.vertices)
    domino = read_mesh(ASSETS / "domino.obj")  # 0.04 m thick
    assert radius_cap(domino.vertices) == pytest.approx(0.01)
    with pytest.raises(UserError, match=r"particle_radius = 0.06 is more than a quarter of box's thinnest extent "
                                        r"\(0.2 m at scale 0.2\).*use at most 0.05"):
        scene_bodies(SimConfig(mesh=str(ASSETS / "box.obj"), scale=0.2, particle_radius=0.06).validate())


def _start(**keys):
    from rigid.bodies.colliders import check_colliders
    from rigid.bodies.overlap import check_start
    from rigid.bodies.placement import check_inside_box

    config = check_colliders(SimConfig(**keys).validate())
    bodies = scene_bodies(config)
    if config.walls:
        check_inside_box(bodies, config.floor, config.wall, use_radius=True)
    check_start(config, bodies)
    return bodies


def test_starts_whose_meshes_do_not_touch_pass_and_an_overlap_is_named():
    sphere, box = str(ASSETS / "sphere.obj"), str(ASSETS / "box.obj")
    lattice = tuple(dict(position=(-0.72 + 0.36 * i, -0.8 + 0.36 * j, -0.72 + 0.36 * k))
                    for i in range(5) for j in range(5) for k in range(5))
    assert len(_start(mesh=sphere, scale=0.15, bodies=lattice)) == 125  # r = 0.15 spheres with 6 cm gaps
    plane = (dict(point=(0.0, -1.0, 0.0), normal=(0.0, 1.0, 0.0)),)
    _start(mesh=box, scale=0.2, walls=False, planes=plane,  # 3 mm above the plane, in company
           bodies=(dict(position=(0.0, -0.897, 0.0)), dict(position=(0.5, -0.5, 0.0))))
    for mesh, particles in ((sphere, "vertex"), (box, "vertex"), (str(ASSETS / "torus.obj"), "volume")):
        bodies = _start(mesh=mesh, scale=0.25, particles=particles, grid=8,
                        bodies=(dict(count=9, position=(0.0, -0.6, 0.0)), dict(count=4, position=(0.0, 0.3, 0.0))))
        assert len(bodies) == 13
    with pytest.raises(UserError, match=r"body 1 \(box_0\) and body 2 \(box_1\) overlap by 0.02 m at the start "
                                        r"\(their surfaces"):
        _start(mesh=box, scale=0.2, bodies=(dict(position=(0.0, 0.0, 0.0)), dict(position=(0.18, 0.0, 0.0))))


@pytest.fixture(scope="module")
def sim_of(units):
    from rigid.engine.simulator import Simulator

    return lambda **keys: Simulator(SimConfig(**keys).validate(), units)


def test_a_box_rests_at_its_faces_alone_and_in_company(sim_of):
    """Box side 0.2 on the floor y = -1: its centre at -0.9 less the sink of its 4 bottom corners,
    M g / (4 k), the same with a second box in the scene (1 mm) and by the closed form (3 mm)."""
    keys = dict(mesh=str(ASSETS / "box.obj"), scale=0.2, friction_stiffness=0.5)
    alone = sim_of(position=(0.0, -0.85, 0.0), **keys)
    company = sim_of(bodies=(dict(position=(0.0, -0.85, 0.0)), dict(position=(0.5, -0.85, 0.5))), **keys)
    assert company.model.radius_np[0] == pytest.approx(0.05) and alone.model.radius_np[0] == 0.0
    assert np.allclose(company.model.inertia_body_np[0], alone.model.inertia_body_np[0])  # the mesh's I0
    heights = [sim.advance(60)["x"][-1, 0, 1] for sim in (alone, company)]
    m, k = alone.model.body_mass_np[0], alone.config.collision_stiffness
    expected = -1.0 + 0.1 - m * 9.8 / (4 * k)
    print("box centre alone, in company, closed form", heights, expected)
    assert abs(heights[1] - heights[0]) < 1e-3
    assert all(abs(h - expected) < 3e-3 for h in heights)


@pytest.mark.parametrize("particles", ["vertex", "volume"])
def test_equal_spheres_touch_at_their_diameter(sim_of, particles):
    """Two spheres R = 0.15 (e = 0.5) meet at 0.2 m/s without gravity, stiff enough that the
    penalty's squeeze is ~1 mm: their centres come within 0.9-1.02 x 2R of each other (the
    particles' spheres sit inside the mesh; their bumps let the two surfaces mesh a little)."""
    R = 0.15
    sim = sim_of(mesh=str(ASSETS / "sphere.obj"), scale=R, particles=particles, grid=8, walls=False,
                 gravity=(0.0, 0.0, 0.0), collision_stiffness=1e5, particle_mass=0.01, dt=1e-4,
                 restitution=0.5, friction=0.0,
                 bodies=(dict(position=(-0.2, 0.0, 0.0), initial_velocity=(0.1, 0, 0)),
                         dict(position=(0.2, 0.01, 0.02), initial_velocity=(-0.1, 0, 0))))
    x = sim.advance(50)["x"]
    gap = np.linalg.norm(x[:, 0] - x[:, 1], axis=1)
    closest = gap.min()
    print(particles, "closest centres / 2R", closest / (2 * R))
    assert gap[-1] > closest + 1e-3, "they never met"
    assert 0.9 * 2 * R <= closest <= 1.02 * 2 * R
