"""A mesh file holding several meshes: one body per mesh, where the file places it.

A GLB places meshes at the nodes of its scene graph, and an ASCII STL may hold several
solids; trimesh reads either as a Scene. ``read_mesh`` joins the meshes (one body whose
parts, touching or not, would move in lockstep); ``entry_geometries`` makes one body of
each mesh placed in the scene instead (``rigid.config.mesh_count`` counts them, so that
the config knows the scene has several bodies):

- a body is a node with a mesh, the mesh's primitives joined (a glTF mesh drawn in two
  materials is one body); a mesh placed by two nodes is two bodies;
- its vertices are the mesh's, moved by the node's world transform (file units), then
  scaled by ``scale`` about the file's origin; coincident vertices are merged per mesh;
- order: the file's meshes in order, the nodes of one mesh by name (trimesh's traversal
  order is not the file's).

Placement (rigid.bodies.placement): the group is placed as one rigid body. Its centre of
mass (every particle of every mesh, equal masses) goes to ``position``, ``orientation``
turns the group about it, and the group starts as one rigid body moving with velocity v0
and angular velocity ω: body i at x_i gets v_i = v0 + ω × (x_i − x) and ω. Each body's
orientation is that of the group, so its body frame is the file's frame (as for one body).
A file with one mesh is read by ``read_mesh``, as always.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..config import mesh_count
from ..errors import UserError
from .mesh import BodyGeometry, Mesh, body_geometry, checked_mesh, mesh_geometry


def entry_geometries(config) -> list[tuple[str, BodyGeometry]]:
    """(mesh name, geometry) per body of the config's mesh file: [("", body_geometry(config))]
    for a file with one mesh; one per mesh of the scene otherwise, the first note saying so."""
    if mesh_count(config.mesh) < 2:
        return [("", body_geometry(config))]
    path = Path(config.mesh)
    parts = read_mesh_parts(path, config.scale)
    out = []
    for name, mesh in parts:
        try:
            geometry = mesh_geometry(mesh, f"mesh '{name}' of {path.name}", config)
        except UserError as err:
            raise UserError(f"mesh file {path}, mesh '{name}': {err}") from None
        out.append((name, geometry))
    first = out[0][1]
    first.note = f"{path.name} holds {len(out)} meshes: {len(out)} bodies\n{first.note}"
    return out


def read_mesh_parts(path: Path, scale: float = 1.0) -> list[tuple[str, Mesh]]:
    """(name, Mesh) per mesh placed in the file's scene: world-frame vertices, scaled, merged."""
    import trimesh  # deferred: slow to import

    try:
        placed = _stl_solids(path) if path.suffix.lower() == ".stl" else _scene_meshes(trimesh, path)
    except Exception as err:  # trimesh raises many types for garbled files
        raise UserError(f"mesh file {path} could not be read ({type(err).__name__}: "
                        f"{str(err).splitlines()[0] if str(err) else 'garbled'}); "
                        f"check that it is a valid {path.suffix} file") from None
    parts = []
    for name, T, vertices, faces in placed:
        vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3) @ T[:3, :3].T + T[:3, 3]
        faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
        if np.linalg.det(T[:3, :3]) < 0:  # a mirroring node: keep the triangles facing outward
            faces = faces[:, ::-1]
        parts.append((name, checked_mesh(path, vertices, faces, scale, where=f", mesh '{name}'")))
    return parts


def _scene_meshes(trimesh, path: Path) -> list:
    """(node name, world transform (4, 4), vertices, faces) per node with a mesh: the file's meshes
    in order, the nodes of one mesh by name."""
    scene = trimesh.load(str(path), force="scene", process=False, maintain_order=True, merge_primitives=True)
    graph = scene.graph
    order = {name: i for i, name in enumerate(scene.geometry)}
    out = []
    for node in sorted(graph.nodes_geometry, key=lambda node: (order[graph[node][1]], str(node))):
        transform, geometry_name = graph[node]
        geometry = scene.geometry[geometry_name]
        out.append((str(node), np.asarray(transform, dtype=np.float64), geometry.vertices,
                    getattr(geometry, "faces", np.zeros((0, 3)))))
    return out


def _stl_solids(path: Path) -> list:
    """The solids of an ASCII STL, as the file stores them: trimesh.load would build a Scene of
    processed meshes (its own merging of nearby vertices) where one solid is read unprocessed."""
    from trimesh.exchange.stl import load_stl

    with open(path, "rb") as file:
        loaded = load_stl(file)
    solids = loaded.get("geometry", {"": loaded})
    return [(name, np.eye(4), solid["vertices"], solid["faces"]) for name, solid in solids.items()]


def group_centre(geometries: list[BodyGeometry]) -> np.ndarray:
    """Centre of mass (3,) of the group's particles, all of one mass (mesh frame)."""
    return np.concatenate([g.particles for g in geometries]).mean(axis=0)
