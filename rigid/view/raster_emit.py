"""The rasteriser's primitives in (raster.py): each emit kernel projects a mesh's triangles, a
set of segments or discs into the frame's triangle list, as screen vertices with their world
normals, positions and colours.

Every kernel takes the triangles (``vs``, ``vn``, ``vp``, ``vc``, ``kinds``: raster_data.Triangles),
the camera (``cam``: raster.Rasterizer.begin's rows), the picture's size, where to write (``base``,
``n``), and the primitives: vec3 ndarrays of vertices (f32 or f64), optional indices, normals and
per-vertex colours, each with a flag (``has_*``, compiled in or out) since kernels take no None.
"""
# (no "from __future__ import annotations": Taichi reads the kernels' annotations as objects)

import math

import taichi as ti

NEAR = 0.05  # m: primitives with a vertex nearer the eye than this are skipped
LINE_BIAS = 1e-3  # lines are drawn this fraction of their depth nearer, to win over the face under them
# Triangle kinds. RECEIVER: lit two-sided and shadowed; FRONT: lit, skipped where it faces away.
CULLED, FLAT, LIT, LIT_TWO_SIDED, RECEIVER, FRONT = 0, 1, 2, 3, 4, 5
vec3 = ti.types.vector(3, ti.f32)


@ti.func
def _project(vs: ti.template(), vp: ti.template(), cam: ti.template(), width, height, p, slot: ti.i32,
             bias: ti.f32):
    """Write world point p's screen x, y, depth key and 1/distance to vertex ``slot``; False if too near."""
    rel = p - cam[0]
    dist = rel.dot(cam[3]) * (1.0 - bias)
    ok = dist > NEAR
    q = 1.0 / ti.max(dist, NEAR)
    f = cam[8][0]
    screen = ti.Vector([0.5 * width + f * rel.dot(cam[1]) * q, 0.5 * height + f * rel.dot(cam[2]) * q,
                        1.0 - NEAR * q, q])
    vs[slot] = ti.cast(screen, ti.f32)  # (literals are f64 under --fp64: cast where stored)
    vp[slot] = ti.cast(p, ti.f32)
    return ok


@ti.kernel
def _emit_mesh(vs: ti.types.ndarray(), vn: ti.types.ndarray(), vp: ti.types.ndarray(), vc: ti.types.ndarray(),
               kinds: ti.types.ndarray(), cam: ti.types.ndarray(), width: ti.i32, height: ti.i32, base: ti.i32,
               n: ti.i32, verts: ti.types.ndarray(), idx: ti.types.ndarray(), has_idx: ti.template(),
               nrm: ti.types.ndarray(), has_nrm: ti.template(), pvc: ti.types.ndarray(), has_pvc: ti.template(),
               color: vec3, kind: ti.i32):
    for t in range(n):
        ok = True
        ids = ti.Vector([3 * t, 3 * t + 1, 3 * t + 2])
        if ti.static(has_idx):
            ids = ti.Vector([idx[3 * t], idx[3 * t + 1], idx[3 * t + 2]])
        p0, p1, p2 = ti.cast(verts[ids[0]], ti.f32), ti.cast(verts[ids[1]], ti.f32), ti.cast(verts[ids[2]], ti.f32)
        face = (p1 - p0).cross(p2 - p0).normalized(1e-20)
        for k in ti.static(range(3)):
            slot = 3 * (base + t) + k
            ok = _project(vs, vp, cam, width, height, ti.cast(verts[ids[k]], ti.f32), slot, 0.0) and ok
            vn[slot] = ti.cast(face, ti.f32)
            if ti.static(has_nrm):
                vn[slot] = ti.cast(nrm[ids[k]], ti.f32)
            vc[slot] = color
            if ti.static(has_pvc):
                vc[slot] = ti.cast(pvc[ids[k]], ti.f32)
        kinds[base + t] = kind if ok else CULLED


@ti.func
def _segment(vs: ti.template(), vp: ti.template(), vc: ti.template(), kinds: ti.template(), cam: ti.template(),
             width, height, tri: ti.i32, p0, p1, half: ti.f32, color):
    """Segment p0-p1 as a screen-space quad (two flat triangles from ``tri`` on), nudged nearer."""
    s = 3 * tri
    ok = _project(vs, vp, cam, width, height, p0, s, LINE_BIAS) and \
        _project(vs, vp, cam, width, height, p1, s + 2, LINE_BIAS)
    a, b = vs[s], vs[s + 2]
    d = ti.Vector([b[0] - a[0], b[1] - a[1]])
    ok = ok and d.norm() > 1e-6
    side = ti.Vector([-d[1], d[0]]).normalized(1e-20) * half
    offset = ti.Vector([side[0], side[1], 0.0, 0.0])
    corners = [a - offset, a + offset, b + offset, b - offset]
    for k in ti.static(range(3)):  # (a-, a+, b+) and (a-, b+, b-)
        vs[s + k] = ti.cast(corners[k], ti.f32)
        vs[s + 3 + k] = ti.cast(corners[(0, 2, 3)[k]], ti.f32)
    for k in ti.static(range(6)):
        vc[s + k] = color
    kinds[tri] = FLAT if ok else CULLED
    kinds[tri + 1] = FLAT if ok else CULLED


@ti.kernel
def _emit_lines(vs: ti.types.ndarray(), vn: ti.types.ndarray(), vp: ti.types.ndarray(), vc: ti.types.ndarray(),
                kinds: ti.types.ndarray(), cam: ti.types.ndarray(), width: ti.i32, height: ti.i32, base: ti.i32,
                n: ti.i32, verts: ti.types.ndarray(), half: ti.f32, color: vec3):
    for i in range(n):
        p0, p1 = ti.cast(verts[2 * i], ti.f32), ti.cast(verts[2 * i + 1], ti.f32)
        _segment(vs, vp, vc, kinds, cam, width, height, base + 2 * i, p0, p1, half, color)


@ti.kernel
def _emit_edges(vs: ti.types.ndarray(), vn: ti.types.ndarray(), vp: ti.types.ndarray(), vc: ti.types.ndarray(),
                kinds: ti.types.ndarray(), cam: ti.types.ndarray(), width: ti.i32, height: ti.i32, base: ti.i32,
                n: ti.i32, verts: ti.types.ndarray(), idx: ti.types.ndarray(), has_idx: ti.template(), half: ti.f32,
                color: vec3):
    for t in range(n):
        ids = ti.Vector([3 * t, 3 * t + 1, 3 * t + 2])
        if ti.static(has_idx):
            ids = ti.Vector([idx[3 * t], idx[3 * t + 1], idx[3 * t + 2]])
        for k in ti.static(range(3)):
            _segment(vs, vp, vc, kinds, cam, width, height, base + 6 * t + 2 * k, ti.cast(verts[ids[k]], ti.f32),
                     ti.cast(verts[ids[(k + 1) % 3]], ti.f32), half, color)


@ti.kernel
def _emit_particles(vs: ti.types.ndarray(), vn: ti.types.ndarray(), vp: ti.types.ndarray(), vc: ti.types.ndarray(),
                    kinds: ti.types.ndarray(), cam: ti.types.ndarray(), width: ti.i32, height: ti.i32, base: ti.i32,
                    n: ti.i32, centers: ti.types.ndarray(), radius: ti.f32, color: vec3, pvc: ti.types.ndarray(),
                    has_pvc: ti.template()):
    for i in range(n):
        c = ti.cast(centers[i], ti.f32)
        toward_eye = -cam[3]
        rgb = color
        if ti.static(has_pvc):
            rgb = ti.cast(pvc[i], ti.f32)
        for k in ti.static(range(8)):  # a fan of 8 triangles; normals bend outwards at the rim
            tri = base + 8 * i + k
            s = 3 * tri
            ok = _project(vs, vp, cam, width, height, c, s, 0.0)
            vn[s] = ti.cast(toward_eye, ti.f32)
            for j in ti.static(range(2)):
                angle = 2.0 * math.pi * (k + j) / 8.0
                rim = ti.cos(angle) * cam[1] + ti.sin(angle) * cam[2]
                ok = _project(vs, vp, cam, width, height, c + radius * rim, s + 1 + j, 0.0) and ok
                vn[s + 1 + j] = ti.cast(rim, ti.f32)
            for j in ti.static(range(3)):
                vc[s + j] = rgb
            kinds[tri] = LIT if ok else CULLED
