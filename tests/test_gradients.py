"""rigid.gradient and rigid.fit (rigid/diff): gradients through contact and fitting to a recording.

The float64 numbers come from tests/gradients_fp64_worker.py (one process: Taichi takes one
precision per process); every reference there is from outside rigid.diff: a closed form, or
central differences of the forward engine (rigid.Simulator). Bad inputs are refused here, in the
suite's own process, before anything compiles.
"""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT

WORKER = ROOT / "tests" / "gradients_fp64_worker.py"


@pytest.fixture(scope="module")
def results():
    env = dict(os.environ, TI_SKIP_VERSION_CHECK="ON")
    run = subprocess.run([sys.executable, str(WORKER)], capture_output=True, text=True, timeout=600, env=env, cwd=ROOT)
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


def rel(a, b):
    return np.abs(np.asarray(a) - np.asarray(b)) / np.abs(np.asarray(b))


def test_the_pass_runs_the_engines_physics_rows_match_the_simulator_to_round_off(results):
    # Explicit Euler with the materials' law and with the plain law; two bodies (a ball and a box)
    # under symplectic Euler with the materials' law (gradients_fp64_worker.TWO_BODIES).
    for name in ("materials", "plain", "two_bodies_symplectic"):
        diffs = results[f"match_{name}"]
        assert set(diffs) == {"x", "q", "v", "omega", "P", "L"}
        assert max(diffs.values()) < 1e-10, (name, diffs)  # 40 frames through a bounce, float64


def test_free_flight_gradient_is_the_sum_of_weights_times_times(results):
    r = results["free_flight"]
    assert r["grad"][0] == pytest.approx(r["expected"], rel=1e-8)
    assert r["grad"][1:] == [0.0, 0.0]  # x's x-row does not depend on v0's other components


def test_bounce_gradients_match_central_differences_of_the_engine(results):
    r = results["bounce"]
    assert max(rel(r["v0"], r["fd_v0"])) < 0.01
    assert rel(r["e"], r["fd_e"]) < 0.02


def test_sliding_box_friction_and_resting_box_stiffness_match_central_differences(results):
    assert rel(results["sliding"]["mu"], results["sliding"]["fd_mu"]) < 0.02
    assert results["sliding"]["mu"] < 0  # more friction, a shorter slide
    # In segments of 8 frames: checkpoints and carried adjoints while the box slides.
    assert rel(results["sliding"]["mu_segments"], results["sliding"]["mu"]) < 1e-10
    assert rel(results["resting"]["k"], results["resting"]["fd_k"]) < 0.02
    assert results["resting"]["k"] > 0  # stiffer, less sag


def test_orientation_gradient_is_tangent_and_matches_central_differences_along_tangents(results):
    r = results["orientation"]
    assert abs(r["along_q"]) < 1e-12 * np.linalg.norm(r["grad"])  # the key is normalised: no radial part
    assert max(rel(r["tangents"], r["fd"])) < 0.01, r


def test_time_of_impact_the_gradient_is_the_local_slope_not_the_slope_across_contact_events(results):
    for name in ("plain", "materials"):
        r = results[f"toi_{name}"]
        assert rel(r["grad"], r["local"]) < 0.01  # between events: exact
        # Across a window of events the samples jump, some against the gradient's sign, and the
        # fitted slope is not the gradient (the bound docs/gradients.md states).
        assert np.any(np.sign(np.diff(r["samples"])) != np.sign(r["grad"])), r
        assert abs(r["window_slope"] - r["grad"]) > 0.1 * abs(r["grad"]), r


def test_fit_recovers_restitution_and_throw_from_a_recording_clean_and_with_2mm_noise(results):
    for name in ("fit", "fit_noise"):
        r = results[name]
        assert r["e"] == pytest.approx(0.6, rel=0.02), r
        assert np.allclose(r["v0"], (0.8, -1.0, 0.4), rtol=0.01), r
        assert r["loss"][-1] < r["loss"][0]
    assert results["fit"]["loss"][-1] < 1e-8


def test_the_gradient_at_a_point_is_the_same_after_runs_at_other_values(results):
    # The fused adjoint (one launch a segment) against itself after other runs, and against the
    # per-substep adjoint: Taichi 1.7's ad-stacks overhung their allocations by 4 bytes when full, so
    # the gradients at A once drifted by up to 37x after a per-substep adjoint ran at B.
    r = results["repeat"]
    size = np.abs(r["per_substep"]).max()
    for name in ("again", "per_substep", "segments", "per_substep_segments"):
        assert np.abs(np.subtract(r[name], r["first"])).max() <= 1e-10 * size, (name, r)


def test_a_float32_gradient_through_a_bounce_agrees_with_float64(ti_cpu, results):
    # The suite's process computes in float32, where the 4 bytes Taichi 1.7's ad-stacks lacked are
    # a whole adjoint: this gradient was 3.6 % off (v0's y) before the pass's adjoints were
    # compiled with spare entries (rigid.diff.passes, its compile settings).
    import rigid
    from gradients_fp64_worker import FLOAT32_CASE, float32_case_cotangent

    case = FLOAT32_CASE
    g = rigid.gradient(case["scene"], case["frames"], float32_case_cotangent(), case["wrt"])
    got = np.concatenate([np.ravel(g[n]) for n in case["wrt"]])
    reference = np.asarray(results["float32_reference"])
    assert np.abs(got - reference).max() < 1e-4 * np.abs(reference).max(), (got, reference)


@pytest.mark.parametrize("call, message", [
    (dict(wrt=["velocity"]), "wrt 'velocity' is not a key the gradient takes"),
    (dict(wrt=["restitution"]), "the scene sets no restitution"),
    (dict(cot={"x": np.zeros((5, 1, 3))}), "cotangent 'x' has shape (5, 1, 3)"),
    (dict(cot={"speed": np.zeros((11, 1, 3))}), "cotangent 'speed' is not a row"),
    (dict(scene=dict(integrator="rk4")), "integrator = 'rk4' is not differentiated"),
    (dict(scene=dict(count=3)), "count > 1"),
    (dict(scene=dict(springs=({"bodies": [0, -1]},))), "[[spring]]s are not differentiated"),
    (dict(frames=0), "frames = 0"),
])
def test_bad_inputs_are_one_line_before_any_compile(call, message):
    import rigid
    from rigid.errors import UserError

    scene = dict(mesh="sphere.obj", scale=0.3, **call.get("scene", {}))
    frames = call.get("frames", 10)
    cot = call.get("cot", {"x": np.zeros((11, 1, 3))})
    with pytest.raises(UserError) as err:
        rigid.gradient(scene, frames, cot, call.get("wrt", ["initial_velocity"]))
    assert message in str(err.value) and "\n" not in str(err.value)
