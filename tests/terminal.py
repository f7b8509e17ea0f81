"""A command line run with its stderr on a terminal (a pty), as a user at a terminal runs it.

The progress bars (rigid.run.progress.FrameBar) show only on a terminal, and they count frames
done from right after the first frames (the ones that compile): a test waits on a count there,
an event, before it presses Ctrl-C, instead of waiting for a line a log file gets only after
seconds of simulating or for a clock.
"""
import os
import re
import select
import signal
import subprocess

from conftest import default_sigint


class Terminal:
    """``Terminal(command, cwd=..., env=...)``: started with stderr on a new pty, stdin and stdout
    closed off, Ctrl-C's default action; a context that kills the run if it is left running."""

    BOUND = 300.0  # s without output: a hung run, not a wait (output or the end comes first)

    def __init__(self, command, **popen):
        self.master, slave = os.openpty()
        try:
            self.proc = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                         stderr=slave, preexec_fn=default_sigint, **popen)
        finally:
            os.close(slave)
        self.seen = b""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        os.close(self.master)

    def _read(self) -> bytes:
        """The next output; b"" once the run closed its terminal (Linux says EIO)."""
        if not select.select([self.master], [], [], self.BOUND)[0]:
            raise AssertionError(f"no output from the run in {self.BOUND:.0f} s: {self.text}")
        try:
            chunk = os.read(self.master, 4096)
        except OSError:
            chunk = b""
        self.seen += chunk
        return chunk

    def count(self, total: int) -> int:
        """Wait until a progress bar over ``total`` shows a count; the latest count shown."""
        bar = re.compile(rb"\| *(\d+)/%d \[" % total)  # tqdm's "recording x.mp4:   0%|   | 12/301 [00:01<..."
        while not bar.search(self.seen):
            if not self._read():
                raise AssertionError(f"the run ended before its progress bar counted a frame: {self.text}")
        return max(map(int, bar.findall(self.seen)))

    def ctrl_c(self, timeout: float = 60) -> int:
        """Send Ctrl-C, read the rest, wait for the end; the exit code."""
        self.proc.send_signal(signal.SIGINT)
        while self._read():
            pass
        return self.proc.wait(timeout=timeout)

    @property
    def text(self) -> str:
        return self.seen.decode(errors="replace")
