"""Clean ends a new user met (issue: "tried as a new user would, round four"): files from other
editors load, outputs that cannot be written are refused before the simulation, refusals name
what is wrong without a traceback. Each test here runs without compiling a kernel."""
import numpy as np
import pytest

from conftest import run_cli

WINDOWS_QUADS = ("\ufeff# exported on Windows\r\n"
                 "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\n"
                 "v 0 0 1\r\nv 1 0 1\r\nv 1 1 1\r\nv 0 1 1\r\n"
                 "f -8 -5 -6 -7\r\nf -4 -3 -2 -1\r\nf 1 2 6 5\r\nf 2 3 7 6\r\nf 3 4 8 7\r\nf 4 1 5 8\r\n")


def test_obj_with_bom_crlf_quads_and_negative_indices_loads(tmp_path):
    """A byte-order mark glued to the first keyword made the plain reader give up, and trimesh
    then counted the negative indices from the wrong end ("faces that index missing vertices")."""
    from rigid.bodies.mesh import read_mesh

    path = tmp_path / "cube.obj"
    path.write_bytes(WINDOWS_QUADS.encode("utf-8"))
    mesh = read_mesh(path)
    assert mesh.vertices.shape == (8, 3) and mesh.faces.shape == (12, 3)
    # the first face is the bottom (z = 0) quad, the second the top (z = 1): split into two triangles each
    assert set(np.unique(mesh.vertices[mesh.faces[:2]][..., 2])) == {0.0}
    assert set(np.unique(mesh.vertices[mesh.faces[2:4]][..., 2])) == {1.0}


def test_export_into_a_folder_that_takes_no_files_is_refused_up_front(tmp_path):
    """/proc passes a permission test as root, then the partial file could not be created after
    the whole simulation (a FileNotFoundError traceback)."""
    from rigid.errors import UserError
    from rigid.run.atomic import check_output_path

    with pytest.raises(UserError, match=r"^output folder /proc does not take new files"):
        check_output_path("/proc/t.npz")
    check_output_path(tmp_path / "t.npz")
    assert list(tmp_path.iterdir()) == []  # the probe leaves nothing behind


def test_export_to_proc_exits_2_with_one_line_before_simulating():
    proc = run_cli("--headless", "--frames", "2", "--export", "/proc/t.npz")
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert lines[-1].startswith("error: output folder /proc does not take new files"), proc.stderr
    assert "Traceback" not in proc.stderr
