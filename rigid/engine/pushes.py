"""What pushes the bodies from outside a run: an impulse, the mouse's grab, waking sleepers.

A mixin of the Simulator (simulator.py), which holds the model, the state, the params and the
kernels these use. The grab's force acts at a point through TODO 3 and 4 (forces.point_wrench).
"""
from __future__ import annotations

import numpy as np

from .arrays import clear, download, upload
from .grab import default_spring, holding, released


class Pushes:
    def wake(self, bodies=None):
        """Wake bodies (all by default; an index or a list of indices) that sleep (sleep.py): a
        grab or any outside push should call this for the body it moves."""
        if bodies is None:  # every body: a parameter change since the last run is then taken care of
            self._params_version = self.params.version
            clear(self.state.sleep)
            return
        sleep = download(self.state.sleep)
        sleep[np.atleast_1d(np.asarray(bodies, int))] = 0
        upload(self.state.sleep, sleep)

    def asleep(self) -> np.ndarray:
        """(B,) bool: which bodies sleep now (at rest, not integrated; the window greys them)."""
        return download(self.state.sleep)[:, 0] != 0

    def apply_impulse(self, particle: int, impulse):
        """Hit particle ``particle`` (its index in the mesh files' order, body after body) with
        impulse J (N s, world frame): ΔP = J, ΔL = r × J."""
        if not 0 <= particle < self.model.num_particles:
            raise IndexError(f"particle {particle} out of range 0..{self.model.num_particles - 1}")
        slot = int(self.model.slot_of[particle])
        self.kernels.apply_impulse(self.model.args, self.state.args, slot, [float(c) for c in impulse])

    def grab(self, particle: int, target, stiffness: float | None = None, damping: float | None = None):
        """Hold particle ``particle`` (mesh files' order) on a damped spring to ``target`` (world,
        m) from the next substep on: f = k (target − p) − c v_p, a force at that particle through
        TODO 3 and 4 (forces.point_wrench), in every scene. Default k, c: a 2 Hz, critically damped spring on the body's mass. Call
        again to move the target; ``release()`` lets go (a reset too)."""
        if not 0 <= particle < self.model.num_particles:
            raise IndexError(f"particle {particle} out of range 0..{self.model.num_particles - 1}")
        body = int(np.searchsorted(np.cumsum(self.model.body_count_np), particle, side="right"))
        k, c = default_spring(float(self.model.body_mass_np[body]))
        k, c = k if stiffness is None else float(stiffness), c if damping is None else float(damping)
        self.params.grab_values = holding(int(self.model.slot_of[particle]), target, k, c)
        self.params.upload(wakes=False)
        self.grabbed = int(particle)
        self.wake(body)  # a held body must move (sleep.py)

    def release(self):
        """Let go of the grabbed particle (nothing if none is held)."""
        self.params.grab_values = released()
        self.params.upload(wakes=False)
        self.grabbed = None
