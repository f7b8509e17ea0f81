"""A reader for plain triangle OBJ files, so that start-up need not import trimesh.

Importing trimesh costs ~0.45 s of a ~2 s start-up; the assets and the
handout's sphere are plain OBJ: ``v x y z`` lines, triangles ``f a b c`` (each
index optionally ``a/t/n``), and ``vt``/``vn``/``s``/comment lines. For those,
this reader returns what trimesh returns with ``process=False,
maintain_order=True`` (the file's vertices in file order, faces 0-based).
Anything else (polygons, negative indices, groups, materials, odd lines)
returns None and ``rigid.bodies.mesh.load_mesh`` hands the file to trimesh, which
also reports garbled files.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

SKIPPED = {"vt", "vn", "s"}


def read_plain_obj(path: str | Path) -> tuple[np.ndarray, np.ndarray] | None:
    """(vertices (V, 3) float64, faces (F, 3) int64) of a plain triangle OBJ, else None."""
    try:
        lines = Path(path).read_text().splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    vertices, faces = [], []
    for line in lines:
        parts = line.split()
        if not parts or parts[0].startswith("#") or parts[0] in SKIPPED:
            continue
        if parts[0] == "v" and len(parts) in (4, 7):  # a position, or a position and a colour
            vertices.append(parts[1:4])
        elif parts[0] == "f" and len(parts) == 4:
            faces.append([p.split("/")[0] for p in parts[1:]])
        else:
            return None
    try:
        v = np.array(vertices, dtype=np.float64).reshape(-1, 3)
        f = np.array(faces, dtype=np.int64).reshape(-1, 3)
    except ValueError:
        return None
    if len(v) == 0 or (len(f) and (f.min() < 1 or f.max() > len(v))):
        return None
    return v, f - 1
