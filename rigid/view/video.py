"""``--record out.mp4|out.gif``: simulate, render offscreen, encode; no display needed.

Frame i of the video is the state after i simulated frames (i = 0..N: frame 0
is the initial state, labelled t = 0), so ``--frames N`` gives N + 1 video frames,
one per row of the ``--export`` file (an MP4 at 60 fps; a GIF keeps every second
one at 30 fps). Each frame carries a line of text: the simulated time and the
total energy. The file is written under a temporary name and renamed when
finalised; Ctrl-C or a blow-up finalises it with the frames so far, and a run
that wrote no frame leaves any earlier file at that path untouched.
"""
from __future__ import annotations

import sys
from pathlib import Path

from ..run.atomic import atomic_output
from ..run.progress import FrameBar
from .encoders import BackgroundWriter, open_writer
from .imaging import TextOverlay, moving_bodies, overlay_text, save_png
from .interrupt import ctrl_c_between_frames
from ..run.runner import RunResult, run_frames


class _NothingWritten(Exception):
    """Leave the ``atomic_output`` block without renaming: keep the earlier file."""


def record(sim, path, frames: int, resolution, export_path=None, screenshot=None,
           progress: bool = True, camera=None) -> RunResult:
    """Record ``frames`` frames of ``sim`` into ``path`` (.mp4 or .gif) at ``resolution`` (W, H),
    seen by ``camera`` (a camera.CameraSpec; None frames the scene)."""
    from .render import SceneRenderer  # the renderer's fields and kernels: only when recording

    path = Path(path)
    size = (int(resolution[0]), int(resolution[1]))
    renderer = SceneRenderer(sim, size, offscreen=True, camera=camera)
    try:
        result, writer, last = _record_frames(sim, renderer, path, frames, size, export_path, progress)
    finally:
        renderer.close()
    if writer.frames == 0:
        print(f"no frame was recorded; {path} was not written", file=sys.stderr)
    else:
        note = "" if result.status == "done" else f"; stopped early ({result.status}), the frames so far"
        print(f"wrote {path} ({writer.frames} frames, {size[0]}x{size[1]}, {writer.fps} fps, "
              f"{writer.codec_name}{note})", file=sys.stderr)
    if screenshot and last is not None:
        save_png(last, screenshot)
        print(f"wrote {screenshot}", file=sys.stderr)
    return result


def _record_frames(sim, renderer, path: Path, frames: int, size, export_path, progress):
    """Simulate, draw, encode into a temporary file; rename it to ``path`` if it holds a frame."""
    overlay = TextOverlay(size[1])
    last = None
    try:
        with atomic_output(path) as tmp:
            writer = BackgroundWriter(open_writer(tmp, size, suffix=path.suffix))
            # Opened after frames 0 and 1 (drawing's and simulating's kernels compile in them).
            bar = FrameBar(frames + 1, f"recording {path.name}", enabled=progress, warm_up=2)
            try:
                with ctrl_c_between_frames() as stop_requested:
                    def on_frame(sim, i):
                        nonlocal last
                        renderer.draw()
                        frame = renderer.read_rgba()
                        snap = sim.snapshot()
                        energy = snap["kinetic_energy"] + snap["potential_energy"]
                        overlay.draw(frame, overlay_text(sim.time, energy, moving_bodies(sim)))
                        writer.write(frame)
                        last = frame
                        bar.update(i + 1)
                        if stop_requested():  # after drawing: the export holds this frame's row too
                            raise KeyboardInterrupt

                    result = run_frames(sim, frames, export_path=export_path, on_frame=on_frame)
            finally:
                bar.close()
                writer.close()  # finalise whatever was encoded: a playable file
            if writer.frames == 0:
                raise _NothingWritten
    except _NothingWritten:
        pass
    return result, writer, last
