"""Ctrl-C between frames, and Ctrl-C that would also stop the window's X server.

``ctrl_c_between_frames``: Ctrl-C sets a flag that the frame loop reads between frames, so an
encoder is never cut mid-packet and GGUI is never interrupted inside a call.

``shield_x_server_from_ctrl_c``: a terminal sends Ctrl-C to its whole foreground process group.
Under ``xvfb-run -a python3 rigid_body_dynamic.py`` that group holds the virtual X server too,
which then exits at once; GGUI's next call fails in C (Xlib's "XIO: fatal IO error", or a
failed Vulkan present) and ends the process: no summary, no export, no exit code 130. When the
X server shares our foreground group, we move into a process group of our own and make it the
terminal's foreground: Ctrl-C then reaches only this process, the run stops cleanly, and
xvfb-run stops its server after we exit. Ctrl-Z is ignored meanwhile (it would stop this
process alone, and the shell would wait for xvfb-run for ever).
"""
from __future__ import annotations

import atexit
import contextlib
import os
import re
import signal
import threading


@contextlib.contextmanager
def ctrl_c_between_frames():
    """Ctrl-C sets a flag read between frames; yields the flag's reader.

    A second Ctrl-C interrupts at once (the previous handler comes back).
    """
    pressed = threading.Event()
    previous = signal.getsignal(signal.SIGINT) if threading.current_thread() is threading.main_thread() else None
    if previous in (None, signal.SIG_IGN):  # not the main thread, or Ctrl-C ignored on purpose (nohup)
        yield pressed.is_set
        return

    def handler(signum, frame):
        pressed.set()
        signal.signal(signal.SIGINT, previous)

    signal.signal(signal.SIGINT, handler)
    try:
        yield pressed.is_set
    finally:
        signal.signal(signal.SIGINT, previous)


def shield_x_server_from_ctrl_c(display: str | None = None) -> bool:
    """If the X server of ``display`` (default $DISPLAY) is in our terminal's foreground process
    group, take a group of our own as the foreground (given back at exit). True if we did."""
    server = x_server_pid(display if display is not None else os.environ.get("DISPLAY", ""))
    if server is None or threading.current_thread() is not threading.main_thread():
        return False
    try:
        tty = os.open("/dev/tty", os.O_RDWR)  # our controlling terminal, if any
    except OSError:
        return False
    try:
        group = os.getpgrp()
        if os.getpgid(server) != group or os.tcgetpgrp(tty) != group:
            os.close(tty)
            return False
        signal.signal(signal.SIGTTOU, signal.SIG_IGN)  # a background group may then set the foreground
        os.setpgid(0, 0)
        os.tcsetpgrp(tty, os.getpgrp())
    except OSError:
        os.close(tty)
        return False
    signal.signal(signal.SIGTSTP, signal.SIG_IGN)
    atexit.register(_give_back, tty, group)
    return True


def _give_back(tty: int, group: int) -> None:
    with contextlib.suppress(OSError):
        os.tcsetpgrp(tty, group)
        os.close(tty)


def x_server_pid(display: str) -> int | None:
    """The process id of the local X server for ``display`` (":99", ":0.0"), from its lock file."""
    match = re.fullmatch(r"(?:unix)?:(\d+)(?:\.\d+)?", display.strip())
    if not match:
        return None  # no display, or a remote one
    try:
        with open(f"/tmp/.X{match.group(1)}-lock") as lock:
            return int(lock.read().strip())
    except (OSError, ValueError):
        return None
