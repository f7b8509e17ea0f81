"""Recording (--record): MP4 and GIF from the offscreen renderer, checked by decoding them.

A frame "shows the body" where pixels are the body's orange (red well above blue: the
floor, box, text and background are grey or white); the body "moves" when the orange
centroid travels down the picture as the sphere falls. Recording draws with our own
rasterizer and needs no Vulkan; the checks that a missing Vulkan is one line (for the
window) and that recording works without one are at the end.
"""
import os
import subprocess
import sys

import av
import numpy as np
import pytest

from conftest import ROOT, SOLUTION
from terminal import Terminal

W, H = 160, 120


def decode(path):
    """All frames of a video as (H, W, 3) uint8 arrays, and its video stream."""
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        frames = [f.to_ndarray(format="rgb24") for f in container.decode(stream)]
        return frames, stream, container.duration


def body_mask(rgb):
    rgb = rgb.astype(np.int32)
    return (rgb[..., 0] - rgb[..., 2] > 60) & (rgb[..., 0] > 120)


def centroid_row(rgb):
    rows, _ = np.nonzero(body_mask(rgb))
    return rows.mean()


@pytest.fixture
def falling_sphere(sim_cache):
    """The handout's sphere dropped from rest: it falls 0.7 m onto the floor in ~23 frames."""
    return sim_cache()


def test_mp4_has_frames_rate_size_and_shows_the_falling_body(falling_sphere, tmp_path):
    from rigid.view.video import record

    out = tmp_path / "fall.mp4"
    out.write_bytes(b"an older recording")
    result = record(falling_sphere, out, 24, (W, H), progress=False)
    assert result.status == "done"
    frames, stream, _ = decode(out)
    assert len(frames) == 25  # the initial state, then one per simulated frame (as the export's rows)
    assert stream.average_rate == 60 and stream.codec_context.name == "h264"
    assert stream.codec_context.pix_fmt == "yuv420p"
    assert (stream.width, stream.height) == (W, H) and frames[0].shape == (H, W, 3)
    assert all(body_mask(f).sum() > 30 for f in frames)  # the body is in every frame
    assert centroid_row(frames[-1]) - centroid_row(frames[0]) > 10  # ... and falls (pixels down)
    assert not any(p.name.startswith(".") for p in tmp_path.iterdir())  # no temporary file left


def test_gif_keeps_every_second_frame_at_30_fps_and_moves(falling_sphere, tmp_path):
    from rigid.view.video import record

    out = tmp_path / "fall.gif"
    record(falling_sphere, out, 24, (W, H), progress=False, screenshot=tmp_path / "last.png")
    frames, stream, duration = decode(out)
    assert len(frames) == 13 and (stream.width, stream.height) == (W, H)  # frames 0, 2, ..., 24
    assert abs(duration / 1e6 - 13 / 30) < 0.02  # as long as the 25-frame MP4 at 60 fps
    assert all(body_mask(f).sum() > 30 for f in frames)
    assert centroid_row(frames[-1]) - centroid_row(frames[0]) > 10
    from PIL import Image
    shot = np.asarray(Image.open(tmp_path / "last.png").convert("RGB"))
    assert shot.shape == (H, W, 3) and body_mask(shot).sum() > 30


def test_blow_up_keeps_the_frames_before_it(sim_cache, tmp_path):
    from rigid.view.video import record

    sim = sim_cache(collision_stiffness=1e7)  # explicit Euler needs dt < 6.3e-4 s for this spring
    out = tmp_path / "boom.mp4"
    result = record(sim, out, 120, (W, H), progress=False)
    frames, _, _ = decode(out)
    assert result.status == "blew-up" and 0 < len(frames) == result.frames + 1 < 121


def test_a_failed_recording_leaves_the_earlier_file(falling_sphere, tmp_path, monkeypatch):
    import rigid.view.video

    out = tmp_path / "keep.mp4"
    out.write_bytes(b"an older recording")
    calls = []

    def failing_draw(self, frame, text):
        calls.append(text)
        if len(calls) == 5:
            raise RuntimeError("disk full")

    monkeypatch.setattr(rigid.view.video.TextOverlay, "draw", failing_draw)
    with pytest.raises(RuntimeError, match="disk full"):
        rigid.view.video.record(falling_sphere, out, 24, (W, H), progress=False)
    assert out.read_bytes() == b"an older recording"
    assert [p.name for p in tmp_path.iterdir()] == ["keep.mp4"]


def test_the_first_frame_is_the_initial_state_at_t_0(falling_sphere, tmp_path, monkeypatch):
    import rigid.view.video

    texts = []
    monkeypatch.setattr(rigid.view.video.TextOverlay, "draw", lambda self, frame, text: texts.append(text))
    rigid.view.video.record(falling_sphere, tmp_path / "short.mp4", 3, (W, H), progress=False)
    frame_time = falling_sphere.substeps * falling_sphere.config.dt  # 16 substeps of 1 ms
    assert [t.split(" s")[0] for t in texts] == [f"t {i * frame_time:.2f}" for i in range(4)]
    assert texts[0].startswith("t 0.00 s \u00b7 total energy ") and texts[0].endswith(" J \u00b7 1 body")


def test_no_vulkan_is_one_line_naming_the_package_for_the_window(falling_sphere, tmp_path, monkeypatch):
    import rigid.view.vulkan
    from rigid.errors import UserError
    from rigid.view.render import SceneRenderer

    monkeypatch.setattr(rigid.view.vulkan, "vulkan_problem", lambda: "no Vulkan driver")
    with pytest.raises(UserError) as err:
        SceneRenderer(falling_sphere, (W, H), offscreen=False)
    message = str(err.value)
    assert "\n" not in message and "sudo apt-get install mesa-vulkan-drivers" in message
    # and the real probe answers without Taichi when the loader finds no driver
    code = "from rigid.view.vulkan import vulkan_problem; print(vulkan_problem())"
    probe = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=no_vulkan_env(tmp_path), capture_output=True,
                           text=True, timeout=30)
    assert probe.stdout.startswith("no Vulkan"), probe.stdout + probe.stderr


def no_vulkan_env(tmp_path):
    """The environment with a Vulkan loader that finds no driver."""
    nowhere = str(tmp_path / "none.json")
    return dict(os.environ, VK_ICD_FILENAMES=nowhere, VK_DRIVER_FILES=nowhere)


def test_ctrl_c_finalises_a_playable_file_with_the_frames_so_far(tmp_path):
    """... recorded with no Vulkan driver at all: recording does not need one."""
    out = tmp_path / "long.mp4"
    out.write_bytes(b"an older recording")
    command = [sys.executable, str(SOLUTION), "--record", str(out), "--frames", "100000",
               "--resolution", str(W), str(H)]
    with Terminal(command, cwd=ROOT, env=no_vulkan_env(tmp_path)) as run:
        # Frames drawn and handed to the encoder: the kernels are compiled (a Ctrl-C during the
        # compile writes nothing, see tests/test_clean_ends.py), the recording loop runs.
        run.count(100001)
        code = run.ctrl_c()
    assert code == 130, run.text
    frames, stream, _ = decode(out)
    assert 0 < len(frames) < 100000 and stream.average_rate == 60
    assert f"wrote {out} ({len(frames)} frames" in run.text and "Traceback" not in run.text
    assert not (tmp_path / ".long.partial.mp4").exists()
