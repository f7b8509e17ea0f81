"""Video writers over PyAV (which ships its own FFmpeg): H.264 MP4 and GIF.

Both take (H, W, 3) RGB or (H, W, 4) RGBA uint8 frames at the simulation's 60 frames per second and
are finalised by ``close()``, so a recording stopped early is still a playable
file. MP4: H.264, yuv420p (plays in browsers and on phones), 60 fps. GIF: its
frame delays count in 1/100 s and browsers slow down delays under 2/100 s, so a
GIF keeps every second frame and plays at 30 fps: real time, like the MP4.
"""
from __future__ import annotations

from fractions import Fraction

import av
import numpy as np
from PIL import Image

from ..errors import UserError

FPS = 60
GIF_FPS = 30
MP4_OPTIONS = {"preset": "veryfast", "crf": "20"}  # x264: fast, visually clean


def open_writer(path, size: tuple[int, int], suffix: str | None = None):
    """The writer for ``path`` by its suffix (.mp4 or .gif); ``size`` = (W, H)."""
    from pathlib import Path

    kind = (suffix or Path(path).suffix).lower()
    if kind == ".gif":
        return GifWriter(path, size)
    if kind == ".mp4":
        return Mp4Writer(path, size)
    raise UserError(f"output {path}: use a file name ending in .mp4 or .gif")


class _StreamWriter:
    """What both writers share: frame numbering, encoding and muxing, flushing on close."""

    def _encode(self, frame) -> None:
        frame.pts = self.frames
        frame.time_base = Fraction(1, self.fps)
        for packet in self.stream.encode(frame):
            self.container.mux(packet)
        self.frames += 1

    def close(self) -> None:
        for packet in self.stream.encode():  # flush the frames the encoder still holds
            self.container.mux(packet)
        self.container.close()


class Mp4Writer(_StreamWriter):
    codec_name = "H.264"

    def __init__(self, path, size: tuple[int, int], fps: int = FPS):
        width, height = size
        if width % 2 or height % 2:
            raise UserError(f"--resolution {width} {height}: H.264 in yuv420p needs an even width and height; "
                            f"use e.g. --resolution {width + width % 2} {height + height % 2}")
        self.fps = fps
        self.frames = 0
        # faststart: the index goes first, so browsers play while downloading.
        self.container = av.open(str(path), mode="w", format="mp4", options={"movflags": "faststart"})
        self.stream = self.container.add_stream("libx264", rate=fps)
        self.stream.width, self.stream.height = width, height
        self.stream.pix_fmt = "yuv420p"
        self.stream.options = dict(MP4_OPTIONS)

    def write(self, pixels: np.ndarray) -> None:
        self._encode(av.VideoFrame.from_ndarray(pixels, format="rgba" if pixels.shape[2] == 4 else "rgb24"))


class GifWriter(_StreamWriter):
    """Every second frame, 30 fps; one 255-colour palette made from the first frame (no flicker)."""

    codec_name = "GIF"

    def __init__(self, path, size: tuple[int, int], fps: int = GIF_FPS):
        width, height = size
        self.fps = fps
        self.stride = FPS // fps
        self.seen = 0
        self.frames = 0
        self.palette_image = None
        self.palette_argb = None
        self.container = av.open(str(path), mode="w", format="gif")
        self.stream = self.container.add_stream("gif", rate=fps)
        self.stream.width, self.stream.height = width, height
        self.stream.pix_fmt = "pal8"

    def write(self, pixels: np.ndarray) -> None:
        self.seen += 1
        if (self.seen - 1) % self.stride:
            return
        image = Image.fromarray(np.ascontiguousarray(pixels[..., :3]))
        if self.palette_image is None:
            self.palette_image = image.quantize(colors=255, method=Image.Quantize.MEDIANCUT)
            rgb_palette = np.zeros((256, 3), np.uint8)
            entries = np.asarray(self.palette_image.getpalette(), np.uint8).reshape(-1, 3)[:256]
            rgb_palette[:len(entries)] = entries
            # PyAV takes the palette as (256, 4) ARGB bytes.
            self.palette_argb = np.concatenate([np.full((256, 1), 255, np.uint8), rgb_palette], axis=1)
        indices = np.asarray(image.quantize(palette=self.palette_image, dither=Image.Dither.NONE))
        self._encode(av.VideoFrame.from_ndarray((np.ascontiguousarray(indices), self.palette_argb), format="pal8"))


class BackgroundWriter:
    """Runs a writer's ``write`` in a worker thread, so encoding overlaps the next frame's render.

    FFmpeg encodes with the GIL released, and the renderer leaves a core idle part of
    each frame; a short queue (a few frames) bounds the memory. ``close()`` drains the
    queue, then finalises the file; an encoder error is raised in the caller's thread.
    """

    def __init__(self, writer, depth: int = 3):
        import queue
        import threading

        self.writer = writer
        self.queue = queue.Queue(maxsize=depth)
        self.error = None
        self.thread = threading.Thread(target=self._work, name="video-encoder", daemon=True)
        self.thread.start()

    def __getattr__(self, name):  # fps, frames, codec_name of the wrapped writer
        return getattr(self.writer, name)

    def _work(self):
        while True:
            pixels = self.queue.get()
            if pixels is None:
                return
            if self.error is None:
                try:
                    self.writer.write(pixels)
                except BaseException as err:  # handed to the main thread
                    self.error = err

    def write(self, pixels: np.ndarray) -> None:
        self._raise()
        self.queue.put(pixels)

    def close(self) -> None:
        self.queue.put(None)
        self.thread.join()
        self.writer.close()
        self._raise()

    def _raise(self):
        if self.error is not None:
            error, self.error = self.error, None
            raise error
