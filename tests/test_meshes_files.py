"""Mesh files read right (issue 15, items 3, 4): OBJ relative indices, coincident vertices
merged (an STL box is 8 particles, like the OBJ box), and the note that says so (the CLI prints
it before the summary: tests/test_smoke.py)."""
import numpy as np
import pytest

from conftest import ASSETS, ROOT

DATA = ROOT / "tests" / "data"


def _edges_shared_twice(faces) -> bool:
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    return bool(np.all(counts == 2))


def _same_points(a, b) -> bool:
    return np.array_equal(np.unique(a, axis=0), np.unique(b, axis=0))


def test_relative_indices_read_as_the_cube_they_are():
    """tests/data/cube_relative.obj: box.obj's cube, quads with negative v/vt/vn indices written
    between the v lines (trimesh 5.2 counted back from the file's end: 8 open edges)."""
    from rigid.bodies.mesh import read_mesh
    from rigid.bodies.sampling import sample_volume

    cube, box = read_mesh(DATA / "cube_relative.obj"), read_mesh(ASSETS / "box.obj")
    assert len(cube.vertices) == 8 and len(cube.faces) == 12 and cube.note == ""
    assert _same_points(cube.vertices, box.vertices) and _edges_shared_twice(cube.faces)
    volume = np.einsum("ij,ij->i", cube.vertices[cube.faces[:, 0]],
                       np.cross(cube.vertices[cube.faces[:, 1]], cube.vertices[cube.faces[:, 2]])).sum() / 6
    assert np.isclose(volume, 1.0)  # closed, and every face turned outward
    assert _same_points(sample_volume(cube.vertices, cube.faces, 8), sample_volume(box.vertices, box.faces, 8))


@pytest.mark.parametrize("text, faces", [
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -4 -2 -1\n", [[0, 1, 2], [0, 2, 3]]),  # back from the line
    ("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 -2 -1\n", [[0, 1, 2], [0, 2, 3]]),  # mixed, a quad's fan
    ("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1/1 2/2 3//1 4/4/4 5\n", [[0, 1, 2], [0, 2, 3], [0, 3, 4]]),
    ("mtllib m.mtl\no a\ng b\nusemtl c\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 3 1 2\n", [[2, 0, 1]]),  # forward refs too
])
def test_obj_indices(tmp_path, text, faces):
    from rigid.bodies.objfile import read_plain_obj

    (tmp_path / "m.obj").write_text(text)
    v, f = read_plain_obj(tmp_path / "m.obj")
    assert f.tolist() == faces


def test_stl_box_is_eight_particles_like_the_obj_box():
    from rigid.bodies.mesh import body_geometry
    from rigid.config import SimConfig

    stl = body_geometry(SimConfig(mesh=str(DATA / "box.stl"), scale=1.0).validate())
    obj = body_geometry(SimConfig(mesh=str(ASSETS / "box.obj"), scale=1.0).validate())
    assert len(stl.particles) == len(obj.particles) == 8 and _same_points(stl.particles, obj.particles)
    assert _edges_shared_twice(stl.faces)
    assert stl.note == "8 particles at the vertices of box.stl (its 12 triangles' 36 corners merged into 8 vertices)"
    assert obj.note == "8 particles at the vertices of box.obj"
    volume = body_geometry(SimConfig(mesh=str(DATA / "box.stl"), scale=1.0, particles="volume", grid=4).validate())
    assert len(volume.particles) == 64 and volume.note.startswith("64 particles at the centres of the cells")


def test_seams_merged_in_any_format_and_file_order_kept(tmp_path):
    """A cube written with each face's own four vertices (an exporter's normal seams): 24 -> 8,
    first occurrences in file order; a file without duplicates is left exactly as it is."""
    from rigid.bodies.mesh import merge_coincident, read_mesh

    box = read_mesh(ASSETS / "box.obj")
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    lines = [f"v {x} {y} {z}" for q in quads for x, y, z in box.vertices[list(q)]]
    lines += [f"f {4 * i + 1} {4 * i + 2} {4 * i + 3} {4 * i + 4}" for i in range(6)]
    (tmp_path / "seams.obj").write_text("\n".join(lines) + "\n")
    seams = read_mesh(tmp_path / "seams.obj")
    assert seams.note == "its 24 vertices lie at 8 distinct points, merged into 8"
    assert np.array_equal(seams.vertices, box.vertices[[0, 1, 3, 2, 4, 6, 7, 5]]) and _edges_shared_twice(seams.faces)
    v, f, note = merge_coincident(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, -0.0, 0]]), np.array([[0, 1, 3], [0, 1, 2]]))
    assert note.endswith("; 1 triangle of no area dropped") and f.tolist() == [[0, 1, 2]] and len(v) == 3
    sphere = read_mesh(ASSETS / "sphere.obj")
    assert sphere.note == "" and len(sphere.vertices) == 42
