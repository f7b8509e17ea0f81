"""Meshes in, particles out.

``read_mesh`` (and ``load_mesh``, its (vertices, faces) tuple) reads OBJ, STL, PLY, OFF
and GLB (plain OBJ without trimesh, rigid.bodies.objfile) and returns the file's vertex
positions, in file order: an OBJ with ``vt``/``vn`` lines is not split into one vertex
per (position, uv, normal) triple, because every vertex is a particle of the body (the
handout's sphere.obj gives 42, not 240). Vertices at the same point are merged (first
occurrence kept, faces re-indexed): an STL stores each triangle's own three corners, and
glTF or OBJ exporters split vertices at UV or normal seams, so without merging a box would
weigh 36 or 24 particles instead of 8. ``Mesh.note`` says what was merged.

A file holding several meshes (a GLB's nodes, an ASCII STL's solids) is joined into one
here; rigid.bodies.group reads it as one body per mesh, and scenes use that.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import UserError

FORMATS = (".obj", ".stl", ".ply", ".off", ".glb")


@dataclass
class Mesh:
    """A mesh file read: vertices (V, 3) float64, scaled; faces (F, 3) int32 triangles; and a
    note on what reading changed ("" if nothing), e.g. "its 12 triangles' 36 corners merged
    into 8 vertices"."""

    vertices: np.ndarray
    faces: np.ndarray
    note: str = ""


def load_mesh(path: str | Path, scale: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Return (vertices (V, 3) float64, scaled; faces (F, 3) int32 triangles): ``read_mesh``."""
    mesh = read_mesh(path, scale)
    return mesh.vertices, mesh.faces


def read_mesh(path: str | Path, scale: float = 1.0) -> Mesh:
    """Read a mesh file, coincident vertices merged; every problem is a one-line UserError."""
    path = Path(path)
    if path.is_dir():
        raise UserError(f"mesh file {path} is a folder, not a file; {_folder_hint(path)}")
    if not path.is_file():
        raise UserError(f"mesh file {path} not found; check the path or use one from assets/ "
                        f"(e.g. --mesh assets/sphere.obj)")
    if path.suffix.lower() not in FORMATS:
        raise UserError(f"mesh file {path}: format {path.suffix or '(none)'} is not supported; "
                        f"use one of {', '.join(FORMATS)}")
    from .objfile import read_plain_obj  # plain OBJ without trimesh: a faster start-up

    if path.suffix.lower() == ".stl":
        check_binary_stl_size(path)
    plain = read_plain_obj(path) if path.suffix.lower() == ".obj" else None
    if plain is not None:
        vertices, faces = plain
    else:
        vertices, faces = _load_with_trimesh(path)
    return checked_mesh(path, vertices, faces, scale)


def check_binary_stl_size(path: Path) -> None:
    """A binary STL is an 80-byte header, a triangle count n and 50 bytes a triangle: a count
    that the file's size does not match is a truncated or damaged file (trimesh then reads
    nothing, and the message would say only "no vertices"). ASCII STL files pass."""
    size = path.stat().st_size
    if size < 84:
        return  # too short to be binary: trimesh's ASCII reader says what it finds
    with path.open("rb") as f:
        head = f.read(1024)
    count = int.from_bytes(head[80:84], "little")
    if 84 + 50 * count == size:
        return
    text = head.lstrip().lower()
    if text.startswith(b"solid") and (b"facet" in text or b"endsolid" in text):
        return  # ASCII
    whole = (size - 84) / 50
    raise UserError(f"mesh file {path}: its binary STL header says {count:,} triangles, which take "
                    f"84 + 50 x {count:,} = {84 + 50 * count:,} bytes, but the file has {size:,} bytes "
                    f"({'room for ' + format(int(whole), ',') + ' triangles' if whole == int(whole) else 'not a whole number of triangles'}); "
                    f"the file is truncated or damaged: export it again")


def checked_mesh(path: Path, vertices: np.ndarray, faces: np.ndarray, scale: float, where: str = "") -> Mesh:
    """A Mesh of vertices and faces read from ``path``: checked, coincident vertices merged, scaled
    (``where``: which mesh of the file, e.g. ", mesh 'box'", for the messages)."""
    if vertices.ndim != 2 or len(vertices) == 0:
        raise UserError(f"mesh file {path}{where} has no vertices (empty, or not a valid {path.suffix} file); "
                        f"use a mesh with vertices that span a volume")
    if not np.all(np.isfinite(vertices)):
        raise UserError(f"mesh file {path}{where} has non-finite vertex coordinates; repair the file")
    if len(faces) and (faces.min() < 0 or faces.max() >= len(vertices)):
        raise UserError(f"mesh file {path}{where} has faces that index missing vertices; repair the file")
    vertices, faces, note = merge_coincident(vertices, faces, stl=path.suffix.lower() == ".stl")
    return Mesh(vertices * float(scale), faces.astype(np.int32), note)


def _folder_hint(folder: Path) -> str:
    import shlex

    try:
        meshes = sorted(p for p in folder.iterdir() if p.suffix.lower() in FORMATS and p.is_file())
    except OSError:
        meshes = []
    if not meshes:
        return f"name a mesh file ({', '.join(FORMATS)}); this folder holds none"
    return f"name a mesh file in it, e.g. --mesh {shlex.quote(str(meshes[0]))}"


def merge_coincident(vertices: np.ndarray, faces: np.ndarray, stl: bool = False):
    """(vertices, faces, note): one vertex per distinct point, in order of first occurrence;
    faces re-indexed, and those left with two corners at one point (no area) dropped."""
    _, first, inverse = np.unique(vertices + 0.0, axis=0, return_index=True, return_inverse=True)
    if len(first) == len(vertices):
        return vertices, faces, ""
    order = np.argsort(first)  # distinct points in order of first occurrence
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    new_index = rank[np.asarray(inverse).reshape(-1)]
    merged = new_index[faces] if len(faces) else faces
    keep = (merged[:, 0] != merged[:, 1]) & (merged[:, 1] != merged[:, 2]) & (merged[:, 0] != merged[:, 2]) \
        if len(faces) else np.zeros(0, bool)
    if stl and len(vertices) == 3 * len(faces):
        note = f"its {len(faces)} triangles' {len(vertices)} corners merged into {len(first)} vertices"
    else:
        note = (f"its {len(vertices)} vertices lie at {len(first)} distinct points, merged into {len(first)}"
                if len(first) > 1 else f"its {len(vertices)} vertices lie at one point")
    dropped = int((~keep).sum())
    if dropped:
        note += f"; {dropped} triangle{'s' if dropped > 1 else ''} of no area dropped"
    return vertices[first[order]], merged[keep], note


def _load_with_trimesh(path: Path) -> tuple[np.ndarray, np.ndarray]:
    import trimesh  # deferred: slow to import

    try:
        # process=False + maintain_order=True: keep the file's vertices as they are.
        mesh = trimesh.load(str(path), force="mesh", process=False, maintain_order=True)
        vertices = np.asarray(mesh.vertices, dtype=np.float64)
        faces = np.asarray(getattr(mesh, "faces", np.zeros((0, 3))), dtype=np.int64).reshape(-1, 3)
    except Exception as err:  # trimesh raises many types for garbled files
        raise UserError(f"mesh file {path} could not be read ({type(err).__name__}: "
                        f"{str(err).splitlines()[0] if str(err) else 'garbled'}); "
                        f"check that it is a valid {path.suffix} file") from None
    return vertices, faces


def make_particles(vertices: np.ndarray, faces: np.ndarray, mode: str = "vertex",
                   grid: int = 32) -> np.ndarray:
    """Particle positions (N, 3) for a mesh: its vertices, or cell centres inside it."""
    if mode == "vertex":
        return vertices
    from .sampling import sample_volume

    return sample_volume(vertices, faces, grid)


@dataclass
class BodyGeometry:
    """A body before Taichi starts: particles (N, 3) and the drawn mesh (V, 3), (F, 3), world frame."""

    particles: np.ndarray
    vertices: np.ndarray
    faces: np.ndarray
    note: str = ""  # how many particles and why, e.g. "8 particles at the vertices of box.stl (...)"


def body_geometry(config) -> BodyGeometry:
    """Load the config's mesh and make its particles; every input error is raised here, before Taichi.
    A file holding several meshes is joined here: rigid.bodies.group makes one body of each."""
    mesh = read_mesh(config.mesh, config.scale)
    return mesh_geometry(mesh, Path(config.mesh).name, config)


def mesh_geometry(mesh: Mesh, name: str, config) -> BodyGeometry:
    """Particles of a mesh read (config: particles, grid) and the note on them; ``name`` names
    the mesh in the note ("box.stl", or "mesh 'box' of parts.glb")."""
    particles = make_particles(mesh.vertices, mesh.faces, config.particles, config.grid)
    check_not_degenerate(particles, mesh.note)
    if config.particles == "vertex":
        note = f"{len(particles)} particles at the vertices of {name}" + (f" ({mesh.note})" if mesh.note else "")
    else:
        note = (f"{len(particles)} particles at the centres of the cells inside {name} of a grid of "
                f"{config.grid} cells along its longest side" + (f" ({mesh.note})" if mesh.note else ""))
    return BodyGeometry(np.asarray(particles, np.float64), mesh.vertices, mesh.faces, note)


def check_not_degenerate(particles: np.ndarray, why: str = "") -> None:
    """A body needs particles spanning a plane at least, or its I0 is singular (``why``: the mesh's note)."""
    if len(particles) == 0:
        raise UserError("the body has no particles; use a mesh with vertices")
    if len(particles) == 1:
        raise UserError(f"the body has one particle{f' ({why})' if why else ''}, so the inertia tensor is "
                        f"singular; use a mesh that spans a plane or a volume")
    centred = particles - particles.mean(axis=0)
    s = np.linalg.svd(centred, compute_uv=False) if len(particles) > 1 else np.zeros(1)
    if len(s) < 2 or s[0] == 0 or s[1] <= 1e-9 * s[0]:
        shape = "one point" if s[0] == 0 else "one line"
        raise UserError(f"all {len(particles)} particles lie on {shape}, so the inertia tensor is "
                        f"singular; use a mesh that spans a plane or a volume")
