"""``python -m rigid sweep``: each run equals the scene run alone, bit for bit; re-running resumes
(after a worker killed mid-sweep, and past a half-written file); a bad --vary is one line before
anything runs; Ray's local cluster writes the local pool's bytes (skipped without ray).

The references are the same scenes run in this process through ``rigid.Simulator`` directly, with
the values each row of index.csv names."""
import csv
import importlib.util
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, default_sigint, killed_at_exit, run_main

SCENE = ROOT / "assets" / "scenes" / "thrown_sphere.toml"
FRAMES = 10
VARY = ["--vary", "friction_stiffness=0.1,0.5", "--vary", "initial_velocity.x=2:4:2"]  # 4 runs
ROW_KEYS = ("t", "x", "q", "v", "omega", "P", "L", "kinetic_energy", "potential_energy")


def sweep_command(out, *extra, vary=VARY, workers=1):
    """One worker unless the test is about several: each starts Taichi (~1.4 CPU-s). Two run side
    by side in test_sweep_worlds (a batch each) and in the killed-worker test (its resume)."""
    return [sys.executable, "-m", "rigid", "sweep", str(SCENE), *vary, "--frames", str(FRAMES), "--out", str(out),
            "--workers", str(workers), *extra]


def run_sweep(out, *extra, vary=VARY, workers=1, timeout=300):
    return subprocess.run(sweep_command(out, *extra, vary=vary, workers=workers), cwd=ROOT, capture_output=True,
                          text=True, timeout=timeout)


def index(out):
    with open(Path(out) / "index.csv", newline="") as f:
        return list(csv.DictReader(f))


def stamps(out):
    """Every file under the sweep's folder with its modification time (hidden ones included)."""
    return {str(p.relative_to(out)): p.stat().st_mtime_ns for p in Path(out).rglob("*") if p.is_file()}


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep") / "thrown"
    proc = run_sweep(out)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return out


def test_each_run_of_a_sweep_equals_the_scene_run_alone(swept, units):
    from rigid.config import SimConfig, load_scene
    from rigid.engine.simulator import Simulator

    rows = index(swept)
    assert [r["run"] for r in rows] == ["run-0000", "run-0001", "run-0002", "run-0003"]
    assert list(rows[0]) == ["run", "friction_stiffness", "initial_velocity.x", "seed", "status", "final_energy",
                             "wall_seconds"]
    assert {(float(r["friction_stiffness"]), float(r["initial_velocity.x"])) for r in rows} == \
        {(0.1, 2.0), (0.1, 4.0), (0.5, 2.0), (0.5, 4.0)}  # the product
    scene = SimConfig(**load_scene(SCENE)).validate()
    assert scene.initial_velocity == (4.0, 2.0, 3.0) and scene.friction_stiffness == 0.1
    for row in rows:
        assert row["status"] == "ok" and row["seed"] == "0" and float(row["wall_seconds"]) > 0
        config = scene.replace(friction_stiffness=float(row["friction_stiffness"]),
                               initial_velocity=(float(row["initial_velocity.x"]), 2.0, 3.0)).validate()
        alone = Simulator(config, units).advance(FRAMES)
        got = np.load(swept / "runs" / f"{row['run']}.npz")
        assert got["x"].shape == (FRAMES + 1, 3)  # the NPZ contract's one body
        for key in ROW_KEYS:
            want = np.asarray(alone[key])
            want = want[:, 0] if want.ndim == 3 else want
            assert np.array_equal(got[key], want.astype(got[key].dtype)), (row["run"], key)
        energy = alone["kinetic_energy"][-1] + alone["potential_energy"][-1]
        assert float(row["final_energy"]) == pytest.approx(float(energy), rel=1e-12)
    assert not list(swept.rglob(".*")), "no hidden partial file is left"


def test_a_runs_npz_is_the_command_lines_export_byte_for_byte(swept, tmp_path, capsys, monkeypatch):
    (row,) = [r for r in index(swept) if (r["friction_stiffness"], r["initial_velocity.x"]) == ("0.5", "2.0")]
    alone = tmp_path / "alone.npz"
    code, _, err = run_main(capsys, monkeypatch, "--scene", SCENE, "--headless", "--frames", FRAMES,
                            "--friction-stiffness", 0.5, "--v0", 2, 2, 3, "--export", alone)
    assert code == 0, err
    assert alone.read_bytes() == (swept / "runs" / f"{row['run']}.npz").read_bytes()


def test_the_runs_are_the_product_of_the_values_then_the_seeds():
    from rigid.config import SimConfig, load_scene
    from rigid.sweeps.vary import as_varies, plan_runs

    base = SimConfig(**load_scene(SCENE)).validate()
    runs = plan_runs(base, as_varies({"friction_stiffness": "0.1:0.5:5", "integrator": ["euler", "rk4"]}), seeds=2)
    assert [r.name for r in runs[:2]] == ["run-0000", "run-0001"] and len(runs) == 20
    assert [r.values["friction_stiffness"] for r in runs[::4]] == [0.1, 0.2, 0.3, 0.4, 0.5]  # rounded, as written
    assert [(r.values["integrator"], r.seed) for r in runs[:4]] == [("euler", 0), ("euler", 1), ("rk4", 0), ("rk4", 1)]
    assert runs[7].config.friction_stiffness == 0.2 and runs[7].config.integrator == "rk4" and runs[7].config.seed == 1
    assert runs[7].config.initial_velocity == base.initial_velocity  # the scene's other keys as they were


def test_running_the_finished_sweep_again_keeps_every_file(swept):
    before, rows = stamps(swept), index(swept)
    proc = run_sweep(swept)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "4 kept from before, 0 to run" in proc.stderr
    assert stamps(swept) == {**before, "index.csv": stamps(swept)["index.csv"]} and index(swept) == rows


def test_the_python_api_names_the_same_runs_and_returns_the_index(swept):
    import rigid

    before = stamps(swept)
    rows = rigid.sweep(SCENE, {"friction_stiffness": [0.1, 0.5], "initial_velocity.x": "2:4:2"}, frames=FRAMES,
                       out=swept, workers=2)
    assert [r["status"] for r in rows] == ["ok"] * 4  # all kept: nothing ran
    for got, row in zip(rows, index(swept), strict=True):
        assert got == {"run": row["run"], "friction_stiffness": float(row["friction_stiffness"]),
                       "initial_velocity.x": float(row["initial_velocity.x"]), "seed": 0, "status": "ok",
                       "final_energy": float(row["final_energy"]), "wall_seconds": float(row["wall_seconds"])}
    assert {k: t for k, t in stamps(swept).items() if k.startswith("runs/")} == \
        {k: t for k, t in before.items() if k.startswith("runs/")}


def test_a_folder_of_another_sweep_is_refused_in_one_line(swept):
    before = stamps(swept)
    proc = run_sweep(swept, vary=["--vary", "friction_stiffness=0.1,0.9"])
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "holds another sweep" in proc.stderr, proc.stderr
    assert stamps(swept) == before


@pytest.mark.parametrize("spec, words", [
    ("restitutoin=0:1:3", "did you mean 'restitution'"),   # unknown key
    ("restitution=0.8:0.2", "START:STOP:N"),               # bad range
    ("restitution=0.2:x:3", "must be numbers"),
    ("count=1:4:3", "whole numbers"),
    ("restitution=0.5,1.5", "from 0 (no bounce) to 1"),    # a value the scene refuses
    ("frames=10,20", "frames cannot vary"),                # keys that cannot vary
    ("fp64=true,false", "fp64 cannot vary"),
    ("gravity=0,-9.8", "gravity.x, gravity.y or gravity.z"),
])
def test_a_bad_vary_is_one_line_before_anything_runs(tmp_path, capsys, spec, words):
    from rigid.sweeps.command import main

    out = tmp_path / "never"
    code = main([str(SCENE), "--vary", spec, "--frames", "10", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: --vary") and err.count("\n") == 1 and words in err, err
    assert not out.exists()


def test_a_bad_vary_from_the_command_line_exits_2_without_a_traceback(tmp_path):
    proc = run_sweep(tmp_path / "never", vary=["--vary", "drag=-1,1"], timeout=60)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and "drag = -1.0" in proc.stderr, proc.stderr
    assert "Traceback" not in proc.stderr and not (tmp_path / "never").exists()


def test_a_ray_address_where_nothing_answers_is_one_line_before_anything_runs(tmp_path, capsys):
    from rigid.sweeps.command import main

    out = tmp_path / "never"
    code = main([str(SCENE), "--frames", "10", "--out", str(out), "--ray", "127.0.0.1:1"])  # a closed loopback port
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: --ray") and err.count("\n") == 1, err
    has_ray = importlib.util.find_spec("ray") is not None
    assert ("nothing answers there" if has_ray else "needs Ray, which is not installed") in err, err
    assert not out.exists()


def _workers_of(pid: int) -> list[int]:
    """The pool's worker processes: children of ``pid`` started by multiprocessing's spawn."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            parent = int(stat.read_text().rsplit(")", 1)[1].split()[1])
            cmdline = (stat.parent / "cmdline").read_bytes()
        except (OSError, ValueError, IndexError):
            continue
        if parent == pid and b"spawn_main" in cmdline:
            found.append(int(stat.parent.name))
    return found


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="finds the pool's workers through /proc")
def test_a_killed_worker_fails_its_runs_and_the_same_command_resumes(tmp_path):
    out = tmp_path / "sweep"
    vary = ["--vary", "friction_stiffness=0.1,0.2,0.3"]
    proc = subprocess.Popen(sweep_command(out, vary=vary, workers=2), cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    with killed_at_exit(proc):
        deadline = time.monotonic() + 60
        while not (workers := _workers_of(proc.pid)) and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.02)
        assert workers, "the sweep started no worker"
        os.kill(workers[0], signal.SIGKILL)  # while it starts Taichi: before any run is done
        _, err = proc.communicate(timeout=300)
    assert proc.returncode == 1, err[-3000:]
    rows = index(out)  # the killed worker's run failed; the other worker and a fresh one ran the rest
    died = {r["run"] for r in rows if "worker process died" in r["status"]}
    ok = {r["run"] for r in rows if r["status"] == "ok"}
    assert len(died) == 1 and len(ok) == 2 and died | ok == {"run-0000", "run-0001", "run-0002"}, rows
    assert {p.stem for p in (out / "runs").glob("*.npz")} == ok and not list(out.rglob(".*"))
    kept = {name: t for name, t in stamps(out).items() if name.startswith("runs/")}
    (out / "runs" / ".run-0000.partial.npz").write_bytes(b"half a file, as a killed driver leaves")

    again = run_sweep(out, vary=vary, workers=2)
    assert again.returncode == 0, again.stderr[-3000:]
    assert "2 kept from before, 1 to run" in again.stderr
    after = index(out)
    assert all(r["status"] == "ok" for r in after)
    assert [r for r in after if r["run"] in ok] == [r for r in rows if r["run"] in ok]  # its row as it was
    assert {name: t for name, t in stamps(out).items() if name in kept} == kept  # its file untouched
    assert sorted(p.name for p in (out / "runs").iterdir()) == ["run-0000.npz", "run-0001.npz", "run-0002.npz"]


@pytest.fixture(scope="module")
def student_recorded(tmp_path_factory):
    """``python rigid_body_dynamic.py sweep ... --record`` of a student's file whose TODO 2 has twice
    the gravity, over the thrown sphere drawn small (resolution cannot vary): one sweep, one worker
    starting Taichi, for the two tests below."""
    folder = tmp_path_factory.mktemp("student")
    student = folder / "rigid_body_dynamic.py"
    solved = (ROOT / "rigid_body_dynamic.py").read_text()
    assert solved.count("force = particle_mass * gravity") == 1
    student.write_text(solved.replace("force = particle_mass * gravity", "force = 2.0 * particle_mass * gravity"))
    scene = folder / "small.toml"
    scene.write_text(SCENE.read_text().replace('"../sphere.obj"', repr(str(ROOT / "assets" / "sphere.obj")))
                     + "resolution = [96, 64]\n")
    out = folder / "sweep"
    proc = subprocess.run([sys.executable, str(student), "sweep", str(scene), "--vary", "drag=0,0.5", "--frames", "5",
                           "--out", str(out), "--workers", "1", "--record"], cwd=folder, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return out


def test_a_students_file_sweeps_with_its_own_units(student_recorded):
    """The sweep runs that file's TODOs, not the solution's: checked against explicit Euler's free
    fall with twice the gravity before any contact (run-0000: no drag)."""
    assert index(student_recorded)[0]["drag"] == "0.0"
    d = np.load(student_recorded / "runs" / "run-0000.npz")
    k, dt = 5 * int(d["substeps"]), float(d["dt"])  # x_k = x0 + v0 k dt + g dt² k(k-1)/2
    assert d["x"][5, 1] == pytest.approx(0.2 + 2.0 * k * dt - 2 * 9.8 * dt * dt * k * (k - 1) / 2, abs=1e-4)


def test_record_writes_each_runs_video_beside_its_npz(student_recorded):
    import av

    for run in ("run-0000", "run-0001"):
        with av.open(str(student_recorded / "runs" / f"{run}.mp4")) as video:
            stream = video.streams.video[0]
            assert (stream.width, stream.height) == (96, 64)
            assert sum(1 for _ in video.decode(stream)) == 6  # frame 0, then one per simulated frame
        assert np.load(student_recorded / "runs" / f"{run}.npz")["x"].shape == (6, 3)


def test_ctrl_c_keeps_the_finished_runs_and_leaves_only_complete_files(tmp_path):
    """Ctrl-C in a terminal reaches the driver and its workers (one process group) mid-sweep."""
    out = tmp_path / "sweep"
    # Volume particles (~0.2 s a run of 500 frames once the worker is warm, a lone vertex sphere ~20 ms):
    # when the first run's file appears, the worker is mid-way through the second run and two runs
    # wait, so the Ctrl-C lands ~0.6 s before the sweep would end.
    command = sweep_command(out, vary=["--vary", "particles=volume", "--vary", "friction_stiffness=0.1,0.2,0.3,0.4"])
    command[command.index("--frames") + 1] = "500"
    proc = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, preexec_fn=default_sigint)
    with killed_at_exit(proc):
        deadline = time.monotonic() + 120
        while not list((out / "runs").glob("run-*.npz")) and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.02)
        os.killpg(proc.pid, signal.SIGINT)
        _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130 and "interrupted" in err, err[-3000:]
    rows = index(out)
    ok = {r["run"] for r in rows if r["status"] == "ok"}
    assert 1 <= len(ok) < 4, rows
    assert {p.stem for p in (out / "runs").iterdir()} == ok and not list(out.rglob(".*"))
    for run in ok:
        assert np.load(out / "runs" / f"{run}.npz")["x"].shape == (501, 3)  # whole trajectories


def test_ray_local_writes_the_local_pools_bytes(swept, tmp_path):
    pytest.importorskip("ray", reason="the cluster extra is not installed: pip install -e '.[cluster]'")
    out = tmp_path / "ray"
    proc = run_sweep(out, "--ray", "local")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert [r["status"] for r in index(out)] == ["ok"] * 4
    for run in ("run-0000", "run-0001", "run-0002", "run-0003"):
        assert (out / "runs" / f"{run}.npz").read_bytes() == (swept / "runs" / f"{run}.npz").read_bytes(), run
