"""An interrupted --record: the video and the --export file hold the same frames (issue 21:
an MP4 of 92 frames beside an NPZ of 93 rows). Ctrl-C is simulated without a signal or a clock:
the flag the recorder reads between frames turns on after the 6th drawn frame."""
import contextlib

import av
import numpy as np

W, H = 96, 64


def test_interrupted_recording_and_export_hold_the_same_frames(sim_cache, tmp_path, monkeypatch):
    import rigid.view.video as video

    drawn = []
    real_draw = video.TextOverlay.draw

    def counting_draw(self, frame, text):
        drawn.append(text)
        real_draw(self, frame, text)

    @contextlib.contextmanager
    def ctrl_c_after_six_frames():
        yield lambda: len(drawn) >= 6

    monkeypatch.setattr(video.TextOverlay, "draw", counting_draw)
    monkeypatch.setattr(video, "ctrl_c_between_frames", ctrl_c_after_six_frames)
    out, npz = tmp_path / "cut.mp4", tmp_path / "cut.npz"
    result = video.record(sim_cache(), out, 300, (W, H), export_path=npz, progress=False)
    assert result.status == "interrupted"
    with av.open(str(out)) as container:
        frames = sum(1 for _ in container.decode(video=0))
    rows = len(np.load(npz)["t"])
    assert frames == rows == len(drawn) == 6, (frames, rows, len(drawn))
