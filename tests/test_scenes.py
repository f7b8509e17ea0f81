"""Every scene in assets/scenes runs headless through the CLI and exports finite frames.

The command line runs in this process (its kernels are compiled once per process)."""
import numpy as np
import pytest

from conftest import ASSETS, ROOT

SCENES = sorted((ASSETS / "scenes").glob("*.toml"))


def test_there_are_the_four_promised_scenes():
    names = {s.stem for s in SCENES}
    assert {"assignment", "thrown_sphere", "tumbling_t_handle", "bouncing_torus"} <= names


@pytest.mark.parametrize("scene", SCENES, ids=[s.stem for s in SCENES])
def test_scene_runs_headless(scene, tmp_path, monkeypatch, ti_cpu, capsys):
    from rigid.cli import main

    monkeypatch.chdir(ROOT)
    out = tmp_path / "t.npz"
    assert main(["--headless", "--scene", str(scene), "--frames", "20", "--export", str(out)]) == 0
    d = np.load(out)
    assert len(d["t"]) == 21 and np.all(np.isfinite(d["x"])) and np.all(np.isfinite(d["L"]))
    assert "20 frames" in capsys.readouterr().out
