"""The OBJ reader (start-up without trimesh) returns what trimesh returns where trimesh is right, or declines."""
import numpy as np
import trimesh

from conftest import ASSETS


def _trimesh(path):
    mesh = trimesh.load(str(path), force="mesh", process=False, maintain_order=True)
    return np.asarray(mesh.vertices, np.float64), np.asarray(mesh.faces, np.int64)


def test_assets_and_uv_normal_obj_read_as_trimesh_reads_them(tmp_path):
    from rigid.bodies.objfile import read_plain_obj

    s = trimesh.creation.icosphere(subdivisions=1)
    lines = ["# with uv and normals", "s off"] + [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in s.vertices]
    lines += [f"vt {0.5 + x / 2} {0.5 + y / 2}" for x, y, _ in s.vertices]
    lines += [f"vn {x} {y} {z}" for x, y, z in s.face_normals]
    lines += ["f " + " ".join(f"{a + 1}/{a + 1}/{i + 1}" for a in f) for i, f in enumerate(s.faces)]
    (tmp_path / "uv.obj").write_text("\n".join(lines) + "\n")
    paths = sorted(ASSETS.glob("*.obj")) + [tmp_path / "uv.obj"]
    assert len(paths) >= 6
    for path in paths:
        ours = read_plain_obj(path)
        assert ours is not None, path
        theirs = _trimesh(path)
        assert np.array_equal(ours[0], theirs[0]) and np.array_equal(ours[1], theirs[1]), path


def test_polygons_relative_indices_and_groups_read_as_trimesh_reads_them(tmp_path):
    """Where trimesh reads them right (faces after all vertices), the same vertices and triangles."""
    from rigid.bodies.objfile import read_plain_obj

    text = ("mtllib m.mtl\no body\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\ng side\nusemtl red\n"
            "f -5 -4 -3 -2\nf 1 2 5\nf -2 -3 -1\n")
    (tmp_path / "m.obj").write_text(text)
    ours, theirs = read_plain_obj(tmp_path / "m.obj"), _trimesh(tmp_path / "m.obj")
    assert np.array_equal(ours[0], theirs[0])
    assert sorted(map(sorted, ours[1].tolist())) == sorted(map(sorted, theirs[1].tolist()))


def test_anything_unusual_goes_to_trimesh(tmp_path):
    from rigid.bodies.objfile import read_plain_obj

    cases = {"line element": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 2\n",
             "index 0": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
             "before the first": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -2 -1\n",
             "out of range": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
             "two corners": "v 0 0 0\nv 1 0 0\nf 1 2\n",
             "garbled": "v 0 zero 0\n", "garbled face": "v 0 0 0\nf a b c\n", "empty": ""}
    for name, text in cases.items():
        (tmp_path / "m.obj").write_text(text)
        assert read_plain_obj(tmp_path / "m.obj") is None, name
