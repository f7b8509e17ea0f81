"""The rasteriser's edge functions (raster.py): a triangle's edges as linear functions of the
pixel centre, and the rows of a column that the three of them allow.

Edge function of (a, b) at p: twice the signed area of (a, b, p), positive on its left (screen
x right, y up); a pixel centre is inside a triangle where all three edges' functions, times
the triangle's orientation, are >= 0.
"""
# (no "from __future__ import annotations": Taichi reads the funcs' annotations as objects)

import taichi as ti


@ti.func
def column_span(a, b, c, sign, px, y0, y1):
    """The rows y0..y1 of column px where the triangle may cover a pixel centre: each edge's
    function is linear in py along the column, w = k py + m >= 0, which bounds py from one side.
    Widened by a row at each end, so the exact test in _raster decides every pixel (the same
    pixels as the whole bounding box, a big triangle's empty half skipped)."""
    lo, hi = y0 + 0.5, y1 + 0.5
    for e in ti.static(range(3)):
        p, q = (b, c, a)[e], (c, a, b)[e]
        k = sign * (q[0] - p[0])
        m = sign * (-(q[0] - p[0]) * p[1] - (q[1] - p[1]) * (px - p[0]))
        if k > 0:
            lo = ti.max(lo, -m / k)
        elif k < 0:
            hi = ti.min(hi, -m / k)
        elif m < 0:
            hi = lo - 2.0  # parallel to the column and outside it: no row
    start = ti.max(y0, ti.cast(ti.ceil(lo - 0.5), ti.i32) - 1)
    end = ti.min(y1, ti.cast(ti.floor(hi - 0.5), ti.i32) + 1)
    return start, end


@ti.func
def edge(a, b, px, py):
    """Twice the signed area of (a, b, p) in screen space."""
    return (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0])
