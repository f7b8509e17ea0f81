"""The window's control panel (GGUI's imgui): readouts, sliders, buttons.

Sliders write the simulator's runtime parameters (``sim.params``, copied to the device
on change), which the kernels read at every launch: a change takes effect on the next
frame, without a recompile or a restart. A reset keeps the slider values.
"""
from __future__ import annotations

import numpy as np

PANEL_TITLE = "Rigid body"  # imgui's layout file names it; rigid/render.py removes that file

KICK_SPEED = 2.5  # m/s: the random kick changes the body's speed by about this much

HELP = ("space pause  n step  r reset  k kick  esc quit\n"
        "left-drag a body: grab it (release lets go)\nright-drag orbit  middle-drag/arrows zoom")
PANEL_PLACE = (0.725, 0.02, 0.27, 0.6)  # x, y from the top, width, height: fractions of the window
READOUT_SECONDS = 0.25  # the energies and momenta are read (a kernel: the contact energy) 4 times a second


class ControlPanel:
    def __init__(self, sim, seed: int = 0):
        self.sim = sim
        self.rng = np.random.default_rng(seed)
        self.paused = False
        self.wireframe = False
        self.grey_sleepers = True  # sleeping bodies greyer (the renderer's grey_sleepers)
        self.message = ""  # e.g. the last blow-up, shown in red
        self._snap, self._snap_at, self._snap_frame = None, -1e9, -1

    def kick(self) -> None:
        """An impulse of random direction (biased upwards) at a random particle: it moves and spins."""
        sim = self.sim
        particle = int(self.rng.integers(sim.model.num_particles))
        direction = self.rng.normal(size=3) + np.array([0.0, 1.5, 0.0])
        direction /= np.linalg.norm(direction)
        sim.apply_impulse(particle, sim.model.mass * KICK_SPEED * direction)

    def snapshot(self) -> dict:
        """The state for the readouts, read again after READOUT_SECONDS or a step back (reset)."""
        import time

        now, frame = time.perf_counter(), self.sim.frame
        if self._snap is None or now - self._snap_at > READOUT_SECONDS or frame < self._snap_frame \
                or (self.paused and frame != self._snap_frame):
            self._snap, self._snap_at, self._snap_frame = self.sim.snapshot(), now, frame
        return self._snap

    def draw(self, gui, fps: float, timing: dict | None = None) -> dict:
        """Declare the panel for this frame; return the buttons pressed, e.g. {"reset": True}.
        ``timing``: ms a frame spent drawing and simulating (the window's measure), shown with
        how fast the simulation runs against real time when it cannot keep up."""
        sim, prm = self.sim, self.sim.params
        snap = self.snapshot()
        kinetic, potential = snap["kinetic_energy"], snap["potential_energy"]
        pressed = {}
        with gui.sub_window(PANEL_TITLE, *PANEL_PLACE) as w:
            w.text(f"t = {sim.time:.3f} s   frame {sim.frame}   {fps:.0f} fps")
            if timing:
                w.text(speed_line(fps, sim.substeps * float(prm.dt), timing, self.paused))
            w.text(f"kinetic {kinetic:.4g} J   potential {potential:.4g} J")
            w.text(f"total E {kinetic + potential:.4g} J")
            w.text(f"|P| {np.linalg.norm(snap['P'].sum(axis=0)):.4g} kg m/s   "
                   f"|L| {np.linalg.norm(snap['L'].sum(axis=0)):.4g} kg m²/s")
            # (label, parameter, shown value = parameter x scale, slider range)
            sliders = [("dt [ms]", "dt", 1e3, 0.05, 4.0),
                       ("stiffness k", "collision_stiffness", 1.0, 0.0, 1e5),
                       ("damping", "velocity_damping_stiffness", 1.0, 0.0, 5e3),
                       ("friction mu", "friction_stiffness", 1.0, 0.0, 1.0)]
            moved = {}
            for label, name, scale, low, high in sliders:
                shown = float(getattr(prm, name)) * scale
                new = w.slider_float(label, shown, low, high)
                if _differs(new, shown):
                    moved[name] = new / scale
            gravity = prm.gravity.copy()
            gravity_y = w.slider_float("gravity y", float(gravity[1]), -30.0, 0.0)
            self.wireframe = w.checkbox("wireframe", self.wireframe)
            if sim.many:
                asleep = int(sim.asleep().sum())
                self.grey_sleepers = w.checkbox(f"grey sleeping bodies ({asleep} asleep)", self.grey_sleepers)
            self.paused = w.checkbox("paused (space)", self.paused)
            pressed["reset"] = w.button("reset (r)")
            pressed["kick"] = w.button("random kick (k)")
            pressed["step"] = w.button("step one frame (n)")
            w.text(HELP)
            if self.message:
                w.text(self.message, color=(1.0, 0.35, 0.3))
        for name, value in moved.items():
            setattr(prm, name, max(value, 1e-5) if name == "dt" else value)
        changed = bool(moved)
        if _differs(gravity_y, gravity[1]):
            prm.gravity = (float(gravity[0]), gravity_y, float(gravity[2]))
            changed = True
        pressed["params_changed"] = changed
        return pressed


def speed_line(fps: float, frame_seconds: float, timing: dict, paused: bool) -> str:
    """E.g. "simulation 0.4x real time" and, on a second line, "simulating 38 ms, drawing 9 ms a
    frame" (ASCII: imgui's default font has no multiplication sign)."""
    split = f"simulating {timing['sim_ms']:.0f} ms, drawing {timing['draw_ms']:.0f} ms a frame"
    if paused:
        return "paused\n" + split
    factor = fps * frame_seconds
    pace = "real time" if factor >= 0.95 else f"simulation {factor:.2g}x real time"
    return f"{pace}\n{split}"


def _differs(new: float, old: float) -> bool:
    """Did the user move the slider? imgui rounds to float32, so compare there."""
    return bool(np.float32(new) != np.float32(old))
