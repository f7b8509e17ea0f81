"""Grab a body with the mouse: left-press on it, drag, release.

The press casts a ray from the eye through the cursor; the nearest triangle of the drawn meshes
it hits (or, for point clouds, the particle nearest the ray) names the body, and the body's
particle nearest the hit point is held (``Simulator.grab``: a damped spring from that particle
to a target, a particle force through TODO 3 and 4, rigid/engine/grab.py). While the button is
down the target is where the cursor's ray crosses the plane through the grabbed point facing
the camera (as in MuJoCo's viewer), so dragging moves the body in the picture's plane: it
swings, collides and spins. Releasing lets go. A press on the control panel is the panel's.
"""
from __future__ import annotations

import math

import numpy as np

from .panel import PANEL_PLACE

# The panel's rectangle in cursor coordinates ([0, 1]², y up), from panel.py's PANEL_PLACE.
PANEL_RECT = (PANEL_PLACE[0], 1.0 - PANEL_PLACE[1] - PANEL_PLACE[3], PANEL_PLACE[0] + PANEL_PLACE[2], 1.0 - PANEL_PLACE[1])
POINT_PICK = 0.04  # m: a point cloud's particle is picked if the ray passes this close (plus its radius)


class MouseGrab:
    def __init__(self, sim, orbit, size, panel_rect=PANEL_RECT):
        self.sim, self.orbit, self.size, self.panel_rect = sim, orbit, tuple(size), panel_rect
        self.particle = None  # the particle held (mesh files' order), None when nothing is
        self.plane_point = self.plane_normal = self.target = None
        self._was_down = False
        self._ignored = False  # this press began on the panel

    # -- the camera's rays --------------------------------------------------------------------
    def ray(self, cursor) -> tuple[np.ndarray, np.ndarray]:
        """(eye, unit direction) of the ray through cursor (u, v) in [0, 1]², v up."""
        eye = np.asarray(self.orbit.position(), float)
        forward = np.asarray(self.orbit.target, float) - eye
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, [0.0, 1.0, 0.0])
        right /= np.linalg.norm(right)
        up = np.cross(right, forward)
        tan = math.tan(math.radians(self.orbit.fov) / 2.0)
        aspect = self.size[0] / self.size[1]
        d = forward + (2.0 * cursor[0] - 1.0) * tan * aspect * right + (2.0 * cursor[1] - 1.0) * tan * up
        return eye, d / np.linalg.norm(d)

    # -- once per drawn frame -----------------------------------------------------------------
    def track(self, cursor, down: bool) -> bool:
        """Read the cursor and the left button; True while a body is held (the state is then
        changed by hand: the blow-up check measures energy from each such frame)."""
        if self.particle is not None and self.sim.grabbed != self.particle:
            self.particle = None  # a reset let go
        pressed, released = down and not self._was_down, self._was_down and not down
        self._was_down = down
        if pressed:
            self._ignored = self._on_panel(cursor)
            if not self._ignored:
                self.press(cursor)
        elif released:
            self.release()
        elif down and self.particle is not None:
            self.drag(cursor)
        return self.particle is not None

    def press(self, cursor) -> int | None:
        """Pick what is under the cursor and hold it; the particle held, or None (a miss)."""
        eye, d = self.ray(cursor)
        hit = self.pick(eye, d)
        if hit is None:
            return None
        particle, point = hit
        self.particle = particle
        self.plane_point, self.plane_normal = point, -d
        self.target = point
        self.sim.grab(particle, point)
        return particle

    def drag(self, cursor) -> None:
        """Move the target to where the cursor's ray meets the grab plane."""
        eye, d = self.ray(cursor)
        denom = float(d @ self.plane_normal)
        if abs(denom) < 1e-9:
            return
        t = float((self.plane_point - eye) @ self.plane_normal) / denom
        if t <= 0:
            return
        self.target = eye + t * d
        self.sim.grab(self.particle, self.target)

    def release(self) -> None:
        if self.particle is not None:
            self.sim.release()
        self.particle = self.target = None

    def spring(self):
        """(grabbed particle's position, target) to draw, or None."""
        if self.particle is None or self.target is None:
            return None
        return self.sim.particle_positions()[self.particle], self.target

    # -- picking ------------------------------------------------------------------------------
    def pick(self, eye, d):
        """(particle, hit point) of the body the ray hits first, or None."""
        sim, m = self.sim, self.sim.model
        positions = sim.particle_positions()
        if m.num_faces:
            t, face = _first_hit(np.asarray(sim.surface_positions(), np.float64), m.faces_np, eye, d)
            if face is None:
                return None
            point = eye + t * d
            body = int(m.surface_body_np[m.faces_np[face, 0]])
        else:
            rel = positions - eye
            along = rel @ d
            miss = np.linalg.norm(rel - along[:, None] * d, axis=1)
            near = (along > 0) & (miss < POINT_PICK + m.radius_np[sim.particle_bodies()])
            if not near.any():
                return None
            i = int(np.flatnonzero(near)[np.argmin(along[near])])
            point, body = positions[i], int(sim.particle_bodies()[i])
        start = int(m.body_start_np[body])
        mine = positions[start:start + int(m.body_count_np[body])]
        particle = start + int(np.argmin(((mine - point) ** 2).sum(axis=1)))
        return particle, point

    def _on_panel(self, cursor) -> bool:
        x0, y0, x1, y1 = self.panel_rect
        return x0 <= cursor[0] <= x1 and y0 <= cursor[1] <= y1


def _first_hit(vertices, faces, eye, d):
    """Möller-Trumbore over all triangles at once: (t, face) of the nearest hit, or (inf, None)."""
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    e1, e2 = b - a, c - a
    p = np.cross(d, e2)
    det = (e1 * p).sum(axis=1)
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = eye - a
    u = (s * p).sum(axis=1) * inv
    q = np.cross(s, e1)
    v = (q @ d) * inv
    t = (e2 * q).sum(axis=1) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
    if not hit.any():
        return math.inf, None
    face = int(np.flatnonzero(hit)[np.argmin(t[hit])])
    return float(t[face]), face
