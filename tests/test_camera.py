"""The camera: --camera and the [camera] table, the default view that frames the scene, follow."""
import numpy as np
import pytest

from conftest import ASSETS


def _project(orbit, size, points):
    """Pixel columns and rows (row 0 on top) of world points, by the pinhole of raster.py."""
    eye = np.asarray(orbit.position())
    forward = np.asarray(orbit.target) - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rel = np.asarray(points) - eye
    focal = 0.5 * size[1] / np.tan(np.radians(orbit.fov) / 2)
    depth = rel @ forward
    return 0.5 * size[0] + focal * (rel @ right) / depth, 0.5 * size[1] - focal * (rel @ up) / depth


def test_flag_and_table_parse_into_a_spec_and_bad_values_are_one_line():
    from rigid.errors import UserError
    from rigid.view.camera import camera_spec, parse_camera_flag

    table = parse_camera_flag(["position=3,2,4", "look-at=0,-0.8,0", "fov=35", "follow=centre"])
    spec = camera_spec(table)
    assert spec.position == (3.0, 2.0, 4.0) and spec.look_at == (0.0, -0.8, 0.0)
    assert spec.fov == 35.0 and spec.follow == "centre"
    assert camera_spec(parse_camera_flag(["follow=3"])).follow == 3
    assert camera_spec({"follow": "none"}).follow is None
    for bad, message in [({"fov": 0}, "fov = 0: use a field of view from 1 to 170 degrees"),
                         ({"position": [1, 2]}, "position = [1, 2]: use three finite numbers"),
                         ({"zoom": 2}, "unknown key 'zoom'"),
                         ({"position": [0, 0, 0], "look_at": [0, 0, 0]}, "the same point")]:
        with pytest.raises(UserError, match=message.replace("[", r"\[").replace("]", r"\]")):
            camera_spec(bad)
    with pytest.raises(UserError, match="use KEY=VALUE"):
        parse_camera_flag(["fov"])
    with pytest.raises(UserError, match="three numbers"):
        parse_camera_flag(["position=a,b,c"])


def test_a_scene_camera_table_is_read_and_checked(tmp_path):
    from rigid.config import load_scene
    from rigid.errors import UserError
    from rigid.view.camera import camera_spec

    scene = tmp_path / "s.toml"
    scene.write_text("scale = 0.3\n[camera]\nposition = [0.0, 1.0, 4.0]\nlook_at = [0.0, -0.5, 0.0]\nfov = 30\n")
    spec = camera_spec(load_scene(scene)["camera"])
    assert spec.position == (0.0, 1.0, 4.0) and spec.fov == 30.0
    scene.write_text("scale = 0.3\ncamera = 3\n")
    with pytest.raises(UserError, match=r"'camera' must be a \[camera\] table"):
        load_scene(scene)


def test_the_default_view_frames_the_dominoes_and_the_pile_from_a_height(sim_cache):
    """Every particle of the row of dominoes (and where they topple to) is in the picture, and
    the row spans a good part of its width; the pile is seen from above its top layer."""
    from rigid.config import load_scene
    from rigid.view.camera import SceneCamera, fit_distance

    size = (1280, 720)
    dominoes = sim_cache(**load_scene(ASSETS / "scenes" / "dominoes.toml"))
    orbit = SceneCamera(dominoes, aspect=size[0] / size[1]).orbit
    cols, rows = _project(orbit, size, dominoes.particle_positions())
    assert cols.min() > 0 and cols.max() < size[0] and rows.min() > 0 and rows.max() < size[1]
    # the row crosses most of the box, whose whole floor is in the picture (tests/test_camera_box.py)
    assert cols.max() - cols.min() > 0.3 * size[0], (cols.min(), cols.max())
    # Any box fits the picture from fit_distance: its corners project inside, one of them near the edge.
    centre, half = np.array([0.2, -0.5, 0.1]), np.array([0.7, 0.3, 0.4])
    d = fit_distance(centre, half, 28.0, 32.0, 16 / 9, 45.0)
    from rigid.view.orbit import OrbitCamera

    box = OrbitCamera(tuple(centre), d, 28.0, 32.0, 45.0)
    corners = centre + half * np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    c, r = _project(box, size, corners)
    margin = np.minimum.reduce([c, size[0] - c, r, size[1] - r])
    assert margin.min() > 0 and margin.min() < 0.1 * size[1]
    pile = sim_cache(**load_scene(ASSETS / "scenes" / "pile.toml"))
    orbit = SceneCamera(pile, aspect=16 / 9).orbit
    assert orbit.position()[1] > pile.particle_positions()[:, 1].max()  # the eye above the top layer
    cols, rows = _project(orbit, size, pile.particle_positions())
    assert cols.min() > 0 and cols.max() < size[0] and rows.min() > 0 and rows.max() < size[1]


def test_position_look_at_and_follow(sim_cache):
    from rigid.view.camera import CameraSpec, SceneCamera

    sim = sim_cache(initial_velocity=(1.5, 0.0, 0.0))
    camera = SceneCamera(sim, CameraSpec(position=(1.0, 2.0, 3.0), look_at=(0.0, -0.5, 0.0), fov=30.0))
    np.testing.assert_allclose(camera.orbit.position(), (1.0, 2.0, 3.0), atol=1e-12)
    assert camera.orbit.target == (0.0, -0.5, 0.0) and camera.orbit.fov == 30.0
    follow = SceneCamera(sim, CameraSpec(follow=0))
    offset = np.subtract(follow.orbit.position(), follow.orbit.target)
    sim.advance_frames(30)
    follow.update()
    np.testing.assert_allclose(follow.orbit.target, sim.snapshot()["x"][0], atol=1e-6)  # on the body
    np.testing.assert_allclose(np.subtract(follow.orbit.position(), follow.orbit.target), offset, atol=1e-9)
