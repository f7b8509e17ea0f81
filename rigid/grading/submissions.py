"""Find submissions in the paths a TA gives: .py files, folders and .zip files.

A folder holds one submission per .py file, per .zip and per subfolder. A zip
(the handout's ``uid_name_assignment3.zip``) or a subfolder must hold
``rigid_body_dynamic.py``, possibly in a subfolder (the shallowest wins;
macOS ``__MACOSX`` copies are ignored); failing that, its only .py file.
Zips are read in memory, never extracted, so member names cannot escape.
"""
import re
import zipfile
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from ..errors import UserError

FILE_NAME = "rigid_body_dynamic.py"
MAX_BYTES = 2 << 20  # a submission file larger than 2 MB is not an assignment file
MAX_MESH_BYTES = 16 << 20  # a mesh beside it (original handout format) up to 16 MB
MESH_SUFFIXES = (".obj", ".ply", ".stl", ".off")
ZIP_NAME = re.compile(r"^(?P<uid>[^_]+)_(?P<name>.+)_assignment3$", re.IGNORECASE)


@dataclass
class Submission:
    name: str  # shown in reports: the path as given, or folder/entry
    path: Path
    kind: str  # "file", "folder" or "zip"

    @property
    def student(self) -> tuple:
        """(uid, name) from a uid_name_assignment3 stem, else ("", "")."""
        m = ZIP_NAME.match(self.path.stem if self.kind != "folder" else self.path.name)
        return (m["uid"], m["name"]) if m else ("", "")

    @property
    def file_name(self) -> str:
        """The file graded, as the student named it (a zip's or folder's member), for messages."""
        if self.kind == "file":
            return self.path.name
        return f"{self.path.name}/{getattr(self, 'member', FILE_NAME)}"

    def read(self) -> tuple:
        """(bytes, "") or (None, why this submission cannot be graded)."""
        try:
            if self.kind == "file":
                return _checked(self.path.read_bytes(), self.path.name)
            data, problem, self.member = (_from_folder if self.kind == "folder" else _from_zip)(self.path)
            return data, problem
        except OSError as err:
            return None, f"cannot read {self.path}: {err.strerror or err}"


    def meshes(self) -> dict:
        """Mesh files in the submission's zip or folder, by file name (what a file of the original
        handout's format may read); {} for a single .py file or when they cannot be read."""
        found = {}
        try:
            if self.kind == "folder":
                for p in sorted(self.path.rglob("*")):
                    if p.suffix.lower() in MESH_SUFFIXES and p.is_file() and p.stat().st_size <= MAX_MESH_BYTES:
                        found.setdefault(p.name, p.read_bytes())
            elif self.kind == "zip":
                with zipfile.ZipFile(self.path) as z:
                    for i in z.infolist():
                        name = PurePosixPath(i.filename)
                        if (name.suffix.lower() in MESH_SUFFIXES and "__MACOSX" not in name.parts
                                and i.file_size <= MAX_MESH_BYTES):
                            found.setdefault(name.name, z.read(i))
        except (OSError, zipfile.BadZipFile, zipfile.LargeZipFile, NotImplementedError, RuntimeError):
            return {}
        return found


def _checked(data: bytes, where: str) -> tuple:
    if len(data) > MAX_BYTES:
        return None, f"{where} is {len(data) >> 20} MB, too large for an assignment file"
    return data, ""


def _pick(names: list) -> str | None:
    names = [n for n in names if "__MACOSX" not in PurePosixPath(n).parts]
    exact = sorted((n for n in names if PurePosixPath(n).name == FILE_NAME), key=lambda n: (n.count("/"), n))
    if exact:
        return exact[0]
    py = [n for n in names if n.endswith(".py")]
    return py[0] if len(py) == 1 else None


def _from_folder(folder: Path) -> tuple:
    names = [p.relative_to(folder).as_posix() for p in folder.rglob("*.py") if p.is_file()]
    chosen = _pick(names)
    if chosen is None:
        return None, f"folder {folder.name} holds no {FILE_NAME}", FILE_NAME
    return (*_checked((folder / chosen).read_bytes(), chosen), chosen)


def _from_zip(path: Path) -> tuple:
    try:
        with zipfile.ZipFile(path) as z:
            infos = {i.filename: i for i in z.infolist() if not i.is_dir()}
            chosen = _pick(list(infos))
            if chosen is None:
                return None, f"{path.name} holds no {FILE_NAME}", FILE_NAME
            if infos[chosen].file_size > MAX_BYTES:
                return None, f"{chosen} in {path.name} is too large for an assignment file", chosen
            return (*_checked(z.read(chosen), chosen), chosen)
    except (zipfile.BadZipFile, zipfile.LargeZipFile, NotImplementedError, RuntimeError) as err:
        return None, f"{path.name} is not a readable zip file ({err})", FILE_NAME


def discover(paths) -> tuple:
    """(submissions sorted by name within each path, notes about skipped entries). UserError on a bad path."""
    found, notes = [], []
    for given in map(Path, paths):
        if not given.exists():
            raise UserError(f"{given} not found; give .py files, .zip files or folders of them")
        if given.is_file():
            if given.suffix.lower() not in (".py", ".zip"):
                raise UserError(f"{given}: give a .py file, a .zip file or a folder")
            found.append(Submission(str(given), given, "file" if given.suffix.lower() == ".py" else "zip"))
            continue
        entries = sorted(given.iterdir())
        if any(e.name == FILE_NAME for e in entries):
            notes.append(f"note: {given} holds {FILE_NAME}: each .py file in it is graded as a submission")
        for entry in entries:
            if entry.name.startswith(".") or entry.name == "__MACOSX":
                continue
            shown = str(given / entry.name)
            if entry.is_dir():
                found.append(Submission(shown, entry, "folder"))
            elif entry.suffix.lower() in (".py", ".zip"):
                found.append(Submission(shown, entry, "file" if entry.suffix.lower() == ".py" else "zip"))
            else:
                notes.append(f"skipped {shown}: not a .py file, a .zip file or a folder")
    if not found:
        raise UserError(f"no submissions found in {', '.join(map(str, paths))}; give .py files, "
                        f".zip files or folders of them")
    return found, notes
