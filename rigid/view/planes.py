"""The scene's [[plane]] tables drawn: each a square of the plane, 2 x 2 m, around the point
of the plane nearest the world's origin (the box's middle column), two triangles with a flat
normal and an outline, so a ramp, a tilted
floor or a ceiling shows where bodies meet it. The box is drawn by render.py as before; the
[[static]] meshes are bodies of the model and are drawn with them.
"""
from __future__ import annotations

import numpy as np

from .raster_data import vec3_array

PLANE_COLOR = (0.62, 0.7, 0.62)
EDGE_COLOR = (0.3, 0.38, 0.3)
HALF_SIZE = 1.0  # m


def plane_square(point, normal, half: float = HALF_SIZE) -> np.ndarray:
    """(4, 3) corners of the square of side 2·half on the plane through ``point``, centred on
    the plane's point nearest the origin."""
    n = np.asarray(normal, np.float64)
    n = n / np.linalg.norm(n)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    u = np.cross(n, helper)
    u /= np.linalg.norm(u)
    w = np.cross(n, u)
    p = float(np.dot(n, point)) * n
    return np.array([p + half * (su * u + sw * w) for su, sw in ((-1, -1), (1, -1), (1, 1), (-1, 1))])


class PlaneDrawing:
    """Arrays of the planes' triangles and outlines; ``draw(raster)`` adds them to a frame."""

    def __init__(self, planes):
        tris, normals, lines = [], [], []
        for plane in planes:
            c = plane_square(plane["point"], plane["normal"])
            tris += [c[0], c[1], c[2], c[0], c[2], c[3]]
            normals += [plane["normal"]] * 6
            lines += [c[0], c[1], c[1], c[2], c[2], c[3], c[3], c[0]]
        self.vertices = vec3_array(tris)
        self.normals = vec3_array(normals)
        self.lines = vec3_array(lines)

    def draw(self, raster) -> None:
        raster.mesh(self.vertices, normals=self.normals, color=PLANE_COLOR, two_sided=True)
        raster.lines(self.lines, width=2.0, color=EDGE_COLOR)


def plane_drawing(sim):
    """A PlaneDrawing of the simulator's [[plane]] tables, or None if it has none."""
    planes = getattr(sim.config, "planes", ())
    return PlaneDrawing(planes) if planes else None
