"""Runs that would go wrong quietly or not fit (issue 21): a Δt too small for float32, more
particles than the memory holds, the time a long run has left, a body leaving the box.
The bad-input table of docs/bad-input.md holds the command-line rows (tests/test_bad_input.py)."""
import re

import numpy as np
import pytest

from conftest import ASSETS, ROOT


# --- Δt against float32's resolution (rigid.run.precision) ---------------------------------------

def test_float32_refuses_a_tiny_dt_and_names_fp64():
    from rigid.config import SimConfig
    from rigid.run.precision import float32_problem

    line = float32_problem(SimConfig(dt=1e-9).validate())
    assert line.startswith("dt = 1e-09 is too small for float32") and "--fp64" in line
    assert float32_problem(SimConfig(dt=1e-9, fp64=True).validate()) is None
    # The --dt it suggests passes, and a little less does not.
    suggested = float(line.rsplit("--dt ", 1)[1].split()[0])
    assert float32_problem(SimConfig(dt=suggested).validate()) is None
    assert float32_problem(SimConfig(dt=0.9 * suggested).validate()) is not None
    assert 1e-7 < suggested < 1e-6  # where float32's error reaches millimetres (precision.py)


def test_float32_spin_alone_counts():
    """Free flight without gravity: the quaternion's increment Δt·|ω|/2 against float32's spacing."""
    from rigid.config import SimConfig
    from rigid.run.precision import float32_problem

    cfg = SimConfig(dt=1e-8, gravity=(0, 0, 0), walls=False, initial_angular_velocity=(0, 8, 0)).validate()
    assert "quaternion" in float32_problem(cfg) or "moves the body" in float32_problem(cfg)
    assert float32_problem(cfg.replace(initial_angular_velocity=(0, 0, 0))) is None  # nothing moves


@pytest.mark.parametrize("scene", sorted((ASSETS / "scenes").glob("*.toml")), ids=lambda p: p.stem)
def test_float32_passes_every_shipped_scene(scene):
    from rigid.config import SimConfig, load_scene
    from rigid.run.precision import float32_problem

    assert float32_problem(SimConfig(**load_scene(scene)).validate()) is None
    assert float32_problem(SimConfig(**{**load_scene(scene), "dt": 1e-5}).validate()) is None  # convergence studies


# --- memory (rigid.bodies.budget) ------------------------------------------------------------------

def test_volume_estimate_matches_the_sampled_count():
    from rigid.bodies.mesh import read_mesh
    from rigid.bodies.sampling import expected_particles, sample_volume

    for name in ("sphere", "torus", "box"):
        mesh = read_mesh(ASSETS / f"{name}.obj")
        h = float(np.ptp(mesh.vertices, axis=0).max()) / 64
        count = len(sample_volume(mesh.vertices, mesh.faces, 64))
        assert abs(expected_particles(mesh.vertices, mesh.faces, h) / count - 1) < 0.03, name


def test_sampling_refuses_before_filling_what_the_memory_cannot_hold(monkeypatch):
    from rigid.bodies import budget
    from rigid.bodies.mesh import read_mesh
    from rigid.bodies.sampling import sample_volume
    from rigid.errors import UserError

    mesh = read_mesh(ASSETS / "sphere.obj")
    monkeypatch.setattr(budget, "available_bytes", lambda: 220e6)
    sample_volume(mesh.vertices, mesh.faces, 16)  # 1,880 particles fit
    with pytest.raises(UserError) as err:
        sample_volume(mesh.vertices, mesh.faces, 128)  # ~960,000 particles: ~200 MB + 0.3 GB do not
    assert str(err.value).startswith("grid = 128 fills the mesh with about 9")
    assert "of memory, more than the 220 MB free here; use a smaller --grid, e.g. 64" in str(err.value)


def test_copies_are_refused_before_they_are_made(monkeypatch):
    from rigid.bodies import budget
    from rigid.bodies.placement import scene_bodies
    from rigid.config import SimConfig
    from rigid.errors import UserError

    monkeypatch.setattr(budget, "available_bytes", lambda: 250e6)
    assert len(scene_bodies(SimConfig(count=8, scale=0.1).validate())) == 8
    with pytest.raises(UserError, match=r"^count = 5000: 5,000 copies of 42 particles make 210,000: about"):
        scene_bodies(SimConfig(count=5000, scale=0.03).validate())  # 200 MB + 210,000 x 320 B


def test_free_memory_is_read_on_this_machine():
    from rigid.bodies.budget import available_bytes

    free = available_bytes()
    assert free is None or free > 0


def test_grid_limit_agrees_with_the_sampler():
    """--grid's upper limit is the largest grid the sampler takes (a 1024 grid was accepted, then
    refused with another message)."""
    from rigid.bodies.sampling import MAX_CELLS
    from rigid.config import MAX_GRID, SimConfig

    assert MAX_GRID ** 3 <= MAX_CELLS < (MAX_GRID + 1) ** 3
    SimConfig(particles="volume", grid=MAX_GRID).validate()
    assert f"from 2 to {MAX_GRID}" in (ROOT / "docs" / "bad-input.md").read_text()


# --- the time a long headless run has left (rigid.run.progress) -----------------------------------

def test_time_left_says_nothing_for_a_short_run():
    from rigid.run.progress import TimeLeft

    eta = TimeLeft(300)
    assert eta.chunk_done(1, 1, 1.5) is None  # compiling
    assert all(eta.chunk_done(1 + k * 100, 100, 0.01) is None for k in range(1, 4))


def test_time_left_speaks_once_with_the_measured_rate():
    import io

    from rigid.run.progress import TimeLeft

    out = io.StringIO()
    eta = TimeLeft(300, out=out)
    assert eta.chunk_done(1, 1, 1.9) is None  # the first chunk compiles: under SAY_AFTER
    line = eta.chunk_done(2, 1, 0.5)  # 0.5 s a frame measured, 298 frames left
    assert line == "2 of 300 frames in 2.4 s: 0.5 s a frame, about 2 min to go (Ctrl-C stops and keeps what is done)"
    assert eta.chunk_done(3, 1, 0.5) is None and out.getvalue() == line + "\n"


def test_time_left_from_a_first_frame_alone_is_an_upper_bound():
    from rigid.run.progress import TimeLeft

    line = TimeLeft(10, out=open("/dev/null", "w")).chunk_done(1, 1, 120.0)
    assert line.startswith("1 of 10 frames in 120 s: 120 s a frame (compiling included), at most 18 min to go")


# --- a body leaving the box (rigid.run.escape) -----------------------------------------------------

def _block(x, v=None):
    x = np.asarray(x, float)
    return {"x": x, "v": np.ones_like(x) if v is None else np.asarray(v, float)}


def test_escape_finds_the_first_row_past_a_wall():
    from rigid.config import SimConfig
    from rigid.run.escape import first_escape

    cfg = SimConfig().validate()
    inside = [[0.0, -0.7, 0.0], [1.2, -0.7, 0.0]]  # 0.2 m past x = +1: a deep contact, not out
    assert first_escape(_block(inside), cfg) is None
    row, what, fix = first_escape(_block(inside + [[0.5, -0.9, -1.6], [0.0, 9.0, 0.0]]), cfg)
    assert row == 2 and what.startswith("the body left the box: its centre of mass is 0.6 m past the wall z = -1")
    assert "--no-walls" in fix
    assert first_escape(_block([[0.0, 50.0, 0.0]]), cfg) is None  # no ceiling: up is free
    assert first_escape(_block([[0.0, -1.5, 0.0]]), cfg)[1].startswith("the body left the box: its centre of "
                                                                       "mass is 0.5 m past the floor y = -1")
    assert first_escape(_block([[5.0, 0.0, 0.0]]), cfg.replace(walls=False)) is None


def test_escape_names_the_body_and_its_arrival_speed():
    from rigid.config import SimConfig
    from rigid.run.escape import first_escape

    x = np.zeros((2, 3, 3))
    x[1, 2] = [-2.0, 0.0, 0.0]
    v = np.zeros((2, 3, 3))
    v[0, 2] = [-400.0, 0.0, 0.0]  # the speed it came with, a frame before
    row, what, _fix = first_escape(_block(x, v), SimConfig(count=3, scale=0.1).validate())
    assert row == 1 and what.startswith("body 3 left the box: its centre of mass is 1 m past the wall x = -1, "
                                        "moving at 400 m/s (the walls' spring stops a particle within "
                                        "v·√(m/k) = 4 m)")


def test_a_body_thrown_through_the_wall_stops_the_run_and_keeps_the_good_frames(tmp_path, capsys, monkeypatch):
    from conftest import run_main

    out = tmp_path / "t.npz"
    code, _, stderr = run_main(capsys, monkeypatch, "--headless", "--frames", 30, "--v0", 1000, 0, 0, "--export", out)
    assert code == 3, stderr
    last = stderr.strip().splitlines()[-1]
    assert re.match(r"blow-up at t = 0\.016 s \(frame 1\): the body left the box: its centre of mass is "
                    r"1\.\d+ m past the wall x = \+1, moving at 1e\+03 m/s", last), last
    assert np.load(out)["x"].shape == (1, 3)  # frame 0, the last good one


# --- small ones: flags, --help, .gitignore -----------------------------------------------------------

def test_the_handouts_parameters_have_flags():
    from rigid.cli import build_parser, config_from_args

    args = build_parser().parse_args(["--particle-mass", "0.5", "--collision-stiffness", "2e4",
                                      "--velocity-damping-stiffness", "12", "--friction-stiffness", "0.3"])
    cfg = config_from_args(args)
    assert (cfg.particle_mass, cfg.collision_stiffness, cfg.velocity_damping_stiffness,
            cfg.friction_stiffness) == (0.5, 2e4, 12.0, 0.3)


def test_help_mentions_check_and_the_new_flags():
    from rigid.cli import build_parser

    text = build_parser().format_help()
    for flag in ("--check", "--particle-mass", "--collision-stiffness", "--velocity-damping-stiffness",
                 "--friction-stiffness"):
        assert flag in text, flag


def test_the_readme_commands_outputs_are_ignored_by_git():
    import shutil
    import subprocess

    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    proc = subprocess.run(["git", "check-ignore", "out.mp4", "t.npz"], cwd=ROOT, capture_output=True, text=True)
    assert proc.stdout.split() == ["out.mp4", "t.npz"], proc.stdout + proc.stderr
