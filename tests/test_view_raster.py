"""The software renderer (rigid/view/raster.py) and the scene drawn with it: depth, lines, discs, grid."""
import numpy as np
import pytest

W, H = 64, 48
RED, BLUE, GREEN = (1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, 1.0, 0.0)


@pytest.fixture(scope="module")
def raster(ti_cpu):
    from rigid.view.raster import Rasterizer

    return Rasterizer(W, H)


def vec_field(points):
    from rigid.view.raster_data import vec3_array

    return vec3_array(points)


def square(z, half=1.0):
    """Two triangles (no index field) facing +z at depth z."""
    a, b, c, d = (-half, -half, z), (half, -half, z), (half, half, z), (-half, half, z)
    return vec_field([a, b, c, a, c, d])


def frame(raster, *draws):
    raster.begin(eye=(0.0, 0.0, 3.0), target=(0.0, 0.0, 0.0), light=((0.0, 0.0, 5.0), (0.0, 0.0, 0.0)),
                 ambient=(1.0, 1.0, 1.0), background=(1.0, 1.0, 1.0))  # unlit: colours come out as given
    for draw in draws:
        draw()
    raster.finish()
    return raster.read_rgba()


def test_the_nearer_face_wins_whatever_the_order_and_the_picture_is_repeatable(raster):
    near, far = square(0.0, 0.5), square(-1.0, 1.0)
    a = frame(raster, lambda: raster.mesh(far, color=BLUE), lambda: raster.mesh(near, color=RED))
    b = frame(raster, lambda: raster.mesh(near, color=RED), lambda: raster.mesh(far, color=BLUE))
    assert a.shape == (H, W, 4) and (a[..., 3] == 255).all()
    assert tuple(a[H // 2, W // 2, :3]) == (255, 0, 0)  # the red square is in front
    assert (a[..., 2] == 255).sum() > 0 and tuple(a[0, 0, :3]) == (255, 255, 255)  # blue around it, background
    assert np.array_equal(a, b)  # depth, not drawing order, decides; and no thread-order noise


def test_a_line_on_a_face_is_drawn_over_it(raster):
    face, line = square(0.0), vec_field([(-0.8, 0.0, 0.0), (0.8, 0.0, 0.0)])
    rgba = frame(raster, lambda: raster.mesh(face, color=BLUE), lambda: raster.lines(line, width=2.0, color=GREEN))
    assert tuple(rgba[H // 2, W // 2, :3]) == (0, 255, 0)
    assert tuple(rgba[H // 4, W // 2, :3]) == (0, 0, 255)


def test_particles_are_discs_and_a_point_behind_the_eye_is_skipped(raster):
    centres = vec_field([(0.0, 0.0, 0.0), (0.0, 0.0, 10.0)])  # the second is behind the eye (z = 3)
    rgba = frame(raster, lambda: raster.particles(centres, radius=0.3, color=RED))
    red = (rgba[..., 0] == 255) & (rgba[..., 1] < 50)
    assert red[H // 2, W // 2] and 50 < red.sum() < 400 and not red[0].any()


def test_wireframe_draws_the_edges(raster):
    face = square(0.0)
    plain = frame(raster, lambda: raster.mesh(face, color=BLUE))
    wire = frame(raster, lambda: raster.mesh(face, color=BLUE, show_wireframe=True))
    assert (np.abs(plain.astype(int) - wire.astype(int)).sum(axis=2) > 0).sum() > 50


def test_scenes_without_walls_draw_a_grid_on_the_floor_plane(sim_cache):
    from rigid.view.render import GRID_COLOR, SceneRenderer

    grid = np.round(np.array(GRID_COLOR) * 255).astype(int)
    counts = {}
    for walls in (True, False):
        renderer = SceneRenderer(sim_cache(walls=walls), (160, 120), offscreen=True)
        renderer.draw()
        rgb = renderer.read_rgba()[..., :3].astype(int)
        counts[walls] = (np.abs(rgb - grid).max(axis=2) <= 2).sum()
        renderer.close()
    assert counts[False] > 300 and counts[True] < counts[False] / 10


def test_more_triangles_than_its_first_room_keeps_every_draw(ti_cpu):
    from rigid.view.raster import Rasterizer

    small = Rasterizer(W, H, capacity=4)
    near = square(0.0, 0.3)
    strip = vec_field([p for x in np.linspace(-1.0, 0.9, 20) for p in
                       ((x, -1.0, -1.0), (x + 0.1, -1.0, -1.0), (x + 0.1, -0.5, -1.0))])  # 20 triangles
    first = frame(small, lambda: small.mesh(near, color=RED))
    both = [frame(small, lambda: small.mesh(near, color=RED), lambda: small.mesh(strip, color=BLUE))
            for _ in range(2)]
    assert small.tris.capacity >= 22 and np.array_equal(both[0], both[1])
    assert tuple(both[1][H // 2, W // 2, :3]) == tuple(first[H // 2, W // 2, :3]) == (255, 0, 0)
    blue = (both[1][..., 2] == 255) & (both[1][..., 0] == 0)
    assert blue.sum() > 20 and not ((first[..., 2] == 255) & (first[..., 0] == 0)).any()


FP64_DRAW = """
import numpy as np, taichi as ti
from rigid.runtime import init_taichi
init_taichi("cpu", fp64=True)
from rigid.view.raster import Rasterizer
points = ti.Vector.ndarray(3, ti.f64, shape=6)
points.from_numpy(np.array([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, -1, 0), (1, 1, 0), (-1, 1, 0)], float))
raster = Rasterizer(32, 24)
raster.begin((0.0, 0.0, 3.0), (0.0, 0.0, 0.0))
raster.mesh(points, per_vertex_color=points, show_wireframe=True)
raster.lines(points)
raster.particles(points, radius=0.1, per_vertex_color=points)
raster.finish()
print((raster.read_rgba()[..., :3] != 255).sum())
"""


def test_float64_fields_draw_without_precision_warnings(tmp_path):
    """--fp64 makes Taichi's float literals f64; the renderer still stores f32 (it crashed before), and
    takes float64 arrays."""
    import os
    import subprocess
    import sys

    from conftest import ROOT

    env = dict(os.environ, TI_OFFLINE_CACHE_FILE_PATH=str(tmp_path))  # compile afresh: warnings show then
    proc = subprocess.run([sys.executable, "-c", FP64_DRAW], cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert int(proc.stdout.split()[-1]) > 100 and "precision" not in proc.stderr, proc.stderr[-3000:]
