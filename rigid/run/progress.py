"""How long a headless run has left, said once on stderr when it is long (rigid.run.runner)."""
from __future__ import annotations

import sys


class TimeLeft:
    """A headless run that will take a while says so once, on stderr: the time per frame as
    measured, and the time left. The first chunk compiles the kernels (seconds): its rate is
    not used unless the chunk took more than TRUST_FIRST (then a frame is that slow, and its
    rate is an upper bound); later chunks replace it. Quiet for runs under ~10 s."""

    SAY_AFTER = 2.0  # seconds of simulating before the estimate is trusted enough to print
    SAY_ABOVE = 10.0  # seconds left: shorter runs need no estimate
    TRUST_FIRST = 30.0  # s: a first chunk shorter than this is mostly compiling; longer, it is a slow frame

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
        if first and seconds < self.TRUST_FIRST:  # mostly compiling: wait for a chunk that only simulates
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


class FrameBar:
    """A tqdm progress bar over a run's frames, opened only once ``warm_up`` updates are done: the
    first frames compile the kernels (seconds), and a bar started during them would show a rate,
    and an estimate, many times too slow (a recording's first ETA said 16:34 while compiling).
    ``enabled`` None: shown when stderr is a terminal (a log file gets TimeLeft's one line)."""

    def __init__(self, frames: int | None, desc: str, enabled: bool | None = None, warm_up: int = 1, out=None):
        self.out = out or sys.stderr
        if enabled is None:
            enabled = bool(getattr(self.out, "isatty", lambda: False)())
        self.frames, self.desc, self.enabled, self.warm_up = frames, desc, enabled and bool(frames), warm_up
        self.updates, self.bar = 0, None

    def update(self, done: int) -> None:
        """``done`` frames are finished."""
        if not self.enabled:
            return
        self.updates += 1
        if self.bar is None:
            if self.updates <= self.warm_up:
                return
            from tqdm import tqdm

            import shutil

            # The terminal's size, 100 x 20 where it reports none (a pty of size 0 x 0, as under
            # script(1), would make tqdm print nothing at all).
            size = shutil.get_terminal_size((100, 20))
            self.bar = tqdm(total=self.frames, initial=done, unit="frame", desc=self.desc, file=self.out,
                            mininterval=0.5, smoothing=0.1, ncols=size.columns, nrows=size.lines)
            return
        self.bar.update(done - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None
