"""Progress bars of headless runs and recordings open once the first frames are done, not while
the kernels compile; the one-line estimate waits for a chunk that only simulates."""
import io


def test_the_bar_opens_after_the_warm_up_frames_and_counts_from_there():
    from rigid.run.progress import FrameBar

    out = io.StringIO()
    bar = FrameBar(10, "recording x.mp4", enabled=True, warm_up=2, out=out)
    bar.update(1)
    bar.update(2)
    assert out.getvalue() == ""  # compiling: no bar, no rate
    bar.update(3)
    assert "3/10" in out.getvalue() and "recording x.mp4" in out.getvalue()
    for done in range(4, 11):
        bar.update(done)
    bar.close()
    assert "10/10" in out.getvalue()
    quiet = io.StringIO()
    off = FrameBar(10, "simulating", out=quiet)  # enabled=None: only on a terminal
    for done in range(1, 11):
        off.update(done)
    off.close()
    assert quiet.getvalue() == ""


def test_the_estimate_waits_for_a_chunk_that_only_simulates():
    from rigid.run.progress import TimeLeft

    out = io.StringIO()
    eta = TimeLeft(600, out=out)
    assert eta.chunk_done(1, 1, 6.0) is None  # the first chunk: 6 s, mostly compiling
    line = eta.chunk_done(3, 2, 0.02)  # 10 ms a frame measured: 6 s left, under SAY_ABOVE
    assert line is None and out.getvalue() == ""
    slow = TimeLeft(600, out=out)
    slow.chunk_done(1, 1, 6.0)
    line = slow.chunk_done(2, 1, 0.5)  # 0.5 s a frame: 5 min left
    assert line.startswith("2 of 600 frames in 6.5 s: 0.5 s a frame, about 5 min to go")
