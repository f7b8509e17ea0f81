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


def test_ctrl_c_while_the_kernels_compile_stops_within_seconds(tmp_path):
    """On an empty kernel cache the pile's first frame compiles for tens of seconds inside C++
    calls that hold Python's lock, where Python's own Ctrl-C handling waited for the compile."""
    import os
    import signal
    import subprocess
    import sys
    import time

    from conftest import ROOT, SOLUTION, default_sigint

    env = dict(os.environ, TI_OFFLINE_CACHE_FILE_PATH=str(tmp_path / "cache"))  # nothing compiled yet
    out = tmp_path / "pile.npz"
    proc = subprocess.Popen([sys.executable, str(SOLUTION), "--headless", "--frames", "5", "--scene",
                             "assets/scenes/pile.toml", "--export", str(out)], cwd=ROOT, env=env,
                            stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True, preexec_fn=default_sigint)
    try:
        seen = []
        for line in proc.stderr:  # the simulator is built; its substep's kernels compile next
            seen.append(line)
            if line.startswith("simulating"):
                break
        time.sleep(1.0)
        assert proc.poll() is None, "the run ended before it could be interrupted"
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        code = proc.wait(timeout=60)
        waited = time.monotonic() - sent
        rest = "".join(seen) + proc.stderr.read()
    finally:
        proc.kill()
        proc.wait()
    assert code in (-signal.SIGINT, 130), rest  # ended by the signal (a shell says 130), or caught in Python
    assert waited < 5.0, f"Ctrl-C took {waited:.1f} s to act"
    assert rest.startswith("compiling kernels (first run only") and "Traceback" not in rest, rest
    assert not out.exists() and not list(tmp_path.glob(".pile.partial*"))


def test_one_edge_is_singular():
    """Two tetrahedra sharing one edge: that edge has four triangles, the only bad one."""
    from rigid.bodies.sampling import check_closed
    from rigid.errors import UserError

    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, -1, 0], [0, 0, -1]], float)
    tet = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    other = np.array([[0, 1, 4], [0, 5, 1], [0, 4, 5], [1, 5, 4]])
    with pytest.raises(UserError, match=r"^the mesh is not watertight \(1 edge is not shared by exactly two"):
        check_closed(v, np.concatenate([tet, other]))


def _overlap_message(tmp_path, **keys):
    from rigid.bodies.overlap import check_start
    from rigid.bodies.placement import scene_bodies
    from rigid.bodies.statics import static_bodies
    from rigid.config import SimConfig, load_scene
    from rigid.errors import UserError

    scene = tmp_path / "bowl.toml"
    scene.write_text('[[static]]\nmesh = "bowl.obj"\nscale = 0.7\nposition = [0.0, -0.28, 0.0]\n')
    config = SimConfig(**{**load_scene(scene), **keys}).validate()
    bodies = scene_bodies(config)
    bodies += static_bodies(config, bodies)
    with pytest.raises(UserError) as err:
        check_start(config, bodies)
    return str(err.value)


def test_overlap_message_without_count_or_radius_says_neither(tmp_path):
    """A lone body (particles of no radius) in a bowl's side: no "radius 0", no "lower count"."""
    message = _overlap_message(tmp_path, position=(0.5, -0.45, 0.0))
    assert "radius 0 " not in message and "count" not in message, message
    assert "body 1's particles inside the other's particle spheres of radius" in message, message
    assert message.endswith("move them apart (position)"), message
    copies = _overlap_message(tmp_path, position=(0.5, -0.45, 0.0), count=2, scale=0.2)
    assert copies.endswith("or use a smaller count"), copies


def test_help_says_how_long_a_frame_is():
    """A frame is int((1/60) // dt) substeps: 16 ms at the default, so 300 frames end at 4.8 s."""
    from rigid.cli import build_parser

    text = " ".join(build_parser().format_help().split())
    assert "a frame is 1/60 s" not in text
    assert "16 x 1 ms = 16 ms at the default" in text and "t = 4.8 s at the default dt" in text


def test_copies_that_would_stack_kilometres_high_are_refused():
    """--count 100000 of the default sphere stacked 25,000 layers, 19.5 km high, and crashed the
    process (exit 139); the refusal names the most copies that fit, and that many still place."""
    from rigid.bodies.placement import MAX_STACK_HEIGHT, scene_bodies
    from rigid.config import SimConfig
    from rigid.errors import UserError

    with pytest.raises(UserError, match=r"^count = 100000: 100,000 copies 0.612 m apart make 11,112 layers "
                                        r"of 3 x 3, 6,800 m high.*\(at most 20 m: 297 copies of this size\)"):
        scene_bodies(SimConfig(count=100000).validate())
    bodies = scene_bodies(SimConfig(count=297).validate())
    top = max(b.position[1] for b in bodies) - min(b.position[1] for b in bodies)
    assert MAX_STACK_HEIGHT - 0.612 < top <= MAX_STACK_HEIGHT
    with pytest.raises(UserError, match=r"^count = 298: "):
        scene_bodies(SimConfig(count=298).validate())
    assert len(scene_bodies(SimConfig(count=200, walls=False).validate())) == 200  # no box: a cube of copies


def test_count_100000_exits_2_with_one_line():
    proc = run_cli("--headless", "--count", "100000")
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    assert proc.stderr.strip().splitlines()[-1].startswith("error: count = 100000: 100,000 copies"), proc.stderr


def test_the_parallel_builds_chunks_of_slots_are_exact_past_a_million_particles(ti_cpu):
    """The parallel build's active list cuts the N slots into chunks at n k // chunks; n k overflowed
    an i32 from 2^20 particles at 2,048 chunks, and the schedule crashed (SIGSEGV). Against Python's
    exact integers, for sizes around that and the grid's chunk counts."""
    import taichi as ti

    from rigid.engine.neighbours import chunk_start

    @ti.kernel
    def starts(n: ti.i32, chunks: ti.i32, out: ti.types.ndarray(dtype=ti.i32, ndim=1)):
        for k in range(chunks + 1):
            out[k] = chunk_start(n, chunks, k)

    for n, chunks in ((1_048_572, 2048), (1_048_614, 2048), (1_050_000, 16384), (4_200_000, 16384), (1000, 8)):
        out = np.zeros(chunks + 1, np.int32)
        starts(n, chunks, out)
        assert out.tolist() == [n * k // chunks for k in range(chunks + 1)], (n, chunks)
