"""Many bodies colliding: conservation, restitution, piles, stacks, dominoes, non-convex contact.

Float64 numbers come from tests/many_body_fp64_worker.py, started in the background when this
module is imported (one ti.init per process; under xdist by the first test that needs it, see
background.py); the scenes run here in float32.
"""
import os
from pathlib import Path

import numpy as np
import pytest

from background import Worker
from conftest import ROOT, run_cli, run_main

_worker = Worker(Path(__file__).resolve().parent / "many_body_fp64_worker.py", timeout_s=300).start_early()


@pytest.fixture(scope="module")
def fp64():
    return _worker.result()


def test_head_on_conserves_total_momentum(fp64):
    r = fp64["momentum"]
    assert r["touched"], "the bodies never met: the test would prove nothing"
    assert r["P_drift"] < 1e-12 * r["P_scale"]


def test_symplectic_conserves_total_angular_momentum_with_friction(fp64):
    r = fp64["angular"]
    assert r["touched"]
    assert r["J_drift"] < 1e-12 * max(r["J_scale"], 1.0)


def test_a_spring_between_two_bodies_keeps_total_momentum_and_angular_momentum(fp64):
    # Equal and opposite forces along the line of the two points: Σ P and Σ (L + x × P) stay
    # what they were under symplectic Euler (the spring's torques do turn each body).
    r = fp64["springs"]
    assert r["turned"] > 0.05, "the spring never turned the bodies: the test would prove little"
    assert r["P_drift"] < 1e-12 * max(r["P_scale"], 1.0)
    assert r["J_drift"] < 1e-12 * max(r["J_scale"], 1.0)


def test_explicit_euler_angular_momentum_error_is_first_order(fp64):
    coarse, fine = fp64["euler_coarse"]["J_drift"], fp64["euler_fine"]["J_drift"]
    assert coarse > 1e-6, "explicit Euler should drift: otherwise the order is not measurable"
    assert 1.6 < coarse / fine < 2.6, (coarse, fine)


def test_restitution_matches_the_damped_spring(fp64):
    """e = exp(-pi zeta / sqrt(1 - zeta^2)) of one linear damped contact. The damper never pulls,
    which ends the contact a little early and raises e above the formula as zeta grows (0.7 % at
    zeta = 0.058, 6 % at 0.17): hence light damping here."""
    for r in fp64["restitution"]:
        assert r["spin"] == 0.0, "tip to tip along the line of centres: no torque"
        assert abs(r["measured"] - r["expected"]) < 0.03 * r["expected"], r


@pytest.fixture
def scene_sim(units):
    """scene_sim(name, **changes) -> a Simulator of the scene, at its initial state."""
    from rigid.config import SimConfig, load_scene
    from rigid.engine.simulator import Simulator

    def get(name, **changes):
        values = load_scene(ROOT / "assets" / "scenes" / f"{name}.toml")
        values.update(changes)
        config = SimConfig(**values).validate()
        return Simulator(config, units)

    return get


def test_damped_pile_loses_energy_and_stays_in_the_box(scene_sim):
    # 27 spheres in a narrow box (walls at ±0.4 m: 3 x 3 x 3), so that they pile up.
    sim = scene_sim("pile", wall=0.4, bodies=(dict(mesh=str(ROOT / "assets" / "sphere.obj"), scale=0.1,
                                                   grid=5, count=27, position=(0.0, -0.85, 0.0)),))
    energies, overlaps = [], []
    for frame in range(150):
        row = sim.snapshot()
        energies.append(row["kinetic_energy"] + row["potential_energy"])
        sim.step_frame()
    x = sim.snapshot()["x"]
    rise = np.max(np.diff(energies))
    assert rise < 1e-3 * abs(energies[0] - energies[-1]), f"energy rose by {rise} J in a frame"
    assert energies[-1] < energies[0]
    assert np.all(np.abs(x[:, [0, 2]]) < 0.4) and np.all(x[:, 1] > -1.0)
    assert x[:, 1].max() > -0.6, "three layers: some spheres rest on others"
    # No body passes through another: particle spheres of different bodies overlap by < 40 % of a radius.
    from scipy.spatial import cKDTree

    p, body = sim.state.particle_x.to_numpy(), sim.model.particle_body.to_numpy()
    r = float(sim.model.radius_np.max())
    pairs = cKDTree(p).query_pairs(2 * r, output_type="ndarray")
    pairs = pairs[body[pairs[:, 0]] != body[pairs[:, 1]]]
    assert len(pairs) > 27, f"a settled pile has contacts ({len(pairs)})"
    depth = 2 * r - np.linalg.norm(p[pairs[:, 0]] - p[pairs[:, 1]], axis=1)
    assert depth.max() < 0.4 * r, depth.max() / r


def test_stack_stands(scene_sim):
    sim = scene_sim("stack")
    for _ in range(60):  # 1 s to settle from the 2 mm gaps
        sim.step_frame()
    start = sim.snapshot()["x"][-1]
    for _ in range(300):  # 5 s
        sim.step_frame()
    moved = np.linalg.norm(sim.snapshot()["x"][-1] - start)
    assert moved < 0.01, f"the top box moved {moved:.4f} m"


def test_dominoes_all_fall_in_turn(scene_sim):
    sim = scene_sim("dominoes")
    tipped = np.full(24, -1)  # frame at which each domino first leans past 15 degrees
    for frame in range(150):
        sim.step_frame()
        q = sim.snapshot()["q"]
        up = 1 - 2 * (q[:, 1] ** 2 + q[:, 3] ** 2)  # R[1, 1]: the domino's long axis against world y
        tipped[(tipped < 0) & (up < np.cos(np.radians(15)))] = frame
    tilt = np.degrees(np.arccos(np.clip(up, -1, 1)))
    assert np.all(tipped >= 0), f"standing: {np.flatnonzero(tipped < 0)}"
    assert np.all(np.diff(tipped) > 0), f"not in turn: {tipped}"
    assert np.all(tilt > 30), tilt.round(0)


def test_ball_passes_through_the_torus_hole_untouched(scene_sim):
    from scipy.spatial import cKDTree

    sim = scene_sim("ball_through_torus")
    body = sim.model.particle_body.to_numpy()
    r = sim.model.radius_np
    closest, lowest = np.inf, np.inf
    for _ in range(45):  # the ball reaches the floor inside the ring after ~0.55 s, then bounces
        sim.step_frame()
        p = sim.state.particle_x.to_numpy()
        d, _i = cKDTree(p[body == 0]).query(p[body == 1])
        closest = min(closest, d.min())
        lowest = min(lowest, sim.snapshot()["x"][1][1])
    torus_y = sim.snapshot()["x"][0][1]
    assert lowest < torus_y - 0.03, f"the ball stopped at y = {lowest:.3f}, above the ring at {torus_y:.3f}"
    assert closest > r[0] + r[1], f"closest particles {closest:.3f} m apart: they touched"


# The pinned run (tests/data/assignment_120_frames.npz, written by the command line below) and how
# far a run may stray from it: a few float32 round-offs grown over 120 frames and 8 bounces. The
# kernels' bits depend on the CPU they were compiled for (fast math lets LLVM vectorise sums to the
# machine's width: AVX2 and AVX-512 round differently), so the pin is the values, not the bytes;
# a run against Taichi's exact maths (fast_math=False) differs from the fast one by at most
# 4e-6 m in x, 2e-5 m/s in v, 8e-4 in P and 1e-4 rad/s in the (round-off) spin. A change of the
# physics moves the bounces by millimetres and their speeds by cm/s.
PIN = ROOT / "tests" / "data" / "assignment_120_frames.npz"
PIN_TOLERANCE = dict(t=0.0, x=1e-4, q=1e-4, v=1e-3, omega=1e-3, P=4e-2, L=1e-3, kinetic_energy=1e-3,
                     potential_energy=1e-3, mass=0.0, inertia_body=1e-6, dt=0.0, substeps=0)


def test_single_body_export_unchanged():
    """Regression pin: the assignment scene's NPZ, 120 frames: its keys, shapes and dtypes exactly,
    its values within round-off (PIN_TOLERANCE). Re-pinned once for the one engine (#19: the one
    contact law, sums by blocks); any change beyond round-off is a change of the physics and must
    be explained. (That a run repeats bit for bit on one machine: test_export.py.)"""
    out = ROOT / "out" / "pin_assignment.npz"
    out.parent.mkdir(exist_ok=True)
    users = {**os.environ, "RIGID_QUICK_COMPILE": "0"}  # compiled as for users (conftest.py)
    proc = run_cli("--scene", "assets/scenes/assignment.toml", "--headless", "--frames", "120", "--export", out,
                   env=users)
    assert proc.returncode == 0, proc.stderr
    run, pin = np.load(out), np.load(PIN)
    assert run.files == pin.files == list(PIN_TOLERANCE)
    for key in pin.files:
        assert run[key].dtype == pin[key].dtype and run[key].shape == pin[key].shape, key
        worst = float(np.max(np.abs(run[key].astype(np.float64) - pin[key])))
        assert worst <= PIN_TOLERANCE[key], f"{key} strays {worst:.2e} from the pinned run"


def test_count_flag_and_refusals(tmp_path, monkeypatch, capsys):
    out = tmp_path / "m.npz"
    code, _, stderr = run_main(capsys, monkeypatch, "--count", "4", "--scale", "0.2", "--headless", "--frames", "3",
                               "--export", out)
    assert code == 0, stderr
    d = np.load(out)
    assert d["x"].shape == (4, 4, 3) and d["q"].shape == (4, 4, 4) and d["mass"].shape == (4,)
    assert d["inertia_body"].shape == (4, 3, 3) and d["kinetic_energy"].shape == (4,)
    # The refusals come before Taichi starts: run in this process (test_bad_input.py runs a real
    # process for a refusal's exit code and stderr).
    from rigid.cli import main

    monkeypatch.chdir(ROOT)
    code = main(["--scene", "assets/scenes/stack.toml", "--mesh", "assets/box.obj", "--headless"])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: --mesh sets one body"), err



def test_rk4_runs_colliding_bodies_and_conserves_their_momentum(scene_sim):
    """RK4 evaluates the whole pipeline (pairs included) at each of its four stages: the head-on
    scene's bodies meet, push apart, and their total momentum stays at its start to round-off
    (every pair force is equal and opposite at every stage)."""
    sim = scene_sim("head_on", integrator="rk4")
    rows = sim.advance(60)
    P = rows["P"].sum(axis=1)
    scale = np.abs(rows["P"]).max()
    assert np.abs(P - P[0]).max() < 1e-5 * scale
    v = rows["v"][:, :, 0]
    assert v[0, 0] > 1.0 and v[0, 1] < -1.0  # approaching ...
    assert v[-1, 0] < v[0, 0] - 0.5 and v[-1, 1] > v[0, 1] + 0.5  # ... and pushed back by the contact
