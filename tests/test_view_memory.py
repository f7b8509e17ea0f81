"""Recording runs in constant memory (issue 15): 440 frames peak within 30 MB of 40.

GGUI's 3D scene on Mesa's lavapipe 22.3 kept ~300 KB per drawn object and frame (see
rigid/view/raster.py): 2,000 frames at 320x240 peaked at 1.47 GB against 417 MB for 200.
Both recordings run at once, each in its own process; ``os.wait4`` gives each one's peak
resident memory. Small frames keep it quick; 400 frames more catch any leak over ~75 KB a frame
(GGUI's was ~300 KB; 1,000 frames, which caught ~35 KB, cost the suite twice the CPU). The short
run only has to be past what a recording allocates once: the encoder holds up to 40 frames
before it writes (x264's lookahead), and from there on the peak stays within 1 MB.
"""
import os
import subprocess
import sys

from conftest import ROOT, SOLUTION


def start(tmp_path, frames):
    log = open(tmp_path / f"{frames}.log", "w")
    proc = subprocess.Popen([sys.executable, str(SOLUTION), "--record", str(tmp_path / f"{frames}.mp4"),
                             "--frames", str(frames), "--resolution", "160", "120"],
                            cwd=ROOT, stdout=log, stderr=log)
    log.close()
    return proc


def peak_mb(proc, tmp_path, frames):
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    assert proc.returncode == 0, (tmp_path / f"{frames}.log").read_text()[-2000:]
    return usage.ru_maxrss / 1024  # KiB on Linux


def test_a_long_recording_peaks_within_30_mb_of_a_short_one(tmp_path):
    short, long = start(tmp_path, 40), start(tmp_path, 440)
    short_mb, long_mb = peak_mb(short, tmp_path, 40), peak_mb(long, tmp_path, 440)
    print(f"peak resident memory: 40 frames {short_mb:.0f} MB, 440 frames {long_mb:.0f} MB")
    assert long_mb - short_mb < 30, (short_mb, long_mb)
    assert "441 frames" in (tmp_path / "440.log").read_text()
