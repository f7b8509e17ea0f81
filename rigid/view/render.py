"""The scene: the body's mesh, a checkered floor and the wire box (or a grid), a light, a camera.

The engine never imports ``ti.ui``; this module copies what it draws into ndarrays of
its own (the meshes' world vertices from ``sim.surface_positions()``, their triangles
from ``sim.model.faces_np``, floor tiles, box edges, grid), as Taichi's
``mass_spring_3d_ggui.py`` does. The picture is drawn by ``raster.Rasterizer``
(GGUI's 3D scene grows without bound on Mesa's lavapipe: see raster.py); a
window shows it with GGUI's ``canvas.set_image``, a recording reads it directly
(no window, so no Vulkan). One shown ``SceneRenderer`` per process: GGUI keeps one window.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import taichi as ti

from ..engine.arrays import upload
from ..errors import UserError
from .camera import SceneCamera
from .panel import PANEL_TITLE
from .planes import plane_drawing
from .raster import Rasterizer
from .raster_data import closed_and_outward, vec3_array
from .shadow import ContactShadows
from .vulkan import INSTALL_HINT, require_vulkan

BACKGROUND = (1.0, 1.0, 1.0)
BODY_COLOR = (0.93, 0.47, 0.18)
SLEEP_GREY = np.array([0.62, 0.62, 0.62])  # a sleeping body's colour is halfway to this
STATIC_COLOR = (0.70, 0.71, 0.74)
BOX_COLOR = (0.25, 0.3, 0.4)
TILE_COLORS = ((0.86, 0.87, 0.9), (0.74, 0.76, 0.8))
FLOOR_TILES = 8  # per side
GRID_COLOR = (0.72, 0.74, 0.78)
SPRING_COLOR = (0.85, 0.1, 0.1)
SCENE_SPRING_COLOR = (0.15, 0.15, 0.2)  # a scene's [[spring]]s (the grab's is SPRING_COLOR)
GRID_HALF_WIDTH, GRID_STEP = 2.0, 0.25  # m: without walls, lines every 25 cm on the floor plane, 4 m across
AMBIENT, LIGHT = (0.35, 0.35, 0.35), ((2.5, 4.0, 3.5), (0.75, 0.75, 0.75))


class SceneRenderer:
    """Draws one simulator's scene into a picture; shows it in a GGUI window unless ``offscreen``."""

    def __init__(self, sim, resolution=(1280, 720), offscreen=False, title="Rigid body",
                 fps_limit=1000, camera=None):
        """``camera``: a camera.CameraSpec (a scene's [camera] table, --camera); None frames the scene."""
        size = tuple(int(r) for r in resolution)
        self.window = self.canvas = None
        if not offscreen:
            require_vulkan("the window")
            self._imgui_ini = Path("imgui.ini").resolve()  # see close()
            try:
                # No vsync: fps_limit paces the frames (lavapipe's vsync under Xvfb costs time every frame)
                self.window = ti.ui.Window(title, size, vsync=False, show_window=True, fps_limit=fps_limit)
            except RuntimeError as err:  # a Vulkan the probe could not see through
                raise UserError(f"GGUI could not start ({err}); {INSTALL_HINT}") from None
            self.canvas = self.window.get_canvas()
        self.sim = sim
        self.raster = Rasterizer(*size, window=not offscreen)
        self.camera = SceneCamera(sim, camera, aspect=size[0] / size[1])
        self.orbit = self.camera.orbit  # the mouse orbits it; follow moves its target
        self.wireframe = False
        self.spring = None  # (from, to): the mouse's grab, drawn as a line (grab.py)
        self._spring_line = ti.Vector.ndarray(3, ti.f32, shape=2)
        self._scene_springs = ti.Vector.ndarray(3, ti.f32, shape=2 * len(sim.springs)) if sim.springs else None
        self._build_box(float(sim.params.floor), float(sim.params.wall))
        self.planes = plane_drawing(sim)  # [[plane]] tables (planes.py)
        m = sim.model
        self.surface = ti.Vector.ndarray(3, ti.f32, shape=max(m.num_surface, 1))
        self.indices = ti.ndarray(ti.i32, shape=max(3 * m.num_faces, 3))
        if m.num_faces:
            upload(self.indices, m.faces_np.reshape(-1))
        # Closed meshes wound outwards (the assets) skip their back faces: half the triangles.
        self.cull_back = bool(m.num_faces) and closed_and_outward(
            np.concatenate(m.surfaces_np), m.faces_np, m.surface_body_np[m.faces_np[:, 0]])
        self.particles = ti.Vector.ndarray(3, ti.f32, shape=m.num_particles)
        self.vertex_colors = self.particle_colors = None
        self.grey_sleepers = True  # sleeping bodies (rigid.engine.sleep) drawn greyer; the panel toggles it
        self._shown_asleep = None
        if sim.many:  # each body its own colour (body_palette)
            self.palette = body_palette(m.num_bodies)
            self.palette[m.static_np] = STATIC_COLOR  # [[static]] meshes: the scenery, not a body's hue
            self.vertex_colors = vec3_array(self.palette[m.surface_body_np]) if m.num_surface else None
            self.particle_colors = vec3_array(self.palette[sim.particle_bodies()])
        # Under each body a soft shadow on the floor (shadow.py); none without walls (no floor drawn).
        self.shadows = None
        if sim.params.walls:
            points = np.concatenate(m.surfaces_np) if m.num_faces else m.r0_np[m.slot_of]
            counts = np.bincount(m.surface_body_np, minlength=m.num_bodies) if m.num_faces else m.body_count_np
            self.shadows = ContactShadows(m.num_bodies, float(sim.params.floor), float(sim.params.wall), points, counts)

    def _build_box(self, floor: float, wall: float) -> None:
        """Floor tiles (two triangles each, own vertices so colours stay flat) and 12 box edges."""
        n = FLOOR_TILES
        edges = np.linspace(-wall, wall, n + 1)
        vertices, colors = [], []
        for i in range(n):
            for k in range(n):
                x0, x1, z0, z1 = edges[i], edges[i + 1], edges[k], edges[k + 1]
                quad = [(x0, floor, z0), (x1, floor, z0), (x1, floor, z1),
                        (x0, floor, z0), (x1, floor, z1), (x0, floor, z1)]
                vertices += quad
                colors += [TILE_COLORS[(i + k) % 2]] * 6
        self.floor_vertices = vec3_array(np.array(vertices))
        self.floor_colors = vec3_array(np.array(colors))
        # Given normals: the floor is flat.
        self.floor_normals = vec3_array(np.tile([0.0, 1.0, 0.0], (len(vertices), 1)))
        top = floor + 2.0 * wall
        corners = [(-wall, wall), (wall, wall), (wall, -wall), (-wall, -wall)]
        lines = []
        for j, (x, z) in enumerate(corners):
            nx, nz = corners[(j + 1) % 4]
            lines += [(x, floor, z), (nx, floor, nz), (x, top, z), (nx, top, nz), (x, floor, z), (x, top, z)]
        self.box_lines = vec3_array(np.array(lines))
        ticks = np.arange(-GRID_HALF_WIDTH, GRID_HALF_WIDTH + 1e-9, GRID_STEP)
        grid = [[(t, floor, -GRID_HALF_WIDTH), (t, floor, GRID_HALF_WIDTH)] for t in ticks]
        grid += [[(-GRID_HALF_WIDTH, floor, t), (GRID_HALF_WIDTH, floor, t)] for t in ticks]
        self.grid_lines = vec3_array(np.array(grid).reshape(-1, 3))

    def _colour_sleepers(self) -> None:
        """Each body's colour, halfway to grey while it sleeps (if grey_sleepers); the colour
        fields are rewritten only when the set of sleepers changes."""
        sim, m = self.sim, self.sim.model
        asleep = sim.asleep() if self.grey_sleepers else np.zeros(m.num_bodies, bool)
        if self._shown_asleep is not None and np.array_equal(asleep, self._shown_asleep):
            return
        self._shown_asleep = asleep
        colours = np.where(asleep[:, None], 0.5 * self.palette + 0.5 * SLEEP_GREY, self.palette)
        if self.vertex_colors is not None:
            upload(self.vertex_colors, colours[m.surface_body_np])
        upload(self.particle_colors, colours[sim.particle_bodies()])

    def draw(self) -> None:
        """Draw this frame's scene into the picture (and the window's canvas, if shown)."""
        sim, raster = self.sim, self.raster
        if sim.many:
            self._colour_sleepers()
        self.camera.update()
        raster.begin(self.orbit.position(), self.orbit.target, fov_deg=self.orbit.fov, light=LIGHT,
                     ambient=AMBIENT, background=BACKGROUND)
        if sim.params.walls:
            raster.mesh(self.floor_vertices, normals=self.floor_normals, per_vertex_color=self.floor_colors,
                        two_sided=True, receives_shadow=self.shadows is not None)
            raster.lines(self.box_lines, width=2.0, color=BOX_COLOR)
        else:  # free flight: a grid on the floor plane to see motion against
            raster.lines(self.grid_lines, width=1.0, color=GRID_COLOR)
        if self.planes is not None:
            self.planes.draw(raster)
        if sim.model.num_faces:
            upload(self.surface, sim.surface_positions())
            raster.mesh(self.surface, self.indices, color=BODY_COLOR, two_sided=True, cull_back=self.cull_back,
                        show_wireframe=self.wireframe, per_vertex_color=self.vertex_colors)
        else:  # a point cloud: draw the particles
            upload(self.particles, sim.particle_positions())
            raster.particles(self.particles, radius=0.015, color=BODY_COLOR,
                             per_vertex_color=self.particle_colors)
        if self._scene_springs is not None:  # the scene's springs, as lines between their ends
            upload(self._scene_springs, sim.spring_ends())
            raster.lines(self._scene_springs, width=2.0, color=SCENE_SPRING_COLOR)
        if self.spring is not None:
            upload(self._spring_line, self.spring)
            raster.lines(self._spring_line, width=2.5, color=SPRING_COLOR)
        if self.shadows is not None and sim.params.walls:
            self.shadows.update(sim.state.x, sim.state.R)  # read on the device
        raster.finish(self.shadows if sim.params.walls else None)
        if self.canvas is not None:
            self.canvas.set_image(raster.image)

    def read_rgba(self) -> np.ndarray:
        """The drawn frame (the scene, without the window's panel) as (H, W, 4) uint8 RGBA, top row first."""
        return self.raster.read_rgba()

    def close(self) -> None:
        """Destroy the window, if any (GGUI allows a new one afterwards in the same process)."""
        if self.window is not None:
            self.window.destroy()
            _remove_our_imgui_ini(self._imgui_ini)


def _remove_our_imgui_ini(path: Path) -> None:
    """imgui saves panel layouts to ./imgui.ini; ours are placed in code, so the file is litter.

    Removed only when it names no window but ours: another program's layout stays.
    """
    try:
        sections = [line for line in path.read_text().splitlines() if line.startswith("[")]
    except (OSError, UnicodeDecodeError):
        return
    if all(line in IMGUI_SECTIONS for line in sections):
        path.unlink(missing_ok=True)


IMGUI_SECTIONS = {"[Window][Debug##Default]", f"[Window][{PANEL_TITLE}]"}


def body_palette(num_bodies: int) -> np.ndarray:
    """(B, 3) RGB in [0, 1]: distinct, saturated colours (golden-ratio hues), the first one orange."""
    import colorsys

    hues = (0.07 + 0.618034 * np.arange(num_bodies)) % 1.0
    return np.array([colorsys.hsv_to_rgb(h, 0.75, 0.92) for h in hues])
