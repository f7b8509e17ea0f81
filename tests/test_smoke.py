"""The assignment scene runs headless and writes the export with every contract key."""
import numpy as np

from conftest import run_cli


def test_headless_export(tmp_path):
    out = tmp_path / "t.npz"
    proc = run_cli("--headless", "--frames", 30, "--export", out)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines()[-2] == "42 particles at the vertices of sphere.obj"  # before the summary
    data = np.load(out)
    assert data["x"].shape == (31, 3) and data["q"].shape == (31, 4)
    assert data["t"][0] == 0.0
