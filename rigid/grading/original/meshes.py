"""The mesh files a submission in the original format reads, and what its sandbox gets for them.

The handout reads ``sphere.obj`` from the working folder with its own
``read_obj_file(path, scale=0.3)``; students may read another mesh. For every
quoted path ending in a mesh suffix, the sandbox gets, in this order: the file
of that name in the student's zip or folder, the file of that name beside the
course's handout (``grade.py --original-handout``: the handout's own meshes,
what the student ran with, so no note), or, with a note saying which, the project's asset of that name or its
sphere.obj. The project's sphere.obj is a 42-vertex, 80-face icosphere like
the handout's, but with other coordinates and orientation: a spin or a bonus
figure can differ from the student's own run, so its use is always noted. A
path the sandbox cannot hold (absolute, or with '..') is read from the sandbox
folder under its file name instead.
"""
import re
from pathlib import PurePosixPath, PureWindowsPath

from ...config import REPO_ROOT

ASSETS = REPO_ROOT / "assets"
LITERAL = re.compile(r"""(["'])([^"'\n]{1,200}\.(?:obj|ply|stl|off))\1""", re.IGNORECASE)


PROJECT_MESH = ("the project's {name} (its 42-vertex icosphere has the handout's vertex and face counts but other "
                "coordinates and orientation, so spins and bonus figures can differ from the student's run)")


def plan(text: str, companions: dict | None = None, handout_folder=None) -> tuple:
    """(files {relative path: bytes}, renames {path in the file: path in the sandbox}, notes)."""
    companions = companions or {}
    files, renames, notes = {}, {}, []
    for path in dict.fromkeys(m[2] for m in LITERAL.finditer(text)):
        name = PureWindowsPath(path).name if "\\" in path else PurePosixPath(path).name
        target = path
        pure = PurePosixPath(path.replace("\\", "/"))
        if pure.is_absolute() or ".." in pure.parts or re.match(r"^[A-Za-z]:", path) or "\\" in path:
            target = renames[path] = name
        missing = f"the file reads {path}, which the submission does not include: graded with"
        if name in companions:
            data = companions[name]
        elif handout_folder is not None and (handout_folder / name).is_file():
            data = (handout_folder / name).read_bytes()  # what the student ran with: no note
        elif (ASSETS / name).is_file():
            data = (ASSETS / name).read_bytes()
            notes.append(f"{missing} " + (PROJECT_MESH.format(name=name) if name == "sphere.obj"
                                          else f"the project's {name}"))
        elif name.lower().endswith(".obj"):
            data = (ASSETS / "sphere.obj").read_bytes()
            notes.append(f"{missing} {PROJECT_MESH.format(name='sphere.obj')} in its place")
        else:
            notes.append(f"the file reads {path}, which the submission does not include")
            continue
        files[target] = data
    if not files:  # no mesh path read: the mesh may come from elsewhere (a generated one); sphere.obj at hand
        files["sphere.obj"] = (ASSETS / "sphere.obj").read_bytes()
    return files, renames, notes
