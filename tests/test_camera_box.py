"""The default camera of a scene with the box shows the whole floor: the dominoes', the ramp's
and the bounce's videos cut the box off (their bodies' bounding box was framed, and a body that
slides or topples left it). Checked on the scenes' starting bodies, without Taichi kernels."""
from types import SimpleNamespace

import numpy as np
import pytest

from conftest import ASSETS
from test_camera import _project

SIZE = (1280, 720)


def _stand_in(scene: str):
    """What framed_view reads of a Simulator, from the scene's bodies (numpy only)."""
    from rigid.bodies.placement import scene_bodies, world_particles
    from rigid.config import SimConfig, load_scene

    config = SimConfig(**load_scene(ASSETS / "scenes" / scene)).validate()
    bodies = scene_bodies(config)
    r0 = np.concatenate([b.geometry.particles - b.centre_of_mass for b in bodies])
    points = np.concatenate([world_particles(b) for b in bodies])
    params = SimpleNamespace(walls=config.walls, wall=config.wall, floor=config.floor)
    return SimpleNamespace(many=True, particle_positions=lambda: points, model=SimpleNamespace(r0_np=r0),
                           params=params), config


@pytest.mark.parametrize("scene", ["dominoes.toml", "ramp.toml", "bounce.toml", "pile.toml", "bowl.toml"])
def test_the_default_view_holds_the_whole_floor_of_the_box(scene):
    from rigid.view.camera import framed_view
    from rigid.view.orbit import OrbitCamera

    sim, config = _stand_in(scene)
    view = framed_view(sim, SIZE[0] / SIZE[1])
    orbit = OrbitCamera(view["target"], view["distance"], view["azimuth_deg"], view["elevation_deg"], 45.0)
    w, f = config.wall, config.floor
    corners = np.array([[x, f, z] for x in (-w, w) for z in (-w, w)])
    for points in (corners, sim.particle_positions()):
        cols, rows = _project(orbit, SIZE, points)
        assert cols.min() >= 0 and cols.max() <= SIZE[0] and rows.min() >= 0 and rows.max() <= SIZE[1], \
            (scene, cols.min(), cols.max(), rows.min(), rows.max())


def test_the_overlay_counts_the_bowls_27_bodies_not_the_bowl():
    from rigid.bodies.statics import static_bodies
    from rigid.view.imaging import moving_bodies, overlay_text

    sim, config = _stand_in("bowl.toml")
    bodies = _stand_in_bodies("bowl.toml")
    sim.bodies = bodies + static_bodies(config, bodies)
    assert len(sim.bodies) == 28 and moving_bodies(sim) == 27
    assert overlay_text(0.0, -1.0, moving_bodies(sim)).endswith("27 bodies")


def _stand_in_bodies(scene: str):
    from rigid.bodies.placement import scene_bodies
    from rigid.config import SimConfig, load_scene

    return scene_bodies(SimConfig(**load_scene(ASSETS / "scenes" / scene)).validate())
