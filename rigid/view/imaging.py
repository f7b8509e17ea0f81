"""Frames as pictures: a line of text on top, PNG files.

Frames here are (H, W, 4) uint8 RGBA with alpha 255, row 0 on top (as the renderer's
``read_rgba`` gives them, and as encoders and Pillow take them).
"""
from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from ..run.atomic import atomic_output


class TextOverlay:
    """Writes one line of dark text in the top-left corner of (H, W, 3 or 4) uint8 frames."""

    def __init__(self, height: int, color=(40, 40, 40)):
        self.size = max(12, height // 20)  # 5 % of the height: ~7 pt in print at 9 cm wide (the report)
        try:
            self.font = ImageFont.load_default(size=self.size)  # Pillow >= 10.1 with FreeType
        except (TypeError, OSError):
            self.font = ImageFont.load_default()
        self.color = np.asarray(color, np.float32)
        self.margin = max(4, self.size // 2)

    def draw(self, rgb: np.ndarray, text: str) -> None:
        """Blend ``text`` into ``rgb`` in place; only a small strip is touched (cheap per frame)."""
        left, top, right, bottom = self.font.getbbox(text)
        h, w = rgb.shape[:2]
        box_w, box_h = min(right + 2, w - self.margin), min(bottom + 2, h - self.margin)
        if box_w <= 0 or box_h <= 0:
            return
        mask = Image.new("L", (box_w, box_h), 0)
        ImageDraw.Draw(mask).text((0, 0), text, fill=255, font=self.font)
        alpha = np.asarray(mask, np.float32)[..., None] / 255.0
        y, x = self.margin, self.margin
        region = rgb[y:y + box_h, x:x + box_w, :3].astype(np.float32)
        rgb[y:y + box_h, x:x + box_w, :3] = (region * (1.0 - alpha) + self.color * alpha + 0.5).astype(np.uint8)


def save_png(frame: np.ndarray, path) -> None:
    """Write an (H, W, 3 or 4) uint8 frame as an RGB PNG under a temporary name, then rename."""
    with atomic_output(path) as tmp:
        Image.fromarray(np.ascontiguousarray(frame[..., :3])).save(tmp, format="PNG")
