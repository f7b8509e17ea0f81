"""The Python API: build a scene, step it, read it, export it (``import rigid``).

    import rigid
    rigid.init("cpu")                                   # once per process (Taichi)
    scene = rigid.scene(mesh="sphere.obj", scale=0.3)   # or rigid.load_scene("assets/scenes/pile.toml")
    sim = rigid.Simulator(scene)                        # the repository's solved TODO units
    rows = sim.advance(120)                             # 121 rows: row 0 now, then a row per frame
    rigid.export(sim, rows, "drop.npz", "drop.glb")     # the NPZ, glTF and USD exporters
    rigid.show(sim, frames=300)                         # in Jupyter: the run as an inline video
    rigid.sweep("thrown.toml", {"restitution": [0.2, 0.8]}, frames=60, out="sweep1")  # many runs
    many = rigid.Simulator(scene, worlds=100, vary={"initial_velocity": v0s})  # 100 worlds, one launch

Shapes are per body: ``rows["x"]`` (frames + 1, B, 3); the NPZ of a lone body keeps the
contract's (F, 3). Kernels compile once per process: a second Simulator costs milliseconds.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .config import ASSETS, SimConfig, load_scene as _load_scene_values
from .engine.simulator import Simulator
from .engine.units import default_units, load_units
from .runtime import init_taichi


def init(arch: str = "cpu", fp64: bool = False) -> str:
    """Start Taichi (once per process): ``arch`` "cpu" or "gpu" (CUDA, Metal on a Mac or a hardware
    Vulkan, else the CPU with a note), float64 if ``fp64``. Returns the backend used."""
    return init_taichi(arch, fp64)


def scene(**keys) -> SimConfig:
    """A scene from the scene file's keys (``mesh``, ``scale``, ``position``, ``count``,
    ``collision_stiffness``, ...; ``bodies=[dict(mesh=..., count=...), ...]`` for [[body]]
    tables, ``planes=[...]`` and ``statics=[...]`` for [[plane]] and [[static]] ones). A relative ``mesh`` is looked up in the working folder, then in the assets."""
    from .config import resolve_mesh

    here = Path.cwd() / "scene.toml"  # resolve_mesh looks beside "the file", then in assets/
    if "mesh" in keys:
        keys["mesh"] = resolve_mesh(here, str(keys["mesh"]))
    if "bodies" in keys:
        keys["bodies"] = tuple({**b, **({"mesh": resolve_mesh(here, str(b["mesh"]))} if "mesh" in b else {})}
                               for b in keys["bodies"])
    if "statics" in keys:  # [[static]] tables: planes=[dict(point=..., normal=...)] need nothing
        keys["statics"] = tuple({**t, **({"mesh": resolve_mesh(here, str(t["mesh"]))} if "mesh" in t else {})}
                                for t in keys["statics"])
    for key, value in list(keys.items()):
        if isinstance(value, (list, np.ndarray)) and key != "bodies":
            keys[key] = tuple(value)
    return SimConfig(**keys).validate()


def load_scene(path) -> SimConfig:
    """A scene TOML file (assets/scenes/*.toml) as a validated config."""
    return SimConfig(**_load_scene_values(path)).validate()


def export(sim: Simulator, rows: dict, *paths) -> None:
    """Write ``rows`` (from ``sim.advance``) to each path; the suffix picks the format: .npz
    (the trajectory), .glb/.gltf (glTF 2.0), .usd/.usda/.usdc (USD, needs usd-core)."""
    from .run.diagnostics import Trajectory
    from .run.exports import check_exports, write_exports

    check_exports(list(paths))
    m = sim.model
    trajectory = Trajectory(m.body_mass_np, m.inertia_body_np, sim.params.dt, sim.substeps, sim.config.fp64)
    trajectory.append_block(rows)
    write_exports(list(paths), trajectory, sim)


def show(sim: Simulator, frames: int = 300, resolution=(640, 360), camera=None, format: str = "mp4",
         keep_frames: bool = False):
    """Run ``frames`` frames and return them as a video that Jupyter shows inline (HTML5 <video>,
    or an animated GIF with ``format="gif"``), drawn by the project's software renderer: no
    display, no Vulkan. ``.rows`` holds the trajectory (for plots), ``.frames`` the pictures
    (``keep_frames``), ``.save(path)`` writes the file. ``camera``: the [camera] table's keys
    (position, look_at, fov, follow), e.g. ``dict(follow="centre")``; None takes the scene's
    [camera] table, else frames the scene."""
    from .view.notebook import show as _show

    return _show(sim, frames, resolution, camera, format, keep_frames)


def sweep(scene, vary=(), frames: int = None, out=None, seeds: int = 1, workers: int | None = None,
          ray: str | None = None, record: bool = False, units=None) -> list[dict]:
    """Many runs of ``scene`` (a scene TOML's path, or a SimConfig), as ``python -m rigid sweep``:
    one per combination of the ``vary`` values (``{"restitution": [0.2, 0.5], "dt": "1e-3:2e-3:3"}``
    or ``["restitution=0.2,0.5"]``) and seed, ``frames`` frames each, into the folder ``out``
    (``index.csv``, ``runs/<run>.npz``, ``.mp4`` with ``record``), on ``workers`` processes or a Ray
    cluster (``ray="local"`` or an address), with the TODO units of ``units`` (an assignment file's
    path, or ``rigid.load_units(...)``'s module; default the repository's solution). Resumes a
    sweep begun in ``out``. Returns index.csv's rows (numbers as numbers). Call it from a script's
    ``if __name__ == "__main__":`` block (the workers are spawned)."""
    from .sweeps.driver import sweep as _sweep

    return _sweep(scene, vary, frames, out, seeds, workers, ray, record, units)


def frames(sim: Simulator, frames: int = 60, resolution=(640, 360), camera=None) -> np.ndarray:
    """Run ``frames`` frames and return the drawn pictures, (frames + 1, H, W, 3) uint8 numpy."""
    from .view.notebook import frames as _frames

    return _frames(sim, frames, resolution, camera)


__all__ = ["init", "scene", "load_scene", "Simulator", "export", "show", "frames", "sweep", "load_units",
           "default_units", "SimConfig", "ASSETS"]
