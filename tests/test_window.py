"""The interactive window, run for a few seconds under a virtual display (xvfb-run)."""
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT, SOLUTION


def test_window_runs_under_xvfb_and_its_screenshot_shows_the_scene(tmp_path):
    from rigid.view.vulkan import vulkan_problem

    if shutil.which("xvfb-run") is None or vulkan_problem():
        pytest.skip("needs xvfb-run and Vulkan (scripts/setup.sh installs both)")
    shot = tmp_path / "window.png"
    # 60 frames at up to 60 fps: a second or more of the real window loop (a few seconds in all)
    proc = subprocess.run(["xvfb-run", "-a", sys.executable, str(SOLUTION), "--frames", "60",
                           "--screenshot", str(shot)], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "60 frames" in proc.stdout
    from PIL import Image

    rgb = np.asarray(Image.open(shot).convert("RGB")).astype(np.int32)
    assert rgb.shape == (720, 1280, 3)
    orange = (rgb[..., 0] - rgb[..., 2] > 60) & (rgb[..., 0] > 120)
    grey_floor = (np.abs(rgb[..., 0] - rgb[..., 2]) < 20) & (rgb[..., 0] > 150) & (rgb[..., 0] < 235)
    assert orange.sum() > 2000  # the body
    assert grey_floor.sum() > 20000  # the checkered floor
    assert not (tmp_path / "imgui.ini").exists()  # GGUI's panel layout file is cleaned up


def test_window_without_a_display_is_one_line(monkeypatch):
    from rigid.errors import UserError
    from rigid.view.window import run_window

    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    if not sys.platform.startswith("linux"):
        pytest.skip("the display check is for Linux")
    with pytest.raises(UserError, match="xvfb-run"):
        run_window(sim=None, frames=3)  # the display is checked before anything else
