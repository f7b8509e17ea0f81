"""A small software renderer in Taichi kernels: triangles, lines and particles with a depth test.

Why not GGUI's 3D scene: on Mesa's lavapipe 22.3 (Debian 12's software Vulkan) every draw of
``scene.mesh``, ``scene.particles`` or ``scene.lines`` keeps memory until the window is
destroyed. Lavapipe inlines uniform values into shaders that branch or loop on them (GGUI's
mesh and particle shaders loop to ``point_light_count``): each draw whose uniform buffer
changed clones the shader's NIR under the pipeline and builds a new shader state
(``update_inline_shader_state`` in ``lavapipe/lvp_execute.c``). GGUI 1.7.4 makes a new
renderable with fresh uniform buffers for every draw and keeps its pipelines for the window's
life, so nothing is freed. GGUI's 2D ``canvas.set_image`` uses a small shader that is never inlined and does not grow.
So the scene is drawn here into ``image`` and the window only shows it.

A frame: ``begin`` (camera and light), any number of ``mesh``/``lines``/``particles`` calls
(each copies its primitives, projected, into one triangle list), then ``finish``: each triangle
writes ``depth << 32 | triangle`` into a per-pixel 64-bit atomic minimum (so the result does not
depend on thread order), and each pixel is shaded from the triangle it kept (perspective-correct
interpolation, two-sided diffuse lighting). ``image`` is (W, H) RGBA8, row 0 at the bottom, as
GGUI's ``canvas.set_image`` takes it.

Every array is a Taichi ndarray given to module-level kernels as an argument (the inputs too:
vec3 ndarrays of vertices, normals, colours, an i32 ndarray of indices), so the kernels compile
once per process and element type: a second renderer, a new mesh or a larger triangle list
reuses them (kernels that captured a renderer's fields would compile again for each).
Only the window's ``image`` is a field (``canvas.set_image`` takes fields). The kernels that bring
primitives in are in raster_emit.py; those that make pixels, here.
"""
# (no "from __future__ import annotations": Taichi reads the kernels' annotations as objects)

import functools
import math

import numpy as np
import taichi as ti

from ..engine.arrays import download, upload
from .raster_data import Triangles, VertexNormals
from .raster_edges import column_span as _column_span, edge as _edge
from .raster_emit import (CULLED, FRONT, LIT, LIT_TWO_SIDED, RECEIVER, _emit_edges, _emit_lines, _emit_mesh,
                          _emit_particles, vec3)
from .shadow import shade_at

EMPTY = 1 << 62  # a pixel's key before any triangle covers it
ROW_RUNS = 8  # the pixel loops split each column into this many runs of rows (_resolve)
WIRE_COLOR = (0.15, 0.15, 0.15)


class Rasterizer:
    def __init__(self, width: int, height: int, capacity: int = 4096, window: bool = False):
        """``window``: the picture goes to GGUI's canvas (``image``) only, not to ``rgba``
        (``read_rgba`` then converts ``image``: for a screenshot); else to ``rgba`` only."""
        self.width, self.height = int(width), int(height)
        self.window = bool(window)
        self.image = ti.Vector.field(4, ti.u8, shape=(self.width, self.height)) if window else None  # canvas.set_image
        self.rgba = ti.ndarray(ti.u32, shape=(self.height, self.width))  # the same, top row first, for files
        self.key = ti.ndarray(ti.i64, shape=(self.width, self.height))
        # eye, right, up, forward (unit rows); light position, colour; ambient; background; (focal px, 0, 0)
        self.cam = ti.Vector.ndarray(3, ti.f32, shape=9)
        self.count = 0  # triangles queued this frame
        self.tris = Triangles(capacity)
        self._normals = VertexNormals()
        _clear_keys(self.key)

    # ---- one frame --------------------------------------------------------------------------
    def begin(self, eye, target, up=(0.0, 1.0, 0.0), fov_deg=45.0, light=((2.5, 4.0, 3.5), (0.75,) * 3),
              ambient=(0.35,) * 3, background=(1.0, 1.0, 1.0)) -> None:
        """Start a frame seen from ``eye`` looking at ``target`` (vertical field of view in degrees)."""
        eye, target, up = (np.asarray(v, np.float64) for v in (eye, target, up))
        forward = target - eye
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, up)
        right /= np.linalg.norm(right)
        true_up = np.cross(right, forward)
        focal = 0.5 * self.height / math.tan(math.radians(fov_deg) / 2.0)
        rows = [eye, right, true_up, forward, light[0], light[1], ambient, background, (focal, 0.0, 0.0)]
        upload(self.cam, np.asarray(rows, np.float32))
        self.count = 0

    def mesh(self, vertices, indices=None, normals=None, color=(0.5, 0.5, 0.5), per_vertex_color=None,
             two_sided=False, show_wireframe=False, receives_shadow=False, cull_back=False) -> None:
        """Triangles ``indices`` (3 per triangle; None: vertices 3t, 3t+1, 3t+2) of a vec3 ndarray.

        The arguments mean what they mean for GGUI's ``scene.mesh``. Normals: the ``normals``
        ndarray if given, else each vertex's average of its faces' normals (smooth shading, summed
        in a fixed order), else the face's own. ``show_wireframe`` adds the edges.
        """
        n = (indices.shape[0] if indices is not None else vertices.shape[0]) // 3
        if normals is None and indices is not None:
            normals = self._normals.of(vertices, indices)
        base = self._reserve(n)
        kind = RECEIVER if receives_shadow else FRONT if cull_back else LIT_TWO_SIDED if two_sided else LIT
        _emit_mesh(*self._out(), base, n, vertices, *_optional(indices, "i"), *_optional(normals),
                   *_optional(per_vertex_color), vec3(*color), kind)
        if show_wireframe:
            base = self._reserve(6 * n)
            _emit_edges(*self._out(), base, n, vertices, *_optional(indices, "i"),
                        self._line_half_width(1.0), vec3(WIRE_COLOR))

    def lines(self, vertices, width=2.0, color=(0.3, 0.3, 0.3)) -> None:
        """Segments (vertices 2i, 2i+1) of a vec3 ndarray, ``width`` pixels at 720 rows (scaled)."""
        n = vertices.shape[0] // 2
        base = self._reserve(2 * n)
        _emit_lines(*self._out(), base, n, vertices, self._line_half_width(width), vec3(*color))

    def particles(self, centers, radius, color=(0.5, 0.5, 0.5), per_vertex_color=None) -> None:
        """Each centre as a shaded disc of world radius ``radius`` facing the eye (as ``scene.particles``)."""
        n = centers.shape[0]
        base = self._reserve(8 * n)
        _emit_particles(*self._out(), base, n, centers, float(radius), vec3(*color), *_optional(per_vertex_color))

    def finish(self, shadows=None) -> None:
        """Rasterise the queued triangles into ``image`` (and clear the depth keys for the next frame);
        ``shadows`` (shadow.ContactShadows) darkens the triangles drawn with ``receives_shadow``."""
        t = self.tris
        _raster(t.vs, t.kind, self.key, self.width, self.height, self.count)
        shade, box = (shadows.shade, shadows.box) if shadows is not None else _stand_in("shade")
        _resolve(*t.arrays, self.key, self.cam, self.rgba, self.image if self.window else 0, self.window,
                 shade, box, shadows is not None)

    def read_rgba(self) -> np.ndarray:
        """The picture as (H, W, 4) uint8 RGBA, top row first, contiguous (a new array)."""
        if self.window:
            return np.ascontiguousarray(self.image.to_numpy().transpose(1, 0, 2)[::-1])
        return download(self.rgba).view(np.uint8).reshape(self.height, self.width, 4)

    # ---- storage ----------------------------------------------------------------------------
    def _out(self) -> tuple:
        """What every emit kernel writes and reads: the triangles, the camera, the picture's size."""
        return (*self.tris.arrays, self.cam, self.width, self.height)

    def _reserve(self, n: int) -> int:
        base = self.count
        if base + n > self.tris.capacity:
            self.tris = Triangles(max(2 * self.tris.capacity, base + n), old=self.tris, keep=base)
        self.count += n
        return base

    def _line_half_width(self, width: float) -> float:
        return 0.5 * max(1.0, width * self.height / 720.0)


@functools.cache
def _stand_in(kind: str):
    """One-element ndarrays standing for an absent input (the kernels test a flag, never read them):
    "i" indices, "v" vec3 data, "shade" the shadows' (shade, box)."""
    if kind == "i":
        return ti.ndarray(ti.i32, shape=1)
    if kind == "v":
        return ti.Vector.ndarray(3, ti.f32, shape=1)
    return ti.ndarray(ti.f32, shape=(1, 1)), ti.Vector.ndarray(3, ti.f32, shape=1)


def _optional(array, kind: str = "v"):
    """(array, True), or a stand-in and False: Taichi kernels take no None."""
    return (array, True) if array is not None else (_stand_in(kind), False)


# ---- kernels: pixels out ----------------------------------------------------------------
@ti.func
def _column_run(key: ti.template(), item):
    """Work item ``item`` of a pixel loop over ``key``'s W x ROW_RUNS runs: its column x and
    rows [y0, y1) (ROW_RUNS is a constant, so the division is a shift)."""
    x, run = item // ROW_RUNS, item % ROW_RUNS
    return x, run * key.shape[1] // ROW_RUNS, (run + 1) * key.shape[1] // ROW_RUNS


@ti.kernel
def _clear_keys(key: ti.types.ndarray()):
    for item in range(key.shape[0] * ROW_RUNS):  # as _resolve walks the keys
        x, y0, y1 = _column_run(key, item)
        for y in range(y0, y1):
            key[x, y] = ti.i64(EMPTY)


@ti.kernel
def _raster(vs: ti.types.ndarray(), kinds: ti.types.ndarray(), key: ti.types.ndarray(), width: ti.i32,
            height: ti.i32, n: ti.i32):
    for t in range(n):
        if kinds[t] != CULLED:
            a, b, c = vs[3 * t], vs[3 * t + 1], vs[3 * t + 2]
            area = _edge(a, b, c[0], c[1])
            if ti.abs(area) > 1e-9 and (area > 0 or kinds[t] != FRONT):  # FRONT: counter-clockwise only
                sign = 1.0 if area > 0 else -1.0
                x0 = ti.max(0, ti.cast(ti.floor(ti.min(a[0], b[0], c[0])), ti.i32))
                x1 = ti.min(width - 1, ti.cast(ti.ceil(ti.max(a[0], b[0], c[0])), ti.i32))
                y0 = ti.max(0, ti.cast(ti.floor(ti.min(a[1], b[1], c[1])), ti.i32))
                y1 = ti.min(height - 1, ti.cast(ti.ceil(ti.max(a[1], b[1], c[1])), ti.i32))
                small = y1 - y0 <= 2  # a few rows: test them all (finding the span costs more than it saves)
                for x in range(x0, x1 + 1):
                    ys, ye = y0, y1
                    if not small:
                        ys, ye = _column_span(a, b, c, sign, x + 0.5, y0, y1)
                    for y in range(ys, ye + 1):
                        px, py = x + 0.5, y + 0.5
                        w0 = sign * _edge(b, c, px, py)
                        w1 = sign * _edge(c, a, px, py)
                        w2 = sign * _edge(a, b, px, py)
                        if w0 >= 0 and w1 >= 0 and w2 >= 0:
                            depth = (w0 * a[2] + w1 * b[2] + w2 * c[2]) / (sign * area)
                            bits = ti.cast(ti.bit_cast(ti.cast(ti.max(depth, 0.0), ti.f32), ti.i32), ti.i64)
                            ti.atomic_min(key[x, y], (bits << 32) | ti.cast(t, ti.i64))


@ti.func
def _pixel_colour(vs: ti.template(), vn: ti.template(), vp: ti.template(), vc: ti.template(), kinds: ti.template(),
                  cam: ti.template(), shade: ti.template(), box: ti.template(), shadows: ti.template(), k, x, y):
    """The colour of pixel (x, y) from its depth key k: the background, or the triangle it kept, shaded."""
    eye, light, light_color, ambient, background = cam[0], cam[4], cam[5], cam[6], cam[7]
    rgb = background * 1.0  # in the default float type (f64 under --fp64), like what follows
    if k != ti.i64(EMPTY):
        t = ti.cast(k & ti.i64(0xFFFFFFFF), ti.i32)
        a, b, c = vs[3 * t], vs[3 * t + 1], vs[3 * t + 2]
        px, py = x + 0.5, y + 0.5
        w = ti.Vector([_edge(b, c, px, py) * a[3], _edge(c, a, px, py) * b[3], _edge(a, b, px, py) * c[3]])
        w /= w.sum() if ti.abs(w.sum()) > 1e-30 else 1.0  # perspective-correct barycentrics
        rgb = w[0] * vc[3 * t] + w[1] * vc[3 * t + 1] + w[2] * vc[3 * t + 2]
        if kinds[t] >= LIT:
            normal = (w[0] * vn[3 * t] + w[1] * vn[3 * t + 1] + w[2] * vn[3 * t + 2])
            p = w[0] * vp[3 * t] + w[1] * vp[3 * t + 1] + w[2] * vp[3 * t + 2]
            normal = normal.normalized(1e-20)
            if (kinds[t] == LIT_TWO_SIDED or kinds[t] == RECEIVER) and normal.dot(eye - p) < 0:
                normal = -normal
            diffuse = ti.max(0.0, normal.dot((light - p).normalized(1e-20)))
            rgb = rgb * (ambient + light_color * diffuse)
            if ti.static(shadows):
                if kinds[t] == RECEIVER:
                    rgb = rgb * shade_at(shade, box, p)
    return rgb


@ti.kernel
def _resolve(vs: ti.types.ndarray(), vn: ti.types.ndarray(), vp: ti.types.ndarray(), vc: ti.types.ndarray(),
             kinds: ti.types.ndarray(), key: ti.types.ndarray(), cam: ti.types.ndarray(), rgba: ti.types.ndarray(),
             image: ti.template(), window: ti.template(), shade: ti.types.ndarray(), box: ti.types.ndarray(),
             shadows: ti.template()):
    height = rgba.shape[0]
    # Runs of a column's rows in parallel, each run's rows in a loop: an ndrange over run-time
    # sizes divides to find each pixel's (x, y), a large share of this kernel (ROW_RUNS is a
    # constant: its division is a shift). Not one column each: Taichi's CPU backend hands a loop
    # out 512 iterations at a time, so 640 columns would run as 512 and 128. Not rows in
    # parallel: the keys' reads would then go across theirs.
    for item in range(key.shape[0] * ROW_RUNS):
        x, y0, y1 = _column_run(key, item)
        for y in range(y0, y1):
            rgb = _pixel_colour(vs, vn, vp, vc, kinds, cam, shade, box, shadows, key[x, y], x, y)
            byte = ti.cast(ti.min(ti.max(rgb, 0.0), 1.0) * 255.0 + 0.5, ti.u32)
            if ti.static(window):  # one picture written, the one that is read
                image[x, y] = ti.Vector([byte[0], byte[1], byte[2], 255], ti.u8)
            else:
                rgba[height - 1 - y, x] = byte[0] | (byte[1] << 8) | (byte[2] << 16) | ti.u32(0xFF000000)
            key[x, y] = ti.i64(EMPTY)
