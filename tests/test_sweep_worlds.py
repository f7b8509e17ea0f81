"""A sweep whose runs differ only in their bodies' starts runs them as worlds of one Simulator
(rigid.sweeps.batch), and says so; each run's NPZ is still, byte for byte, the file the single
run's frame loop writes (rigid.run.runner.run_frames, as ``--headless --export`` does)."""
import subprocess
import sys

from conftest import ROOT
from test_sweep import SCENE, index

FRAMES = 12


def test_a_sweep_of_throws_runs_as_worlds_and_writes_each_runs_own_bytes(tmp_path, units):
    from rigid.config import SimConfig, load_scene
    from rigid.engine.simulator import Simulator
    from rigid.run.runner import run_frames

    out = tmp_path / "sweep"  # two workers side by side, a batch each
    proc = subprocess.run([sys.executable, "-m", "rigid", "sweep", str(SCENE), "--vary", "initial_velocity.x=1:3:3",
                           "--vary", "initial_angular_velocity.y=0,4", "--frames", str(FRAMES), "--out", str(out),
                           "--workers", "2"], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "as 2 batches of worlds of one simulator each" in proc.stderr, proc.stderr
    rows = index(out)
    assert len(rows) == 6 and all(r["status"] == "ok" for r in rows)
    base = load_scene(SCENE)
    for row in rows:
        v0 = list(base["initial_velocity"])
        v0[0] = float(row["initial_velocity.x"])
        w0 = list(base.get("initial_angular_velocity", (0.0, 0.0, 0.0)))
        w0[1] = float(row["initial_angular_velocity.y"])
        config = SimConfig(**{**base, "initial_velocity": tuple(v0), "initial_angular_velocity": tuple(w0)}).validate()
        alone = tmp_path / f"{row['run']}.npz"
        result = run_frames(Simulator(config, units), FRAMES, export_path=alone)
        assert result.status == "done"
        assert (out / "runs" / f"{row['run']}.npz").read_bytes() == alone.read_bytes(), row
        last = result.last_row  # index.csv's energy: the last row's, as the single run gives it
        assert float(row["final_energy"]) == float(last["kinetic_energy"] + last["potential_energy"])
