"""A run shown inline in Jupyter: ``rigid.show(sim, frames=300)``, drawn by the project's software
renderer (raster.py), so no display and no Vulkan are needed.

``show`` simulates ``frames`` frames, draws each (the framed camera, contact shadows, the
labelled overlay) and returns a ``Video``: Jupyter displays it (an HTML5 <video> of an H.264
MP4, or an animated GIF <img>, embedded as base64), ``.rows`` holds the trajectory (the rows of
``Simulator.advance``: ``t``, ``x``, energies, ... for plots), ``.frames`` the pictures as a
(frames + 1, H, W, 3) uint8 array when ``keep_frames`` (memory: 0.7 MB a frame at 640x360).
``frames(sim, n)`` returns only the pictures.
"""
from __future__ import annotations

import base64
import html
import os
import tempfile

import numpy as np

from .encoders import open_writer
from .imaging import TextOverlay, moving_bodies, overlay_text

DEFAULT_SIZE = (640, 360)


class Video:
    """A recorded run for a notebook: ``_repr_html_`` shows it; ``save(path)`` writes the file."""

    def __init__(self, data: bytes, kind: str, size, rows: dict, frames: np.ndarray | None):
        self.data, self.kind, self.size, self.rows, self.frames = data, kind, tuple(size), rows, frames

    def _repr_html_(self) -> str:
        src = f"data:{'video/mp4' if self.kind == 'mp4' else 'image/gif'};base64," + \
            base64.b64encode(self.data).decode("ascii")
        w, h = self.size
        if self.kind == "mp4":
            return (f'<video width="{w}" height="{h}" controls autoplay loop muted playsinline '
                    f'src="{html.escape(src)}"></video>')
        return f'<img width="{w}" height="{h}" src="{html.escape(src)}"/>'

    def save(self, path) -> None:
        with open(path, "wb") as out:
            out.write(self.data)

    def __repr__(self) -> str:
        n = len(self.rows["t"]) if self.rows else 0
        return f"<rigid Video: {n} frames, {self.size[0]}x{self.size[1]} {self.kind}, {len(self.data):,} bytes>"


def show(sim, frames: int = 300, resolution=DEFAULT_SIZE, camera=None, format: str = "mp4",
         keep_frames: bool = False) -> Video:
    """Simulate ``frames`` frames of ``sim`` from its current state and return them as a Video
    (frame 0 the current state). ``camera``: a dict of the [camera] table's keys (position,
    look_at, fov, follow) or a camera.CameraSpec; None: the scene's [camera] table, else a
    framed view. ``format``: "mp4" (H.264, 60 fps) or "gif" (30 fps)."""
    if format not in ("mp4", "gif"):
        raise ValueError(f"format = {format!r}: use 'mp4' or 'gif'")
    size = _size(resolution, even=True)
    fd, tmp = tempfile.mkstemp(suffix=f".{format}")
    os.close(fd)
    try:
        writer = open_writer(tmp, size)
        kept = []
        rows = _draw_run(sim, frames, size, camera, lambda picture: (writer.write(picture),
                                                                     keep_frames and kept.append(picture[..., :3])))
        writer.close()
        with open(tmp, "rb") as f:
            data = f.read()
    finally:
        os.unlink(tmp)
    return Video(data, format, size, rows, np.stack(kept) if keep_frames else None)


def frames(sim, frames: int = 60, resolution=DEFAULT_SIZE, camera=None, overlay: bool = True) -> np.ndarray:
    """Simulate ``frames`` frames and return the pictures, (frames + 1, H, W, 3) uint8, top row first."""
    kept = []
    _draw_run(sim, frames, _size(resolution), camera, lambda picture: kept.append(picture[..., :3]), overlay)
    return np.stack(kept)


def _draw_run(sim, frames: int, size, camera, take, overlay: bool = True) -> dict:
    """Draw the current state, then each of ``frames`` frames; ``take(picture)`` gets each
    (H, W, 4) picture; returns the rows (frames + 1 of them)."""
    from .camera import CameraSpec, camera_spec
    from .render import SceneRenderer

    if frames < 1:
        raise ValueError(f"frames = {frames}: show at least one frame")
    if camera is None:  # the scene's [camera] table, if it has one
        camera = getattr(sim.config, "camera", None)
    spec = camera if isinstance(camera, CameraSpec) or camera is None else camera_spec(dict(camera))
    renderer = SceneRenderer(sim, size, offscreen=True, camera=spec)
    text = TextOverlay(size[1]) if overlay else None
    blocks = [sim.current_block()]
    try:
        for i in range(frames + 1):
            if i:
                blocks.append(sim.advance_frames(1))
            renderer.draw()
            picture = renderer.read_rgba()
            if text is not None:
                row = blocks[-1]
                energy = float(row["kinetic_energy"][-1] + row["potential_energy"][-1])
                text.draw(picture, overlay_text(sim.time, energy, moving_bodies(sim)))
            take(picture)
    finally:
        renderer.close()
    return {key: np.concatenate([b[key] for b in blocks]) for key in blocks[0]}


def _size(resolution, even: bool = False) -> tuple[int, int]:
    w, h = (int(r) for r in resolution)
    if not (16 <= w <= 8192 and 16 <= h <= 8192):
        raise ValueError(f"resolution = {w} x {h}: width and height go from 16 to 8192 pixels")
    return (w + w % 2, h + h % 2) if even else (w, h)  # H.264 in yuv420p needs even sizes
