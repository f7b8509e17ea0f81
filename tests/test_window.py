"""The interactive window, run for a few seconds under a virtual display (xvfb-run)."""
import fcntl
import os
import select
import shutil
import subprocess
import sys
import termios
import time

import numpy as np
import pytest

from conftest import SOLUTION, default_sigint


def needs_xvfb_and_vulkan():
    from rigid.view.vulkan import vulkan_problem

    if shutil.which("xvfb-run") is None or vulkan_problem():
        pytest.skip("needs xvfb-run and Vulkan (scripts/setup.sh installs both)")


def test_window_runs_under_xvfb_at_its_resolution_and_its_screenshot_shows_the_scene(tmp_path):
    needs_xvfb_and_vulkan()
    shot = tmp_path / "window.png"
    # 60 frames at up to 60 fps: a second or more of the real window loop (a few seconds in all)
    proc = subprocess.run(["xvfb-run", "-a", sys.executable, str(SOLUTION), "--frames", "60",
                           "--resolution", "640", "360", "--screenshot", str(shot)],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "60 frames" in proc.stdout and "window open (640x360)" in proc.stderr
    from PIL import Image

    rgb = np.asarray(Image.open(shot).convert("RGB")).astype(np.int32)
    assert rgb.shape == (360, 640, 3)  # --resolution sizes the window, not only videos
    orange = (rgb[..., 0] - rgb[..., 2] > 60) & (rgb[..., 0] > 120)
    grey_floor = (np.abs(rgb[..., 0] - rgb[..., 2]) < 20) & (rgb[..., 0] > 150) & (rgb[..., 0] < 235)
    assert orange.sum() > 500  # the body
    assert grey_floor.sum() > 5000  # the checkered floor
    assert not (tmp_path / "imgui.ini").exists()  # GGUI's panel layout file is cleaned up


def test_ctrl_c_in_a_terminal_running_xvfb_run_keeps_the_export_and_exits_130(tmp_path):
    """A terminal sends Ctrl-C to its whole foreground group, X server included (issue 15, item 9)."""
    needs_xvfb_and_vulkan()
    master, slave = os.openpty()

    def foreground_job_of_the_new_terminal():
        default_sigint()
        os.setsid()
        fcntl.ioctl(slave, termios.TIOCSCTTY, 0)
        os.tcsetpgrp(slave, os.getpgrp())

    export = tmp_path / "t.npz"
    proc = subprocess.Popen(["xvfb-run", "-a", sys.executable, str(SOLUTION), "--export", str(export)],
                            cwd=tmp_path, stdin=slave, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=foreground_job_of_the_new_terminal)
    os.close(slave)
    try:
        seen, deadline = b"", time.time() + 300  # a bound for a hung run, not a wait: the loop ends on the line
        while b"running:" not in seen and time.time() < deadline and proc.poll() is None:
            if select.select([proc.stderr], [], [], 0.5)[0]:
                seen += os.read(proc.stderr.fileno(), 4096)
        # The window's line once the first frame is simulated and drawn (Ctrl-C while compiling ends at once)
        assert b"running:" in seen, seen.decode()
        os.write(master, b"\x03")  # the terminal's Ctrl-C
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
        os.close(master)
    err = (seen + err).decode()
    assert proc.returncode == 130, err
    assert " frames, t = " in out.decode() and "XIO" not in err and "Traceback" not in err
    assert np.load(export)["t"].shape[0] >= 1 and f"wrote {export}" in err


def test_window_without_a_display_is_one_line(monkeypatch):
    from rigid.errors import UserError
    from rigid.view.window import run_window

    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    if not sys.platform.startswith("linux"):
        pytest.skip("the display check is for Linux")
    with pytest.raises(UserError, match="xvfb-run"):
        run_window(sim=None, frames=3)  # the display is checked before anything else
