"""Frames as pictures: a line of text on top, PNG files.

Frames here are (H, W, 4) uint8 RGBA with alpha 255, row 0 on top (as the renderer's
``read_rgba`` gives them, and as encoders and Pillow take them).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from ..run.atomic import atomic_output


class TextOverlay:
    """Writes one line of dark text on a pale band in the top-left corner of (H, W, 3 or 4) uint8
    frames, its size a fixed fraction of the height (legible in a still printed 9 cm wide)."""

    def __init__(self, height: int, color=(30, 30, 30), band=(255, 255, 255), band_alpha=0.72):
        # 1/20 of the height: 18 px at 360 rows, 36 at 720, i.e. 7.2 pt in a 16:9 still printed 9 cm wide
        self.size = max(14, round(height / 20))
        self.font = _font(self.size)
        self.color = np.asarray(color, np.float32)
        self.band, self.band_alpha = np.asarray(band, np.float32), band_alpha
        self.margin = max(4, self.size // 2)

    def draw(self, rgb: np.ndarray, text: str) -> None:
        """Blend ``text`` into ``rgb`` in place; only a small strip is touched (cheap per frame)."""
        left, top, right, bottom = self.font.getbbox(text)
        h, w = rgb.shape[:2]
        pad = max(2, self.size // 4)
        box_w, box_h = min(right + 2 * pad, w - self.margin), min(bottom + 2 * pad, h - self.margin)
        if box_w <= 0 or box_h <= 0:
            return
        mask = Image.new("L", (box_w, box_h), 0)
        ImageDraw.Draw(mask).text((pad, pad), text, fill=255, font=self.font)
        alpha = np.asarray(mask, np.float32)[..., None] / 255.0
        y, x = self.margin // 2, self.margin // 2
        region = rgb[y:y + box_h, x:x + box_w, :3].astype(np.float32)
        region = region * (1.0 - self.band_alpha) + self.band * self.band_alpha  # the pale band
        rgb[y:y + box_h, x:x + box_w, :3] = (region * (1.0 - alpha) + self.color * alpha + 0.5).astype(np.uint8)


def overlay_text(time: float, energy: float, bodies: int) -> str:
    """The line drawn on frames: "t 2.40 s · total energy −1212 J · 120 bodies"."""
    joules = f"{energy:.4g}".replace("-", "\u2212")
    return f"t {time:.2f} s \u00b7 total energy {joules} J \u00b7 {bodies} {'body' if bodies == 1 else 'bodies'}"


def moving_bodies(sim) -> int:
    """The bodies the overlay counts: a [[static]] mesh (the bowl) is scenery, not one of them."""
    return sum(1 for body in sim.bodies if not body.static)


def _font(size: int):
    """DejaVu Sans (shipped with matplotlib, a dependency), else Pillow's own scalable font."""
    try:
        import matplotlib

        return ImageFont.truetype(str(Path(matplotlib.get_data_path()) / "fonts" / "ttf" / "DejaVuSans.ttf"), size)
    except (ImportError, OSError):
        pass
    try:
        return ImageFont.load_default(size=size)  # Pillow >= 10.1 with FreeType
    except (TypeError, OSError):
        return ImageFont.load_default()


def save_png(frame: np.ndarray, path) -> None:
    """Write an (H, W, 3 or 4) uint8 frame as an RGB PNG under a temporary name, then rename."""
    with atomic_output(path) as tmp:
        Image.fromarray(np.ascontiguousarray(frame[..., :3])).save(tmp, format="PNG")
