"""The frame loop shared by headless runs and recordings.

``run_frames`` steps the simulator frame by frame, keeps the trajectory for the
export, stops at the first frame that blows up, and turns Ctrl-C into a clean
stop: whatever happens, the frames simulated so far are saved.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

from .diagnostics import Trajectory, blow_up, stability_hint
from .exports import write_exports



def energy_bound(mass: float, gravity, kinetic0: float) -> float:
    """How far the total energy may rise above its start before we call it a blow-up.

    The body has no energy source: only the integrator's error adds energy (under 1 J
    over 10 s in every scene of assets/scenes). An unstable contact spring adds it
    exponentially; we stop once it has gained the energy of lifting the body by 1 m
    or half its initial kinetic energy, whichever is larger.
    """
    import numpy as np

    return mass * float(np.linalg.norm(gravity)) * 1.0 + 0.5 * kinetic0 + 1e-6


class StopRun(Exception):
    """Raised by an ``on_frame`` callback to end the run normally (e.g. the window was closed)."""


@dataclass
class RunResult:
    frames: int  # frames simulated after the initial state
    status: str  # "done", "interrupted" or "blew-up"
    message: str = ""

    @property
    def exit_code(self) -> int:
        return {"done": 0, "interrupted": 130, "blew-up": 3}[self.status]


def run_frames(sim, frames: int | None, export_path=None, on_frame=None, check_every: int = 1) -> RunResult:
    """Simulate ``frames`` frames (None: until ``on_frame`` raises StopRun); ``on_frame(sim, i)``
    runs after each (e.g. draw and encode). If it returns True, the state was changed by hand
    (a reset, a kick, a new gravity) and the blow-up check measures energy from there on."""
    cfg = sim.config
    m = sim.model  # many bodies: mass (B,), inertia_body (B, 3, 3); one body: (), (3, 3)
    mass, inertia = (m.body_mass_np, m.inertia_all_np) if sim.many else (m.mass, m.inertia_body_np)
    trajectory = Trajectory(mass, inertia, cfg.dt, sim.substeps, cfg.fp64)
    row = sim.snapshot()
    trajectory.append(row)
    e0 = row["kinetic_energy"] + row["potential_energy"]
    bound = energy_bound(sim.model.mass, cfg.gravity, row["kinetic_energy"])
    result = RunResult(0, "done")
    try:
        if on_frame is not None and on_frame(sim, 0):
            e0, bound = _energy_baseline(sim)
        for i in (itertools.count(1) if frames is None else range(1, frames + 1)):
            sim.step_frame()
            if export_path is not None or i % check_every == 0 or i == frames:
                row = sim.snapshot()
                problem = blow_up(row, e0, bound)
                if problem:
                    result = RunResult(i - 1, "blew-up",
                                       f"blow-up at t = {sim.time:.4g} s (frame {i}): {problem}; "
                                       f"{stability_hint(cfg)}")
                    break
                if export_path:  # rows are kept only for an export: a window left open stays in constant memory
                    trajectory.append(row)
            result.frames = i
            if on_frame is not None and on_frame(sim, i):
                e0, bound = _energy_baseline(sim)
    except StopRun:
        pass
    except KeyboardInterrupt:
        result = RunResult(result.frames, "interrupted", f"interrupted after {result.frames} frames")
    if export_path:  # one path or a list (--export given several times); the suffix picks the format
        write_exports(export_path, trajectory, sim)
    return result


def _energy_baseline(sim) -> tuple[float, float]:
    """Initial energy and blow-up bound measured from the simulator's current state."""
    row = sim.snapshot()
    gravity = sim.params.gravity[None].to_numpy()
    return (row["kinetic_energy"] + row["potential_energy"],
            energy_bound(sim.model.mass, gravity, row["kinetic_energy"]))
