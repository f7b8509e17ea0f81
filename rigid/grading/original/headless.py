"""Stand-ins for ``ti.init``, ``ti.ui`` and ``ti.GUI``: the file runs N frames, draws nothing, opens nothing.

``install()`` replaces them in the (already initialised) taichi module:

- ``ti.init`` and ``ti.reset`` do nothing (the grader initialised Taichi once, without debug);
  the calls are counted, so a file that calls ``ti.init`` twice gets a note, not a crash.
- ``ti.ui.Window`` / ``ti.GUI``: ``window.running`` is True for ``frames`` frames, then False.
  Every read of ``running`` is a frame boundary: it records a snapshot of the body's fields
  (``Recorder.snapshot``), so row 0 is the state before the first frame. A loop that never reads
  ``running`` but calls ``show()`` is cut the same way at ``show()``; one that goes on past the
  last frame is stopped by ``StopRun`` (a BaseException, so ``except Exception`` cannot swallow it).
- Everything else of the GUI (canvas, scene, camera, panels) accepts any call and does nothing;
  sliders and checkboxes return the value they were given, buttons and key presses are False.
"""
import types

import numpy as np


class StopRun(BaseException):
    """The grader has its frames: stop the file's loop."""


class Recorder:
    """The run in progress: how many frames, and the snapshots so far."""

    def __init__(self, frames: int, snapshot):
        self.frames, self.snapshot = frames, snapshot
        self.rows, self.reads, self.shows = [], 0, 0

    @property
    def complete(self) -> bool:
        return len(self.rows) > self.frames

    def running(self) -> bool:
        self.reads += 1
        if not self.complete:
            self.rows.append(self.snapshot())
        return not self.complete

    def shown(self) -> None:
        self.shows += 1
        if self.reads == 0 and not self.complete:
            self.rows.append(self.snapshot())
        if self.complete:  # a loop that ignores running (while True: ... show())
            raise StopRun()


class State:
    recorder: Recorder | None = None
    init_calls = 0


def _keep(*args, **kwargs):
    """gui.slider_float(label, old_value, ...) -> old_value: the panel never changes anything."""
    if len(args) > 1:
        return args[1]
    return kwargs.get("old_value", kwargs.get("value", False))


class _Null:
    """Accepts any attribute, call, context or iteration, and does nothing."""

    def __init__(self, *args, **kwargs):
        pass

    def __getattr__(self, name):
        if name.startswith(("slider", "checkbox", "color_edit", "input")):
            return _keep
        if name in ("button", "is_pressed", "get_event"):
            return lambda *a, **k: False
        if name == "get_events":
            return lambda *a, **k: []
        if name == "get_cursor_pos":
            return lambda *a, **k: (0.5, 0.5)
        return _Null()

    def __call__(self, *args, **kwargs):
        return _Null()

    def __bool__(self):
        return False

    def __iter__(self):
        return iter(())

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


class _Constants(type):
    def __getattr__(cls, name):  # ti.GUI.ESCAPE, ti.GUI.SPACE ...: a key name
        return name


class Window(_Null, metaclass=_Constants):
    """ti.ui.Window and ti.GUI: runs the recorder's frames."""

    def __init__(self, *args, **kwargs):
        self._closed = False
        self.res = kwargs.get("res", (512, 512))

    @property
    def running(self) -> bool:
        if self._closed or State.recorder is None:
            return False
        return State.recorder.running()

    @running.setter
    def running(self, value) -> None:
        self._closed = self._closed or not value

    def show(self, *args, **kwargs):
        if State.recorder is not None:
            State.recorder.shown()

    def get_image_buffer_as_numpy(self):
        return np.zeros((*self.res, 4), np.float32)

    def destroy(self):
        self._closed = True

    close = destroy


class _UI(types.ModuleType):
    Window = Window

    def __getattr__(self, name):
        if name.isupper():  # ti.ui.SPACE, ti.ui.RMB, ti.ui.PRESS ...
            return name.lower()
        return _Null


def _init(*args, **kwargs):
    State.init_calls += 1


def install(ti) -> None:
    """Put the stand-ins into the taichi module (after the grader's own ti.init)."""
    import sys

    ui = _UI("taichi.ui")
    ti.ui = ui
    sys.modules["taichi.ui"] = ui
    ti.GUI = Window
    ti.init = _init
    ti.reset = lambda *a, **k: None
