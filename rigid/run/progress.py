"""How long a headless run has left, said once on stderr when it is long (rigid.run.runner)."""
from __future__ import annotations

import sys


class TimeLeft:
    """A headless run that will take a while says so once, on stderr: the time per frame as
    measured, and the time left. The first chunk compiles the kernels, so its rate is an upper
    bound; later chunks replace it. Quiet for runs under ~10 s."""

    SAY_AFTER = 2.0  # seconds of simulating before the estimate is trusted enough to print
    SAY_ABOVE = 10.0  # seconds left: shorter runs need no estimate

    def __init__(self, frames: int, out=None):
        self.frames, self.out, self.said = frames, out, False
        self.chunks = self.timed_frames = 0
        self.elapsed = self.timed = 0.0

    def chunk_done(self, done: int, size: int, seconds: float) -> str | None:
        """A chunk of ``size`` frames took ``seconds``; ``done`` frames are simulated. Returns the
        line when it prints it."""
        self.chunks += 1
        self.elapsed += seconds
        first = self.chunks == 1
        if not first:
            self.timed_frames, self.timed = self.timed_frames + size, self.timed + seconds
        if self.said or self.elapsed < self.SAY_AFTER:
            return None
        per_frame = self.timed / self.timed_frames if self.timed_frames else seconds / size
        left = (self.frames - done) * per_frame
        if left < self.SAY_ABOVE:
            return None
        self.said = True
        line = (f"{done} of {self.frames} frames in {self.elapsed:.3g} s: {per_frame:.3g} s a frame"
                f"{' (compiling included)' if not self.timed_frames else ''}, "
                f"{'at most ' if not self.timed_frames else 'about '}{_duration(left)} to go "
                f"(Ctrl-C stops and keeps what is done)")
        print(line, file=self.out or sys.stderr, flush=True)
        return line


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"
