"""An orbit camera: it circles a target point at a distance, driven by the mouse.

GGUI's own ``Camera.track_user_inputs`` flies (WASD and mouse-look), which
loses the box easily; orbiting keeps the box in view. The right mouse button
drags the view round the target, the middle button (or the Up/Down arrows)
zooms; the left button stays with the GUI panel.
"""
from __future__ import annotations

import math

import taichi as ti

MIN_ELEVATION, MAX_ELEVATION = math.radians(-80), math.radians(85)


class OrbitCamera:
    def __init__(self, target=(0.0, -0.35, 0.0), distance=4.6, azimuth_deg=28.0,
                 elevation_deg=20.0, fov_deg=45.0):
        self.target = tuple(target)
        self.distance = distance
        self.azimuth = math.radians(azimuth_deg)  # about +y, 0 looks along −z from +z
        self.elevation = math.radians(elevation_deg)
        self.fov = fov_deg
        self._last_cursor = None

    def position(self) -> tuple:
        """World position of the eye: target + distance · (cos e sin a, sin e, cos e cos a)."""
        ce = math.cos(self.elevation)
        tx, ty, tz = self.target
        return (tx + self.distance * ce * math.sin(self.azimuth),
                ty + self.distance * math.sin(self.elevation),
                tz + self.distance * ce * math.cos(self.azimuth))

    def track(self, window) -> None:
        """Read the mouse and arrow keys of ``window`` (a ti.ui.Window) once per frame."""
        cursor = window.get_cursor_pos()  # [0, 1]², y up
        last, self._last_cursor = self._last_cursor, cursor
        if window.is_pressed(ti.ui.UP):
            self.zoom(0.97)
        if window.is_pressed(ti.ui.DOWN):
            self.zoom(1.03)
        if window.is_pressed(ti.ui.LEFT):
            self.azimuth -= 0.03
        if window.is_pressed(ti.ui.RIGHT):
            self.azimuth += 0.03
        if last is None:
            return
        dx, dy = cursor[0] - last[0], cursor[1] - last[1]
        if window.is_pressed(ti.ui.RMB):
            self.azimuth -= 4.0 * dx
            self.elevation = min(MAX_ELEVATION, max(MIN_ELEVATION, self.elevation - 3.0 * dy))
        elif window.is_pressed(ti.ui.MMB):
            self.zoom(math.exp(-2.0 * dy))

    def zoom(self, factor: float) -> None:
        self.distance = min(40.0, max(0.5, self.distance * factor))
