"""Meshes in, particles out.

``load_mesh`` reads OBJ, STL, PLY, OFF and GLB through trimesh and returns the
file's own vertex positions, in file order: an OBJ with ``vt``/``vn`` lines is
not split into one vertex per (position, uv, normal) triple, because every
vertex is a particle of the body (the handout's sphere.obj gives 42, not 240).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import UserError

FORMATS = (".obj", ".stl", ".ply", ".off", ".glb")


def load_mesh(path: str | Path, scale: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Return (vertices (V, 3) float64, scaled; faces (F, 3) int32 triangles)."""
    path = Path(path)
    if not path.is_file():
        raise UserError(f"mesh file {path} not found; check the path or use one from assets/ "
                        f"(e.g. --mesh assets/sphere.obj)")
    if path.suffix.lower() not in FORMATS:
        raise UserError(f"mesh file {path}: format {path.suffix or '(none)'} is not supported; "
                        f"use one of {', '.join(FORMATS)}")
    from .objfile import read_plain_obj  # plain OBJ without trimesh: 0.45 s less start-up

    plain = read_plain_obj(path) if path.suffix.lower() == ".obj" else None
    if plain is not None:
        vertices, faces = plain
    else:
        vertices, faces = _load_with_trimesh(path)
    if vertices.ndim != 2 or len(vertices) == 0:
        raise UserError(f"mesh file {path} has no vertices (empty, or not a valid {path.suffix} file); "
                        f"use a mesh with vertices that span a volume")
    if not np.all(np.isfinite(vertices)):
        raise UserError(f"mesh file {path} has non-finite vertex coordinates; repair the file")
    if len(faces) and (faces.min() < 0 or faces.max() >= len(vertices)):
        raise UserError(f"mesh file {path} has faces that index missing vertices; repair the file")
    return vertices * float(scale), faces.astype(np.int32)


def _load_with_trimesh(path: Path) -> tuple[np.ndarray, np.ndarray]:
    import trimesh  # deferred: 0.45 s of import time

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


def body_geometry(config) -> BodyGeometry:
    """Load the config's mesh and make its particles; every input error is raised here, before Taichi."""
    vertices, faces = load_mesh(config.mesh, config.scale)
    particles = make_particles(vertices, faces, config.particles, config.grid)
    check_not_degenerate(particles)
    return BodyGeometry(np.asarray(particles, np.float64), vertices, faces)


def check_not_degenerate(particles: np.ndarray) -> None:
    """A body needs particles spanning a plane at least, or its I0 is singular."""
    if len(particles) == 0:
        raise UserError("the body has no particles; use a mesh with vertices")
    centred = particles - particles.mean(axis=0)
    s = np.linalg.svd(centred, compute_uv=False) if len(particles) > 1 else np.zeros(1)
    if len(s) < 2 or s[0] == 0 or s[1] <= 1e-9 * s[0]:
        shape = "one point" if s[0] == 0 else "one line"
        raise UserError(f"all {len(particles)} particles lie on {shape}, so the inertia tensor is "
                        f"singular; use a mesh that spans a plane or a volume")
