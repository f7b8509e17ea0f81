"""A mesh file holding several meshes is several bodies (issue 15, item 5), placed as one group.

Expected numbers come from how the files are built here, not from rigid: trimesh's own vertex
counts (distinct points), node translations and rotations written out by hand, masses as
particle_mass x vertex count. tests/data/two_meshes.glb and tests/data/box_and_stick.glb
(used by the README's bad-input rows) were written by ``two_meshes`` and ``box_and_stick``
below with trimesh 5.2.0; ``test_committed_files_are_the_recipes`` checks they still are.
"""
import numpy as np
import pytest
import trimesh
from trimesh.transformations import rotation_matrix, translation_matrix

from conftest import ROOT, run_main

SCALE = 0.3  # SimConfig's default scale
BOX_LOCAL = np.array([-0.8, 0.0, 0.0])  # the box node, child of "pair"
PAIR_T = np.array([0.0, 0.1, 0.0])  # "pair": turned 90 degrees about y, then moved up 0.1
BALL_AT = np.array([0.6, 0.2, -0.4])  # the ball node, child of the root
# World centres in file units: R_y(90) (-0.8, 0, 0) = (0, 0, 0.8); both meshes are centred on their origin.
BOX_CENTRE = np.array([0.0, 0.1, 0.8])
BALL_CENTRE = BALL_AT


def two_meshes(path):
    """A unit box (unmerged: 36 corners at 8 points) under a turned parent node, and a
    42-vertex icosphere of radius 0.5 beside it: the two never touch."""
    box = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    box.unmerge_vertices()
    ball = trimesh.creation.icosphere(subdivisions=1, radius=0.5)
    scene = trimesh.Scene()
    scene.graph.update(frame_from=scene.graph.base_frame, frame_to="pair",
                       matrix=translation_matrix(PAIR_T) @ rotation_matrix(np.pi / 2, (0, 1, 0)))
    scene.add_geometry(box, node_name="box", geom_name="box", parent_node_name="pair",
                       transform=translation_matrix(BOX_LOCAL))
    scene.add_geometry(ball, node_name="ball", geom_name="ball", transform=translation_matrix(BALL_AT))
    scene.export(str(path))
    return box, ball


def box_and_stick(path):
    """A box and a 'stick': one triangle whose three corners lie on a line."""
    scene = trimesh.Scene()
    scene.add_geometry(trimesh.creation.box(), node_name="box", geom_name="box")
    stick = trimesh.Trimesh([[0, 0, 0], [0.5, 0, 0], [1, 0, 0]], [[0, 1, 2]], process=False)
    scene.add_geometry(stick, node_name="stick", geom_name="stick", transform=translation_matrix((1.5, 0, 0)))
    scene.export(str(path))


def distinct(mesh) -> int:
    return len(np.unique(np.asarray(mesh.vertices), axis=0))


@pytest.fixture
def glb(tmp_path):
    path = tmp_path / "t.glb"
    box, ball = two_meshes(path)
    return path, distinct(box), distinct(ball)


def bodies_of(**config):
    from rigid.bodies.placement import scene_bodies
    from rigid.config import SimConfig

    return scene_bodies(SimConfig(**config).validate())


def test_two_meshes_are_two_bodies_where_the_file_puts_them(glb):
    path, n_box, n_ball = glb
    assert (n_box, n_ball) == (8, 42)
    from rigid.config import SimConfig

    assert SimConfig(mesh=str(path)).validate().many_bodies
    bodies = bodies_of(mesh=str(path), position=(0.1, -0.2, 0.05))
    assert [b.name for b in bodies] == ["t_0_box", "t_0_ball"]
    assert [len(b.geometry.particles) for b in bodies] == [n_box, n_ball]
    # The group's centre of mass (equal particle masses) goes to position; each body keeps its offset.
    centres = SCALE * np.array([BOX_CENTRE, BALL_CENTRE])
    group = (n_box * centres[0] + n_ball * centres[1]) / (n_box + n_ball)
    expected = centres - group + np.array([0.1, -0.2, 0.05])
    assert np.allclose([b.position for b in bodies], expected, atol=1e-12)
    # Each body's particles are its mesh's vertices, moved by the node's world transform and scaled.
    box_world = np.unique(np.asarray(trimesh.creation.box().vertices), axis=0) @ \
        rotation_matrix(np.pi / 2, (0, 1, 0))[:3, :3].T + BOX_CENTRE
    assert np.allclose(np.unique(bodies[0].geometry.particles.round(9), axis=0),
                       np.unique((SCALE * box_world).round(9), axis=0), atol=1e-12)
    assert np.allclose(bodies[0].centre_of_mass, SCALE * BOX_CENTRE, atol=1e-12)
    assert np.allclose(bodies[1].centre_of_mass, SCALE * BALL_CENTRE, atol=1e-12)


def test_flags_move_the_group_as_one_rigid_body(glb):
    from rigid.bodies.placement import world_particles
    from rigid.bodies.quaternion import quaternion_to_matrix_np

    path, n_box, n_ball = glb
    c, s = np.cos(np.pi / 4), np.sin(np.pi / 4)
    q = (c, 0.0, 0.0, s)  # 90 degrees about z
    R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    x0, v0, w0 = np.array([0.2, 0.1, 0.0]), np.array([1.0, 0.0, -0.5]), np.array([0.0, 2.0, 3.0])
    bodies = bodies_of(mesh=str(path), position=tuple(x0), orientation=q, initial_velocity=tuple(v0),
                       initial_angular_velocity=tuple(w0))
    assert np.allclose(quaternion_to_matrix_np(np.array(q)), R, atol=1e-12)
    unturned = bodies_of(mesh=str(path))
    masses = np.array([n_box, n_ball], float)
    assert np.allclose(masses @ np.array([b.position for b in bodies]) / masses.sum(), x0, atol=1e-12)
    for body, flat in zip(bodies, unturned):
        arm = R @ flat.position  # unturned, the group's centre is at the origin
        assert np.allclose(body.position, x0 + arm, atol=1e-12)
        assert np.allclose(body.orientation, q) and np.allclose(body.angular_velocity, w0)
        assert np.allclose(body.velocity, v0 + np.cross(w0, arm), atol=1e-12)
        assert np.allclose(world_particles(body), x0 + world_particles(flat) @ R.T, atol=1e-12)


def test_count_copies_the_group(glb):
    path, *_ = glb
    bodies = bodies_of(mesh=str(path), count=2, scale=0.2, position=(0.0, -0.5, 0.0))
    assert [b.name for b in bodies] == ["t_0_0_box", "t_0_0_ball", "t_0_1_box", "t_0_1_ball"]
    gap = 0.2 * np.linalg.norm(BALL_CENTRE - BOX_CENTRE)
    for box, ball in (bodies[0:2], bodies[2:4]):
        assert np.allclose(box.orientation, ball.orientation)  # one group, turned as one
        assert np.isclose(np.linalg.norm(ball.position - box.position), gap, atol=1e-12)


def test_merging_is_per_mesh(tmp_path):
    """Two boxes sharing a face: merged over the joined mesh they would be 12 particles."""
    scene = trimesh.Scene()
    for name, x in (("left", -0.5), ("right", 0.5)):
        box = trimesh.creation.box()
        box.unmerge_vertices()
        scene.add_geometry(box, node_name=name, geom_name=name, transform=translation_matrix((x, 0, 0)))
    scene.export(str(tmp_path / "pair.glb"))
    bodies = bodies_of(mesh=str(tmp_path / "pair.glb"))
    assert [len(b.geometry.particles) for b in bodies] == [8, 8]
    assert "holds 2 meshes: 2 bodies" in bodies[0].geometry.note
    assert "36 vertices lie at 8 distinct points" in bodies[0].geometry.note


def test_ascii_stl_solids_are_bodies(tmp_path):
    a, b = trimesh.creation.box(), trimesh.creation.box()
    b.apply_translation((2.0, 0.0, 0.0))
    (tmp_path / "two.stl").write_text(a.export(file_type="stl_ascii") + b.export(file_type="stl_ascii"))
    bodies = bodies_of(mesh=str(tmp_path / "two.stl"), scale=0.2)
    assert [len(x.geometry.particles) for x in bodies] == [8, 8]
    assert np.allclose(bodies[1].position - bodies[0].position, (0.4, 0.0, 0.0))
    assert "its 12 triangles' 36 corners merged into 8 vertices" in bodies[0].geometry.note


def test_one_mesh_glb_is_one_body_as_before(tmp_path):
    from rigid.bodies.mesh import body_geometry
    from rigid.config import SimConfig

    trimesh.creation.box().export(str(tmp_path / "one.glb"))
    config = SimConfig(mesh=str(tmp_path / "one.glb")).validate()
    assert not config.many_bodies
    (body,) = bodies_of(mesh=str(tmp_path / "one.glb"))
    assert body.name == "body" and body.geometry.note == body_geometry(config).note
    assert np.array_equal(body.geometry.particles, body_geometry(config).particles)


def test_committed_files_are_the_recipes(tmp_path):
    from rigid.bodies.group import read_mesh_parts
    from rigid.config import mesh_count

    two_meshes(tmp_path / "two.glb")
    box_and_stick(tmp_path / "stick.glb")
    for made, kept in (("two.glb", "two_meshes.glb"), ("stick.glb", "box_and_stick.glb")):
        ours, theirs = read_mesh_parts(tmp_path / made), read_mesh_parts(ROOT / "tests" / "data" / kept)
        assert mesh_count(str(ROOT / "tests" / "data" / kept)) == len(theirs) == len(ours) == 2
        for (name_a, a), (name_b, b) in zip(ours, theirs):
            assert name_a == name_b and np.allclose(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)


def test_bad_mesh_in_the_file_is_one_line(capsys, monkeypatch):
    from rigid.cli import main

    monkeypatch.chdir(ROOT)
    for args, message in (
            (["--mesh", "tests/data/box_and_stick.glb"],
             "error: mesh file tests/data/box_and_stick.glb, mesh 'stick': all 3 particles lie on one line"),):
        assert main(["--headless", *args]) == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith(message) and len(err.splitlines()) == 1, err


def test_cli_runs_the_bodies(glb, tmp_path, capsys, monkeypatch):
    path, n_box, n_ball = glb
    out = tmp_path / "out.npz"
    code, stdout, stderr = run_main(capsys, monkeypatch, "--mesh", path, "--headless", "--frames", "5", "--export", out)
    assert code == 0, stderr
    assert "t.glb holds 2 meshes: 2 bodies" in stdout.splitlines()
    d = np.load(out)
    assert d["x"].shape == (6, 2, 3) and d["q"].shape == (6, 2, 4)
    assert np.allclose(d["mass"], [n_box, n_ball])  # particle_mass 1
    centres = SCALE * np.array([BOX_CENTRE, BALL_CENTRE])
    assert np.allclose(d["x"][0], centres - (n_box * centres[0] + n_ball * centres[1]) / (n_box + n_ball),
                       atol=1e-6)


def test_cli_one_mesh_glb_and_a_body_table(tmp_path, capsys, monkeypatch):
    trimesh.creation.box().export(str(tmp_path / "one.glb"))
    out = tmp_path / "one.npz"
    code, stdout, stderr = run_main(capsys, monkeypatch, "--mesh", tmp_path / "one.glb", "--headless", "--frames",
                                    "5", "--export", out)
    assert code == 0, stderr
    assert "holds" not in stdout and np.load(out)["x"].shape == (6, 3)
    two_meshes(tmp_path / "t.glb")
    (tmp_path / "s.toml").write_text(
        'particle_mass = 0.25\nintegrator = "symplectic"\n\n[[body]]\nmesh = "t.glb"\nposition = [0, 0.3, 0]\n\n'
        '[[body]]\nmesh = "sphere.obj"\nscale = 0.1\nposition = [0, -0.7, 0]\n')
    out = tmp_path / "s.npz"
    code, _, stderr = run_main(capsys, monkeypatch, "--scene", tmp_path / "s.toml", "--headless", "--frames", "1",
                               "--export", out)
    assert code == 0, stderr
    d = np.load(out)
    assert d["x"].shape == (2, 3, 3) and np.allclose(d["mass"], 0.25 * np.array([8, 42, 42]))
