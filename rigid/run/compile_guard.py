"""Ctrl-C while Taichi compiles: stop within a moment, not when the compile returns.

Python runs a signal handler only between bytecodes of the main thread. Taichi compiles a
kernel inside one C++ call on that thread (the first frame of a pile: tens of seconds on an
empty kernel cache), so a Ctrl-C there waited for the whole compile before anything noticed it.

Python's C-level handler, though, writes each caught signal's number into the file descriptor
given to ``signal.set_wakeup_fd`` at once, whatever the main thread is doing. While the guard is
armed, a thread of ours waits on that pipe; a SIGINT there prints one line, removes the partial
outputs the run may have opened, and ends the process with exit code 130. Nothing simulated is
lost: the guard is disarmed once the first frame is done (``rigid.run.runner`` does it), and from
then on Ctrl-C stops between frames and keeps them (the runner's and the recorder's own handlers).
"""
from __future__ import annotations

import os
import signal
import sys
import threading
from pathlib import Path

from .atomic import partial_path

MESSAGE = "interrupted while compiling kernels (before the first frame); nothing written"

_active: "CompileGuard | None" = None


class CompileGuard:
    """Arm before ``ti.init``; ``disarm()`` once the first frame has run (idempotent)."""

    def __init__(self, outputs=()):
        self.partials = [partial_path(Path(p)) for p in outputs if p]
        self._read = self._write = None
        self._previous_fd = -1

    def arm(self) -> "CompileGuard":
        global _active
        if sys.platform == "win32" or threading.current_thread() is not threading.main_thread() or \
                signal.getsignal(signal.SIGINT) in (signal.SIG_IGN, signal.SIG_DFL, None):
            # Windows takes only a socket as the wakeup fd: Ctrl-C there waits for the compile.
            # Elsewhere: Ctrl-C ignored on purpose (nohup), or not ours to catch.
            return self
        self._read, self._write = os.pipe()
        os.set_blocking(self._write, False)  # the C handler must never block
        try:
            self._previous_fd = signal.set_wakeup_fd(self._write, warn_on_full_buffer=False)
        except (ValueError, OSError):
            self._close()
            return self
        threading.Thread(target=self._watch, args=(self._read,), name="compile-guard", daemon=True).start()
        _active = self
        return self

    def disarm(self) -> None:
        global _active
        if self._write is None:
            return
        signal.set_wakeup_fd(self._previous_fd)
        os.close(self._write)  # the watcher reads end-of-file and returns
        self._write = None
        if _active is self:
            _active = None

    def _watch(self, fd: int) -> None:
        try:
            while True:
                data = os.read(fd, 64)
                if not data:
                    return  # disarmed
                if signal.SIGINT in data:
                    self._stop()
        finally:
            os.close(fd)

    def _stop(self) -> None:
        print(MESSAGE, file=sys.stderr, flush=True)
        for tmp in self.partials:
            try:
                tmp.unlink()
            except OSError:
                pass
        os._exit(130)  # the main thread is inside Taichi's compiler: nothing else would return soon

    def _close(self) -> None:
        for fd in (self._read, self._write):
            if fd is not None:
                os.close(fd)
        self._read = self._write = None


def disarm_compile_guard() -> None:
    """The first frame is done: Ctrl-C goes back to stopping between frames."""
    if _active is not None:
        _active.disarm()
