"""The NPZ export: contract keys and shapes, row 0 the initial state, reproducible,
never half-written, kept up to the last good frame on a blow-up or Ctrl-C."""
import sys

import numpy as np
import pytest

from conftest import ROOT, SOLUTION, run_cli, run_main
from terminal import Terminal

ROW_SHAPES = {"t": (), "x": (3,), "q": (4,), "v": (3,), "omega": (3,), "P": (3,), "L": (3,),
              "kinetic_energy": (), "potential_energy": ()}


def test_export_keys_shapes_and_initial_row(tmp_path, capsys, monkeypatch):
    out = tmp_path / "t.npz"
    code, _, stderr = run_main(capsys, monkeypatch, "--headless", "--frames", 12, "--export", out, "--scene",
                               "assets/scenes/thrown_sphere.toml")
    assert code == 0, stderr
    d = np.load(out)
    assert set(d.files) == set(ROW_SHAPES) | {"mass", "inertia_body", "dt", "substeps"}
    for key, shape in ROW_SHAPES.items():
        assert d[key].shape == (13, *shape), key
    assert d["inertia_body"].shape == (3, 3) and d["substeps"] == 16 and np.isclose(d["dt"], 1e-3)
    assert d["mass"] == 42.0
    # Row 0 is the scene's initial state, before any step.
    v0, w0 = np.array([4.0, 2.0, 3.0]), np.array([0.0, 10.0, 0.0])
    np.testing.assert_allclose(d["x"][0], [-0.5, 0.2, -0.3], atol=1e-6)
    np.testing.assert_allclose(d["P"][0], 42 * v0, rtol=1e-6)
    np.testing.assert_allclose(d["L"][0], d["inertia_body"] @ w0, rtol=1e-5)
    np.testing.assert_allclose(d["q"][0], [1, 0, 0, 0])
    np.testing.assert_allclose(np.diff(d["t"]), 16e-3, rtol=1e-5)
    assert np.isclose(d["kinetic_energy"][0], 0.5 * 42 * v0 @ v0 + 0.5 * w0 @ d["inertia_body"] @ w0, rtol=1e-5)


def test_fp64_export_is_float64_and_runs_are_byte_identical(tmp_path):
    outs = [tmp_path / "a.npz", tmp_path / "b.npz"]
    for out in outs:
        proc = run_cli("--headless", "--fp64", "--frames", 20, "--export", out)
        assert proc.returncode == 0, proc.stderr
    assert np.load(outs[0])["x"].dtype == np.float64
    assert outs[0].read_bytes() == outs[1].read_bytes()


def test_blow_up_stops_with_one_line_and_keeps_good_frames(tmp_path, capsys, monkeypatch):
    scene = tmp_path / "stiff.toml"
    scene.write_text("collision_stiffness = 1e7\n")
    out = tmp_path / "t.npz"
    code, _, stderr = run_main(capsys, monkeypatch, "--headless", "--frames", 300, "--scene", scene, "--export", out)
    assert code == 3
    line = [ln for ln in stderr.splitlines() if "blow-up" in ln]
    assert len(line) == 1 and "for dt < 0.0001 s, and the contact spring limits it: dt < c/k" in line[0]
    d = np.load(out)
    assert 2 < len(d["t"]) < 300
    energy = d["kinetic_energy"] + d["potential_energy"]
    assert np.all(np.isfinite(energy)) and energy.max() < 42 * 9.8  # only the good frames


def test_interrupted_export_is_complete_and_readable(tmp_path):
    out = tmp_path / "t.npz"
    with Terminal([sys.executable, str(SOLUTION), "--headless", "--frames", "10000000", "--export", str(out)],
                  cwd=ROOT) as run:
        done = run.count(10000000)  # frames simulated, as the terminal's progress bar counts them
        code = run.ctrl_c()
    assert code == 130, run.text
    assert f"wrote {out}" in run.text and "Traceback" not in run.text
    d = np.load(out)
    assert done >= 1 and len(d["t"]) >= done + 1  # row 0 and at least every frame it said were done
    assert np.all(np.isfinite(d["x"])) and np.all(np.diff(d["t"]) > 0)


def test_failed_write_keeps_the_previous_file(tmp_path):
    from rigid.run.atomic import atomic_output

    target = tmp_path / "t.npz"
    target.write_bytes(b"previous")
    with pytest.raises(RuntimeError):
        with atomic_output(target) as tmp:
            tmp.write_bytes(b"half")
            raise RuntimeError("crash mid-write")
    assert target.read_bytes() == b"previous"
    assert list(tmp_path.iterdir()) == [target]
