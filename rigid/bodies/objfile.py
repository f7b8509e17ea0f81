"""A reader for OBJ polygon meshes, so that start-up need not import trimesh, and so that
relative face indices are read right.

Importing trimesh is a large part of start-up. This reader takes ``v x y z`` lines
(optionally with a colour), faces ``f a b c ...`` of three or more corners (each ``a``,
``a/t``, ``a//n`` or ``a/t/n``), and skips ``vt``/``vn``/``s``/``o``/``g``/``usemtl``/
``mtllib`` and comment lines: the file's vertices in file order, one mesh, faces 0-based.
For triangle files this is what trimesh returns with ``process=False,
maintain_order=True``; polygons are split into a fan (a, b, c), (a, c, d), ...

A negative index counts back from the last vertex defined *before the face line*
(``f -4 -3 -2 -1`` after four ``v`` lines is those four): trimesh 5.2 counts back from the
end of the file instead, which gives wrong faces when ``v`` and ``f`` lines interleave, and
raises on negative ``vt``/``vn`` indices. A UTF-8 byte-order mark and CRLF line ends are read as
any editor writes them. Anything else (curves, lines, points, an index of 0 or past either end,
garbled numbers) returns None and
``rigid.bodies.mesh.load_mesh`` hands the file to trimesh, which also reports garbled files.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

SKIPPED = {"vt", "vn", "s", "o", "g", "usemtl", "mtllib"}


def read_plain_obj(path: str | Path) -> tuple[np.ndarray, np.ndarray] | None:
    """(vertices (V, 3) float64, faces (F, 3) int64 triangles) of an OBJ polygon mesh, else None."""
    try:
        # utf-8-sig drops a byte-order mark (Windows editors write one), which would otherwise
        # glue itself to the first keyword; splitlines takes CRLF and LF alike.
        lines = Path(path).read_text(encoding="utf-8-sig").splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    vertices, faces = [], []
    for line in lines:
        parts = line.split()
        if not parts or parts[0].startswith("#") or parts[0] in SKIPPED:
            continue
        if parts[0] == "v" and len(parts) in (4, 7):  # a position, or a position and a colour
            vertices.append(parts[1:4])
        elif parts[0] == "f" and len(parts) >= 4:
            corners = _corners(parts[1:], len(vertices))
            if corners is None:
                return None
            faces += [(corners[0], corners[i], corners[i + 1]) for i in range(1, len(corners) - 1)]
        else:
            return None
    try:
        v = np.array(vertices, dtype=np.float64).reshape(-1, 3)
    except ValueError:
        return None
    f = np.array(faces, dtype=np.int64).reshape(-1, 3)
    if len(v) == 0 or (len(f) and f.max() >= len(v)):  # a positive index past the last vertex
        return None
    return v, f


def _corners(tokens: list[str], defined: int) -> list[int] | None:
    """0-based vertex indices of a face's corners; ``defined`` vertices precede the line."""
    out = []
    for token in tokens:
        try:
            index = int(token.split("/")[0])
        except ValueError:
            return None
        if index == 0 or defined + index < 0:  # no vertex 0; nothing before the first
            return None
        out.append(index - 1 if index > 0 else defined + index)  # 1-based, or counted back
    return out
