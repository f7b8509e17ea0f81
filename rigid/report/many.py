"""The report's many-body runs: the pile and the dominoes, simulated and drawn in this process.

Each scene runs from its TOML (float32, CPU, as the rest of the report) for a fixed number
of frames; the energies are read from ``sim.snapshot()`` after every frame, and a few frames
are drawn offscreen by the project's own renderer (``rigid.view.render.SceneRenderer`` on
``rigid.view.raster.Rasterizer``: Taichi kernels, no window, no Vulkan), labelled with their
time and put side by side in one PNG. Many-body runs are bit-reproducible (every sum has a
fixed order) and the rasteriser resolves depth with an atomic minimum, so the same command
gives the same bytes.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]  # the repository
GAP = 4  # white pixels between the panels of a still grid


@dataclass(frozen=True)
class ManyRun:
    """What to run and draw: a scene, its frames, the frames to draw, the camera."""
    name: str
    frames: int
    stills: tuple  # frame numbers (0 = the initial state)
    target: tuple = (0.0, -0.35, 0.0)
    distance: float = 4.6
    azimuth_deg: float = 28.0
    elevation_deg: float = 20.0


def runs(quick: bool) -> dict:
    """The pile (120 bodies) settles within ~5 s; the dominoes have all fallen by ~2 s. ``quick``
    (the tests' report): the pile's first half second (its first bodies landing), the dominoes'
    first second."""
    pile = ManyRun("pile", 30, (0, 10, 20, 30), distance=4.4) if quick else \
        ManyRun("pile", 300, (0, 20, 40, 300), distance=4.4)
    domino_stills = (0, 20, 40, 60) if quick else (0, 40, 80, 120)
    dominoes = ManyRun("dominoes", domino_stills[-1], domino_stills, (0.0, -0.9, 0.0), 1.9, 25.0, 28.0)
    return {"pile": pile, "dominoes": dominoes}


def simulate(run: ManyRun, units, panel_size: tuple, still_path: Path) -> dict:
    """Run ``run``'s scene; write its stills (a 2 x 2 grid of panels) to ``still_path``.

    Returns the energies per frame (``t``, ``kinetic_energy``, ``potential_energy``: (F+1,)
    float64, row 0 the initial state), the last snapshot (``last``), ``bodies``,
    ``particles``, ``faces``, ``integrator`` (the scheme's name), ``substeps``, and per still
    its time (``still_times``) and how many bodies had turned more than 45° (``fallen``).
    """
    from ..config import SimConfig, load_scene
    from ..engine.simulator import Simulator
    from ..view.orbit import OrbitCamera
    from ..view.render import SceneRenderer

    config = SimConfig(**load_scene(ROOT / "assets" / "scenes" / f"{run.name}.toml")).validate()
    sim = Simulator(config, units)
    renderer = SceneRenderer(sim, panel_size, offscreen=True)
    renderer.orbit = OrbitCamera(run.target, run.distance, run.azimuth_deg, run.elevation_deg)
    rows, panels, fallen = [], [], []
    q0 = sim.snapshot()["q"]
    try:
        for i in range(run.frames + 1):
            if i:
                sim.step_frame()
            snap = sim.snapshot()
            rows.append((sim.time, snap["kinetic_energy"], snap["potential_energy"]))
            if i in run.stills:
                renderer.draw()
                panels.append(_label(renderer.read_rgba(), f"t = {sim.time:.2f} s"))
                fallen.append(int((tilt_deg(q0, snap["q"]) > 45.0).sum()))
    finally:
        renderer.close()
    save_grid(panels, still_path)
    t, kinetic, potential = (np.array(c, np.float64) for c in zip(*rows))
    return dict(t=t, kinetic_energy=kinetic, potential_energy=potential, last=snap,
                bodies=sim.model.num_bodies, particles=sim.model.num_particles, faces=sim.model.num_faces,
                integrator=SCHEMES.get(config.integrator, config.integrator), substeps=sim.substeps,
                still_times=[float(t[i]) for i in run.stills], fallen=fallen, path=still_path)


SCHEMES = {"euler": "explicit Euler", "symplectic": "symplectic Euler"}


def tilt_deg(q0: np.ndarray, q: np.ndarray) -> np.ndarray:
    """(B,) angle in degrees each body turned from q0 to q ((B, 4) unit quaternions)."""
    dot = np.abs(np.sum(q0 * q, axis=1))
    return np.degrees(2.0 * np.arccos(np.clip(dot, 0.0, 1.0)))


def _label(frame: np.ndarray, text: str) -> np.ndarray:
    from ..view.imaging import TextOverlay

    TextOverlay(frame.shape[0]).draw(frame, text)
    return frame


def save_grid(panels: list, path: Path, columns: int = 2) -> None:
    """Panels (H, W, 4) uint8, row by row, with white gaps, as one RGB PNG (no metadata)."""
    from PIL import Image

    h, w = panels[0].shape[:2]
    rows = -(-len(panels) // columns)
    grid = np.full((rows * h + (rows - 1) * GAP, columns * w + (columns - 1) * GAP, 3), 255, np.uint8)
    for k, panel in enumerate(panels):
        r, c = divmod(k, columns)
        grid[r * (h + GAP):r * (h + GAP) + h, c * (w + GAP):c * (w + GAP) + w] = panel[..., :3]
    Image.fromarray(grid).save(path, format="PNG")
