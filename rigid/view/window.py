"""The interactive window: one simulated frame (1/60 s) per drawn frame, at up to 60 fps.

Keys: space pause/resume, n one frame while paused, r reset, k random kick, esc quit
(GGUI 1.7 reports letters, space, arrows and a few named keys only, so the
single step is ``n``, not ``.``). Mouse: left-drag on a body grabs it (grab.py: a spring
to the cursor; release lets go), right-drag orbits, middle-drag zooms.
The frame loop is ``rigid.run.runner.run_frames``: pausing happens inside its
``on_frame`` (we keep drawing without stepping). After a blow-up the window
stays open, paused, with the message in the panel; a reset starts a new run.
The window is ``--resolution`` pixels (default 1280x720), as a recording would be.
Ctrl-C is read between frames, and spares xvfb-run's X server (see interrupt.py).
"""
from __future__ import annotations

import sys
import time

import taichi as ti

from .grab import MouseGrab
from .imaging import save_png
from .interrupt import ctrl_c_between_frames, shield_x_server_from_ctrl_c
from .panel import ControlPanel
from ..run.runner import RunResult, StopRun, run_frames
from .vulkan import require_display


def run_window(sim, frames: int | None = None, export_path=None, screenshot=None, resolution=None,
               camera=None) -> RunResult:
    """Show ``sim`` until the window closes (or for ``frames`` frames); return the last run's result.

    ``resolution`` (W, H): the window's size; None takes the simulator's ``config.resolution``.
    """
    require_display()
    from .render import SceneRenderer  # GGUI starts Vulkan: after the display check

    shield_x_server_from_ctrl_c()  # under xvfb-run in a terminal, Ctrl-C would stop the X server too
    size = tuple(resolution or sim.config.resolution)
    renderer = SceneRenderer(sim, size, offscreen=False, title="Rigid body (HKU COMP3360 A3)", fps_limit=60,
                             camera=camera)
    if camera is None or camera.position is None:
        renderer.orbit.zoom(1.15)  # a little further out than the video: the panel covers the right
    try:
        with ctrl_c_between_frames() as interrupted:
            loop = _WindowLoop(sim, renderer, screenshot=bool(screenshot), frames=frames, interrupted=interrupted)
            print(f"window open ({size[0]}x{size[1]}): esc closes it, Ctrl-C stops the run; either way the "
                  f"frames so far are kept", file=sys.stderr, flush=True)
            return _run_loop(sim, renderer, loop, frames, export_path, screenshot)
    finally:
        renderer.close()


def _run_loop(sim, renderer, loop, frames, export_path, screenshot) -> RunResult:
    remaining = frames
    while True:
        result = run_frames(sim, remaining, export_path=export_path, on_frame=loop.on_frame)
        if result.status != "blew-up" or loop.closed:
            break
        print(result.message, file=sys.stderr)
        remaining = None if frames is None else frames - loop.steps
        if remaining is not None and remaining <= 0:
            break
        if not loop.wait_for_reset(result.message):
            break
    if screenshot and loop.last_frame is not None:
        save_png(loop.last_frame, screenshot)
        print(f"wrote {screenshot}", file=sys.stderr)
    elif screenshot:
        print(f"no screenshot: the window closed before frame {frames}", file=sys.stderr)
    return result


class _WindowLoop:
    def __init__(self, sim, renderer, screenshot: bool, frames: int | None, interrupted=lambda: False):
        self.sim, self.renderer, self.window = sim, renderer, renderer.window
        self.interrupted = interrupted
        self.panel = ControlPanel(sim, seed=sim.config.seed)
        self.screenshot, self.frames = screenshot, frames
        self.last_frame = None
        self.closed = False
        self.steps = 0  # frames stepped over all runs (for --frames)
        self.fps = 0.0
        self._last_time = time.perf_counter()
        self.grab = MouseGrab(sim, renderer.orbit, (renderer.raster.width, renderer.raster.height))
        self.timing = {"sim_ms": 0.0, "draw_ms": 0.0}  # smoothed, per frame (rigid/bench/window.py)
        self._left = None  # when on_frame last returned: the time to the next call is simulating

    def on_frame(self, sim, i) -> bool:
        """Draw frame i; while paused keep drawing and listening. True: the state was changed by hand."""
        if i > 0:
            self.steps += 1
        if i == 1:  # the first frame simulated and drawn: every kernel compiled
            print("running: Ctrl-C now stops between frames and keeps them", file=sys.stderr, flush=True)
        began = time.perf_counter()
        if self._left is not None:
            _smooth(self.timing, "sim_ms", 1e3 * (began - self._left))
        changed = False
        while True:
            actions, pressed, reset = self._poll()
            if self.closed:
                raise StopRun
            changed |= reset or pressed.get("grabbing", False)  # a held body: energy comes in by hand
            if pressed.get("kick") or actions.get("kick"):
                self.panel.kick()
                changed = True
            changed |= pressed.get("params_changed", False)
            if actions.get("pause"):
                self.panel.paused = not self.panel.paused
            if not self.panel.paused or pressed.get("step") or actions.get("step"):
                self._left = time.perf_counter()
                _smooth(self.timing, "draw_ms", 1e3 * (self._left - began))
                return changed

    def wait_for_reset(self, message: str) -> bool:
        """After a blow-up: pause, show the message, wait for a reset. False if the window closed."""
        self.panel.message = message[:160]
        self.panel.paused = True
        while True:
            if self.interrupted():
                return False
            _actions, _pressed, reset = self._poll()
            if self.closed:
                return False
            if reset:
                return True

    def _poll(self):
        """Draw once and read the input: (key actions, panel presses, reset done).

        Sets ``closed`` on esc or a closed window (then nothing else is acted on); a reset
        from the key or the button rewinds the simulation and clears the panel's message.
        """
        if self.interrupted():
            raise KeyboardInterrupt  # run_frames keeps the frames so far
        actions, pressed = self._keys(), self._draw()
        if actions.get("quit") or not self.window.running:
            self.closed = True
            return actions, pressed, False
        reset = bool(pressed.get("reset") or actions.get("reset"))
        if reset:
            self.sim.reset()
            self.panel.message = ""
        return actions, pressed, reset

    def _keys(self) -> dict:
        actions = {}
        for event in self.window.get_events(ti.ui.PRESS):
            key = event.key
            if key == "Escape":
                actions["quit"] = True
            elif key == " ":
                actions["pause"] = True
            elif key == "r":
                actions["reset"] = True
            elif key == "k":
                actions["kick"] = True
            elif key in ("n", "."):
                actions["step"] = True
        return actions

    def _draw(self) -> dict:
        now = time.perf_counter()
        dt, self._last_time = now - self._last_time, now
        self.fps = 0.9 * self.fps + 0.1 / max(dt, 1e-6) if self.fps else 1.0 / max(dt, 1e-6)
        self.renderer.orbit.track(self.window)
        grabbing = self.grab.track(self.window.get_cursor_pos(), self.window.is_pressed(ti.ui.LMB))
        self.renderer.spring = self.grab.spring()
        self.renderer.wireframe = self.panel.wireframe
        self.renderer.grey_sleepers = self.panel.grey_sleepers
        self.renderer.draw()
        pressed = self.panel.draw(self.window.get_gui(), self.fps, self.timing)
        pressed["grabbing"] = grabbing
        # A read-back is slow in software: only for the frame a screenshot keeps
        # (every frame when the window runs until closed: any frame may be the last).
        if self.screenshot and (self.frames is None or self.steps >= self.frames):
            self.last_frame = self.renderer.read_rgba()
        self.window.show()
        return pressed


def _smooth(timing: dict, key: str, ms: float) -> None:
    """An exponential average over ~10 frames (the first frame's value taken as it is)."""
    timing[key] = ms if not timing[key] else 0.9 * timing[key] + 0.1 * ms
