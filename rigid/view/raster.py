"""A small software renderer in Taichi kernels: triangles, lines and particles with a depth test.

Why not GGUI's 3D scene: on Mesa's lavapipe 22.3 (Debian 12's software Vulkan) every draw of
``scene.mesh``, ``scene.particles`` or ``scene.lines`` keeps ~100-300 KB until the window is
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
"""
# (no "from __future__ import annotations": Taichi reads the kernels' annotations as objects)

import math

import numpy as np
import taichi as ti

from .raster_data import Triangles, VertexNormals
from .raster_edges import column_span as _column_span, edge as _edge

NEAR = 0.05  # m: primitives with a vertex nearer the eye than this are skipped
LINE_BIAS = 1e-3  # lines are drawn this fraction of their depth nearer, to win over the face under them
EMPTY = 1 << 62  # a pixel's key before any triangle covers it
# Triangle kinds. RECEIVER: lit two-sided and shadowed; FRONT: lit, skipped where it faces away.
CULLED, FLAT, LIT, LIT_TWO_SIDED, RECEIVER, FRONT = 0, 1, 2, 3, 4, 5
WIRE_COLOR = (0.15, 0.15, 0.15)
vec3 = ti.types.vector(3, ti.f32)


@ti.data_oriented
class Rasterizer:
    def __init__(self, width: int, height: int, capacity: int = 4096, window: bool = False):
        """``window``: the picture goes to GGUI's canvas (``image``) only, not to ``rgba``
        (``read_rgba`` then converts ``image``: for a screenshot); else to ``rgba`` only."""
        self.width, self.height = int(width), int(height)
        self.window = bool(window)
        self.image = ti.Vector.field(4, ti.u8, shape=(self.width, self.height))  # for canvas.set_image
        self.rgba = ti.field(ti.u32, shape=(self.height, self.width))  # the same, top row first, for files
        self.key = ti.field(ti.i64, shape=(self.width, self.height))
        # eye, right, up, forward (unit rows); light position, colour; ambient; background; (focal px, 0, 0)
        self.cam = ti.Vector.field(3, ti.f32, shape=9)
        self.count = 0  # triangles queued this frame
        self.tris = Triangles(capacity)
        self._normals = VertexNormals()
        self._clear_keys()

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
        self.cam.from_numpy(np.asarray(rows, np.float32))
        self.count = 0

    def mesh(self, vertices, indices=None, normals=None, color=(0.5, 0.5, 0.5), per_vertex_color=None,
             two_sided=False, show_wireframe=False, receives_shadow=False, cull_back=False) -> None:
        """Triangles ``indices`` (3 per triangle; None: vertices 3t, 3t+1, 3t+2) of a vec3 field.

        The arguments mean what they mean for GGUI's ``scene.mesh``. Normals: the ``normals``
        field if given, else each vertex's average of its faces' normals (smooth shading, summed
        in a fixed order), else the face's own. ``show_wireframe`` adds the edges.
        """
        n = (indices.shape[0] if indices is not None else vertices.shape[0]) // 3
        if normals is None and indices is not None:
            normals = self._normals.of(vertices, indices)
        base = self._reserve(n)
        self._emit_mesh(self.tris, base, n, vertices, _or0(indices), _or0(normals), _or0(per_vertex_color),
                        vec3(*color), RECEIVER if receives_shadow else FRONT if cull_back
                        else LIT_TWO_SIDED if two_sided else LIT)
        if show_wireframe:
            base = self._reserve(6 * n)
            self._emit_edges(self.tris, base, n, vertices, _or0(indices), self._line_half_width(1.0), vec3(WIRE_COLOR))

    def lines(self, vertices, width=2.0, color=(0.3, 0.3, 0.3)) -> None:
        """Segments (vertices 2i, 2i+1) of a vec3 field, ``width`` pixels at 720 rows (scaled)."""
        n = vertices.shape[0] // 2
        base = self._reserve(2 * n)
        self._emit_lines(self.tris, base, n, vertices, self._line_half_width(width), vec3(*color))

    def particles(self, centers, radius, color=(0.5, 0.5, 0.5), per_vertex_color=None) -> None:
        """Each centre as a shaded disc of world radius ``radius`` facing the eye (as ``scene.particles``)."""
        n = centers.shape[0]
        base = self._reserve(8 * n)
        self._emit_particles(self.tris, base, n, centers, float(radius), vec3(*color), _or0(per_vertex_color))

    def finish(self, shadows=None) -> None:
        """Rasterise the queued triangles into ``image`` (and clear the depth keys for the next frame);
        ``shadows`` (shadow.ContactShadows) darkens the triangles drawn with ``receives_shadow``."""
        self._raster(self.tris, self.count)
        self._resolve(self.tris, _or0(shadows), self.window)

    def read_rgba(self) -> np.ndarray:
        """The picture as (H, W, 4) uint8 RGBA, top row first, contiguous (a new array)."""
        if self.window:
            return np.ascontiguousarray(self.image.to_numpy().transpose(1, 0, 2)[::-1])
        return self.rgba.to_numpy().view(np.uint8).reshape(self.height, self.width, 4)

    # ---- storage ----------------------------------------------------------------------------
    def _reserve(self, n: int) -> int:
        base = self.count
        if base + n > self.tris.capacity:
            self.tris = Triangles(max(2 * self.tris.capacity, base + n), old=self.tris, keep=base)
        self.count += n
        return base

    def _line_half_width(self, width: float) -> float:
        return 0.5 * max(1.0, width * self.height / 720.0)

    # ---- kernels: primitives in -------------------------------------------------------------
    @ti.func
    def _project(self, tris: ti.template(), p, slot: ti.i32, bias: ti.f32):
        """Write world point p's screen x, y, depth key and 1/distance to vertex ``slot``; False if too near."""
        rel = p - self.cam[0]
        dist = rel.dot(self.cam[3]) * (1.0 - bias)
        ok = dist > NEAR
        q = 1.0 / ti.max(dist, NEAR)
        f = self.cam[8][0]
        screen = ti.Vector([0.5 * self.width + f * rel.dot(self.cam[1]) * q,
                            0.5 * self.height + f * rel.dot(self.cam[2]) * q, 1.0 - NEAR * q, q])
        tris.vs[slot] = ti.cast(screen, ti.f32)  # (literals are f64 under --fp64: cast where stored)
        tris.vp[slot] = ti.cast(p, ti.f32)
        return ok

    @ti.kernel
    def _emit_mesh(self, tris: ti.template(), base: ti.i32, n: ti.i32, verts: ti.template(), idx: ti.template(),
                   nrm: ti.template(), pvc: ti.template(), color: vec3, kind: ti.i32):
        for t in range(n):
            ok = True
            ids = ti.Vector([3 * t, 3 * t + 1, 3 * t + 2])
            if ti.static(idx != 0):
                ids = ti.Vector([idx[3 * t], idx[3 * t + 1], idx[3 * t + 2]])
            p0, p1, p2 = ti.cast(verts[ids[0]], ti.f32), ti.cast(verts[ids[1]], ti.f32), ti.cast(verts[ids[2]], ti.f32)
            face = (p1 - p0).cross(p2 - p0).normalized(1e-20)
            for k in ti.static(range(3)):
                slot = 3 * (base + t) + k
                ok = self._project(tris, ti.cast(verts[ids[k]], ti.f32), slot, 0.0) and ok
                tris.vn[slot] = ti.cast(face, ti.f32)
                if ti.static(nrm != 0):
                    tris.vn[slot] = ti.cast(nrm[ids[k]], ti.f32)
                tris.vc[slot] = color
                if ti.static(pvc != 0):
                    tris.vc[slot] = ti.cast(pvc[ids[k]], ti.f32)
            tris.kind[base + t] = kind if ok else CULLED

    @ti.func
    def _segment(self, tris: ti.template(), tri: ti.i32, p0, p1, half: ti.f32, color):
        """Segment p0-p1 as a screen-space quad (two flat triangles from ``tri`` on), nudged nearer."""
        s = 3 * tri
        ok = self._project(tris, p0, s, LINE_BIAS) and self._project(tris, p1, s + 2, LINE_BIAS)
        a, b = tris.vs[s], tris.vs[s + 2]
        d = ti.Vector([b[0] - a[0], b[1] - a[1]])
        ok = ok and d.norm() > 1e-6
        side = ti.Vector([-d[1], d[0]]).normalized(1e-20) * half
        offset = ti.Vector([side[0], side[1], 0.0, 0.0])
        corners = [a - offset, a + offset, b + offset, b - offset]
        for k in ti.static(range(3)):  # (a-, a+, b+) and (a-, b+, b-)
            tris.vs[s + k] = ti.cast(corners[k], ti.f32)
            tris.vs[s + 3 + k] = ti.cast(corners[(0, 2, 3)[k]], ti.f32)
        for k in ti.static(range(6)):
            tris.vc[s + k] = color
        tris.kind[tri] = FLAT if ok else CULLED
        tris.kind[tri + 1] = FLAT if ok else CULLED

    @ti.kernel
    def _emit_lines(self, tris: ti.template(), base: ti.i32, n: ti.i32, verts: ti.template(), half: ti.f32,
                    color: vec3):
        for i in range(n):
            p0, p1 = ti.cast(verts[2 * i], ti.f32), ti.cast(verts[2 * i + 1], ti.f32)
            self._segment(tris, base + 2 * i, p0, p1, half, color)

    @ti.kernel
    def _emit_edges(self, tris: ti.template(), base: ti.i32, n: ti.i32, verts: ti.template(), idx: ti.template(),
                    half: ti.f32, color: vec3):
        for t in range(n):
            ids = ti.Vector([3 * t, 3 * t + 1, 3 * t + 2])
            if ti.static(idx != 0):
                ids = ti.Vector([idx[3 * t], idx[3 * t + 1], idx[3 * t + 2]])
            for k in ti.static(range(3)):
                self._segment(tris, base + 6 * t + 2 * k, ti.cast(verts[ids[k]], ti.f32),
                              ti.cast(verts[ids[(k + 1) % 3]], ti.f32), half, color)

    @ti.kernel
    def _emit_particles(self, tris: ti.template(), base: ti.i32, n: ti.i32, centers: ti.template(), radius: ti.f32,
                        color: vec3, pvc: ti.template()):
        for i in range(n):
            c = ti.cast(centers[i], ti.f32)
            toward_eye = -self.cam[3]
            rgb = color
            if ti.static(pvc != 0):
                rgb = ti.cast(pvc[i], ti.f32)
            for k in ti.static(range(8)):  # a fan of 8 triangles; normals bend outwards at the rim
                tri = base + 8 * i + k
                s = 3 * tri
                ok = self._project(tris, c, s, 0.0)
                tris.vn[s] = ti.cast(toward_eye, ti.f32)
                for j in ti.static(range(2)):
                    angle = 2.0 * math.pi * (k + j) / 8.0
                    rim = ti.cos(angle) * self.cam[1] + ti.sin(angle) * self.cam[2]
                    ok = self._project(tris, c + radius * rim, s + 1 + j, 0.0) and ok
                    tris.vn[s + 1 + j] = ti.cast(rim, ti.f32)
                for j in ti.static(range(3)):
                    tris.vc[s + j] = rgb
                tris.kind[tri] = LIT if ok else CULLED

    # ---- kernels: pixels out ----------------------------------------------------------------
    @ti.kernel
    def _clear_keys(self):
        for x, y in self.key:
            self.key[x, y] = ti.i64(EMPTY)

    @ti.kernel
    def _raster(self, tris: ti.template(), n: ti.i32):
        for t in range(n):
            if tris.kind[t] != CULLED:
                a, b, c = tris.vs[3 * t], tris.vs[3 * t + 1], tris.vs[3 * t + 2]
                area = _edge(a, b, c[0], c[1])
                if ti.abs(area) > 1e-9 and (area > 0 or tris.kind[t] != FRONT):  # FRONT: counter-clockwise only
                    sign = 1.0 if area > 0 else -1.0
                    x0 = ti.max(0, ti.cast(ti.floor(ti.min(a[0], b[0], c[0])), ti.i32))
                    x1 = ti.min(self.width - 1, ti.cast(ti.ceil(ti.max(a[0], b[0], c[0])), ti.i32))
                    y0 = ti.max(0, ti.cast(ti.floor(ti.min(a[1], b[1], c[1])), ti.i32))
                    y1 = ti.min(self.height - 1, ti.cast(ti.ceil(ti.max(a[1], b[1], c[1])), ti.i32))
                    for x in range(x0, x1 + 1):
                        ys, ye = _column_span(a, b, c, sign, x + 0.5, y0, y1)
                        for y in range(ys, ye + 1):
                            px, py = x + 0.5, y + 0.5
                            w0 = sign * _edge(b, c, px, py)
                            w1 = sign * _edge(c, a, px, py)
                            w2 = sign * _edge(a, b, px, py)
                            if w0 >= 0 and w1 >= 0 and w2 >= 0:
                                depth = (w0 * a[2] + w1 * b[2] + w2 * c[2]) / (sign * area)
                                bits = ti.cast(ti.bit_cast(ti.cast(ti.max(depth, 0.0), ti.f32), ti.i32), ti.i64)
                                ti.atomic_min(self.key[x, y], (bits << 32) | ti.cast(t, ti.i64))

    @ti.kernel
    def _resolve(self, tris: ti.template(), shadows: ti.template(), window: ti.template()):
        eye, light, light_color, ambient, background = self.cam[0], self.cam[4], self.cam[5], self.cam[6], self.cam[7]
        for x, y in self.key:
            key = self.key[x, y]
            rgb = background * 1.0  # in the default float type (f64 under --fp64), like what follows
            if key != ti.i64(EMPTY):
                t = ti.cast(key & ti.i64(0xFFFFFFFF), ti.i32)
                a, b, c = tris.vs[3 * t], tris.vs[3 * t + 1], tris.vs[3 * t + 2]
                px, py = x + 0.5, y + 0.5
                w = ti.Vector([_edge(b, c, px, py) * a[3], _edge(c, a, px, py) * b[3], _edge(a, b, px, py) * c[3]])
                w /= w.sum() if ti.abs(w.sum()) > 1e-30 else 1.0  # perspective-correct barycentrics
                rgb = w[0] * tris.vc[3 * t] + w[1] * tris.vc[3 * t + 1] + w[2] * tris.vc[3 * t + 2]
                if tris.kind[t] >= LIT:
                    normal = (w[0] * tris.vn[3 * t] + w[1] * tris.vn[3 * t + 1] + w[2] * tris.vn[3 * t + 2])
                    p = w[0] * tris.vp[3 * t] + w[1] * tris.vp[3 * t + 1] + w[2] * tris.vp[3 * t + 2]
                    normal = normal.normalized(1e-20)
                    if (tris.kind[t] == LIT_TWO_SIDED or tris.kind[t] == RECEIVER) and normal.dot(eye - p) < 0:
                        normal = -normal
                    diffuse = ti.max(0.0, normal.dot((light - p).normalized(1e-20)))
                    rgb = rgb * (ambient + light_color * diffuse)
                    if ti.static(shadows != 0):
                        if tris.kind[t] == RECEIVER:
                            rgb = rgb * shadows.at(p)
            byte = ti.cast(ti.min(ti.max(rgb, 0.0), 1.0) * 255.0 + 0.5, ti.u32)
            if ti.static(window):  # one picture written, the one that is read
                self.image[x, y] = ti.Vector([byte[0], byte[1], byte[2], 255], ti.u8)
            else:
                self.rgba[self.height - 1 - y, x] = byte[0] | (byte[1] << 8) | (byte[2] << 16) | ti.u32(0xFF000000)
            self.key[x, y] = ti.i64(EMPTY)


def _or0(field):
    """Taichi templates take no None: 0 stands for an absent field (tested with ti.static)."""
    return 0 if field is None else field
