"""The trajectory check: a short simulated run against the reference run.

A small asymmetric body of 10 particles (mass 0.7, not 1) is thrown at the
floor and a wall of the box under a slanted gravity, spinning, with Δt =
1.25 ms (not 1 ms): every TODO matters (contact gives torque; gravity alone
gives none about the centre of mass). ``run(units)`` builds the engine's
Simulator with the given units and returns the state (x, q, L) at
CHECKPOINTS substeps, shape (len(CHECKPOINTS), 10): x (3), q (4, scalar
first), L (3), world frame. ``compare`` gives the largest error of each,
relative to the reference's size (x in metres over a ~1 m box).
"""
import numpy as np

from ..config import SimConfig
from ..bodies.mesh import BodyGeometry
from ..engine.simulator import Simulator
from .diagnose import agreement

SUBSTEPS_PER_CHECKPOINT = 160
CHECKPOINTS = 3  # after 160, 320, 480 substeps = 0.6 s: free flight, floor, wall
RTOL = 1e-5


def scenario():
    rng = np.random.default_rng(7)
    particles = rng.uniform(-1, 1, size=(10, 3)) * np.array([0.3, 0.2, 0.12])
    config = SimConfig(particle_mass=0.7, dt=1.25e-3, gravity=(0.6, -9.8, -0.4), position=(0.3, -0.6, -0.2),
                       initial_velocity=(2.5, -2.5, 1.0), initial_angular_velocity=(4.0, -3.0, 6.0)).validate()
    return config, BodyGeometry(particles, particles, np.zeros((0, 3), np.int32))


def run(units) -> np.ndarray:
    config, geometry = scenario()
    sim = Simulator(config, units, geometry)
    rows = []
    for _ in range(CHECKPOINTS):
        sim.step_frame(SUBSTEPS_PER_CHECKPOINT)
        s = sim.snapshot()
        rows.append(np.concatenate([s["x"][0], s["q"][0], s["L"][0]]))
    return np.array(rows)


def compare(out: np.ndarray, ref: np.ndarray) -> dict:
    """{"x": err, "q": err, "L": err}: largest difference over checkpoints, relative; inf if not finite."""
    errors = {}
    for name, cols, scale in (("x", slice(0, 3), 1.0), ("q", slice(3, 7), 1.0),
                              ("L", slice(7, 10), max(float(np.max(np.linalg.norm(ref[:, 7:10], axis=1))), 1e-12))):
        diff = out[:, cols] - ref[:, cols]
        errors[name] = float(np.max(np.abs(diff))) / scale if np.all(np.isfinite(diff)) else float("inf")
    return errors


def passed(errors: dict) -> bool:
    return all(e <= RTOL for e in errors.values())


def summary(errors: dict) -> str:
    """For a run that agrees: one short clause."""
    steps = SUBSTEPS_PER_CHECKPOINT * CHECKPOINTS
    return f"a {steps}-substep simulation agrees with the reference to {agreement(max(errors.values()))}"


def describe(errors: dict) -> str:
    steps = SUBSTEPS_PER_CHECKPOINT * CHECKPOINTS
    return (f"after {steps} substeps x is off by {errors['x']:.1e} m, q by {errors['q']:.1e}, "
            f"L by {errors['L']:.1e} (relative; allowed {RTOL:g})")
