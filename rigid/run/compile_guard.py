"""Ctrl-C while Taichi compiles: stop at once, not when the compile returns.

Python runs a signal handler only between bytecodes of the main thread, and Taichi compiles a
kernel inside C++ calls that hold the interpreter's lock (the first frame of a pile: tens of
seconds on an empty kernel cache), so a Ctrl-C there waited for the whole compile; no Python
thread can act meanwhile either. Until the first frame is done nothing is lost by stopping, so
``ctrl_c_stops_at_once`` gives SIGINT its default action for that stretch: the process ends at
once, as killed by the signal (exit status 130 in a shell), with no traceback. Outputs are
written under temporary names and renamed when complete (rigid.run.atomic), so none is left
under the user's name. After the first frame Ctrl-C stops between frames and keeps them (the
runner's and the recorder's own handlers).

``compile_note`` says so once, before a first run compiles: Taichi's kernel cache is empty.
"""
from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading


@contextlib.contextmanager
def ctrl_c_stops_at_once():
    """SIGINT's default action (end the process) inside the block, then the handler from before.
    Left alone where Ctrl-C is ignored on purpose (nohup) or outside the main thread."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGINT)
    if previous in (signal.SIG_IGN, None):
        yield
        return
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def kernel_cache_is_empty() -> bool:
    """No kernel compiled yet in Taichi's offline cache (rigid/__init__.py sets where it is)."""
    folder = os.environ.get("TI_OFFLINE_CACHE_FILE_PATH")
    if not folder or not os.path.isdir(folder):
        return True
    return not any(files for _root, _dirs, files in os.walk(folder))


def compile_note() -> None:
    """One line before a first run, which compiles for a while."""
    if kernel_cache_is_empty():
        print("compiling kernels (first run only: up to about 10 s for bodies in contact); Ctrl-C stops at once",
              file=sys.stderr, flush=True)
