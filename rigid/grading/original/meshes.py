"""The mesh files a submission in the original format reads, and what its sandbox gets for them.

The handout reads ``sphere.obj`` from the working folder with its own
``read_obj_file(path, scale=0.3)``; students may read another mesh. For every
quoted path ending in a mesh suffix, the sandbox gets, in this order: the file
of that name in the student's zip or folder, the project's asset of that name
(assets/sphere.obj is the handout's 42-vertex icosphere), or, with a note, the
project's sphere.obj in its place. A path the sandbox cannot hold (absolute, or
with '..') is read from the sandbox folder under its file name instead.
"""
import re
from pathlib import PurePosixPath, PureWindowsPath

from ...config import REPO_ROOT

ASSETS = REPO_ROOT / "assets"
LITERAL = re.compile(r"""(["'])([^"'\n]{1,200}\.(?:obj|ply|stl|off))\1""", re.IGNORECASE)


def plan(text: str, companions: dict | None = None) -> tuple:
    """(files {relative path: bytes}, renames {path in the file: path in the sandbox}, notes)."""
    companions = companions or {}
    files, renames, notes = {}, {}, []
    for path in dict.fromkeys(m[2] for m in LITERAL.finditer(text)):
        name = PureWindowsPath(path).name if "\\" in path else PurePosixPath(path).name
        target = path
        pure = PurePosixPath(path.replace("\\", "/"))
        if pure.is_absolute() or ".." in pure.parts or re.match(r"^[A-Za-z]:", path) or "\\" in path:
            target = renames[path] = name
        if name in companions:
            data = companions[name]
        elif (ASSETS / name).is_file():
            data = (ASSETS / name).read_bytes()
        elif name.lower().endswith(".obj"):
            data = (ASSETS / "sphere.obj").read_bytes()
            notes.append(f"the file reads {path}, which the submission does not include: graded with the "
                         f"project's 42-vertex sphere.obj in its place")
        else:
            notes.append(f"the file reads {path}, which the submission does not include")
            continue
        files[target] = data
    if not files:
        files["sphere.obj"] = (ASSETS / "sphere.obj").read_bytes()
    return files, renames, notes
