"""``--export``: the file's suffix picks the format; several exports come from the same frames.

- ``.npz``: the trajectory (rigid.run.diagnostics, the contract's keys)
- ``.glb`` / ``.gltf``: animated glTF 2.0 (rigid.run.export_gltf)
- ``.usd`` / ``.usda`` / ``.usdc``: animated USD (rigid.run.export_usd; needs usd-core)

``check_exports`` runs before the simulation (one line and exit code 2 on a bad path, an
unknown suffix or a missing usd-core); ``write_exports`` runs after it, on the frames
kept (all, or those before a blow-up or Ctrl-C), each file written atomically.
"""
from __future__ import annotations

import sys
from pathlib import Path

from ..errors import UserError
from .atomic import atomic_output, check_output_path

FORMATS = {".npz": "trajectory", ".glb": "glTF", ".gltf": "glTF", ".usd": "USD", ".usda": "USD", ".usdc": "USD"}
SUFFIX_HINT = ".npz (the trajectory), .glb or .gltf (glTF 2.0), .usd, .usda or .usdc (USD)"


def export_paths(value) -> list[Path]:
    """None, one path, or a list of paths (``--export`` given several times), in order, once each."""
    if value is None:
        return []
    values = [value] if isinstance(value, (str, Path)) else list(value)
    return list(dict.fromkeys(Path(v) for v in values))


def check_exports(value) -> list[Path]:
    """Fail early (UserError: one line, exit 2) on an export the run could not write."""
    paths = export_paths(value)
    for path in paths:
        suffix = path.suffix.lower()
        if suffix not in FORMATS:
            raise UserError(f"output {path}: use a file name ending in {SUFFIX_HINT}")
        check_output_path(path)
        if FORMATS[suffix] == "USD":
            from .export_usd import INSTALL_HINT, require_usd

            try:
                require_usd()
            except ImportError:
                raise UserError(f"output {path}: USD export needs the usd-core package; {INSTALL_HINT}") from None
    return paths


def write_exports(value, trajectory, sim) -> None:
    """Write every export of ``value`` from ``trajectory`` (the frames kept), NPZ first."""
    paths = sorted(export_paths(value), key=lambda p: FORMATS.get(p.suffix.lower()) != "trajectory")
    arrays = trajectory.arrays()
    motion = None
    for path in paths:
        kind = FORMATS.get(path.suffix.lower(), "trajectory")
        if kind == "trajectory":
            trajectory.save(path)
            print(f"wrote {path} ({trajectory.num_rows} rows)", file=sys.stderr)
            continue
        if motion is None:
            from .export_motion import motion_from

            motion = motion_from(arrays, sim.model.body_surfaces(), sim.config)
        if kind == "glTF":
            from .export_gltf import write_gltf as write
        else:
            from .export_usd import write_usd as write
        with atomic_output(path) as tmp:
            write(tmp, motion)
        bodies = f"{motion.num_bodies} bod{'y' if motion.num_bodies == 1 else 'ies'}"
        print(f"wrote {path} ({kind}: {bodies}, {motion.num_keys} keys)", file=sys.stderr)
