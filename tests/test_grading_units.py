"""The grader's pieces without Taichi: diagnosis messages, the mistake table, submissions, points.

The right answers here are the slides' formulas written again in numpy (not
the grader's tables), so a wrong table entry cannot agree with itself.
"""
import zipfile

import numpy as np
import pytest

from rigid.errors import UserError
from rigid.grading.cli import parse_points
from rigid.grading.diagnose import close, diagnose_output
from rigid.grading.mistakes import MISTAKES
from rigid.grading.specs import DEFAULT_POINTS, TODOS, sample_inputs
from rigid.grading.submissions import discover
from rigid.engine.rotation import quaternion_multiplication_np


def right_answers(k, d):
    """The slides' formulas, one call at a time (name -> (K, ...))."""
    rows = []
    for i in range(len(next(iter(d.values())))):
        a = {n: v[i] for n, v in d.items()}
        if k == 1:
            r = a["r0"]
            rows.append({"I": a["m"] * (r @ r * np.eye(3) - np.outer(r, r))})
        elif k == 2:
            rows.append({"f": a["m"] * a["g"]})
        elif k == 3:
            rows.append({"F": a["f"]})
        elif k == 4:
            rows.append({"tau": np.cross(a["p"] - a["x"], a["f"])})
        elif k == 5:
            rows.append({"x_new": a["x"] + a["dt"] * a["P"] / a["M"], "P_new": a["P"] + a["dt"] * a["F"]})
        elif k == 6:
            q = a["q"] + a["dt"] * 0.5 * quaternion_multiplication_np(np.r_[0.0, a["omega"]], a["q"])
            rows.append({"q_new": q / np.linalg.norm(q)})
        else:
            L = a["L"] + a["dt"] * a["tau"]
            inv = a["R"] @ a["I0_inv"] @ a["R"].T
            rows.append({"L_new": L, "I_inv": inv, "omega": inv @ L})
    return {n: np.array([row[n] for row in rows]) for n in rows[0]}


@pytest.mark.parametrize("k", list(TODOS))
def test_every_known_mistake_is_far_from_right_and_named_by_its_own_message(k):
    spec, d = TODOS[k], sample_inputs(k)
    right = right_answers(k, d)
    for output, message, predict in MISTAKES[k]:
        wrong = predict(d)
        assert not close(wrong, right[output]), message  # the grader's inputs expose it
        sub = dict(right, **{output: wrong})
        said = diagnose_output(spec, output, wrong, right[output], d, sub)
        assert message in said, (message, said)


def test_generic_diagnoses_name_factor_direction_and_components():
    spec, d = TODOS[4], sample_inputs(4)
    tau = right_answers(4, d)["tau"]
    say = lambda out: diagnose_output(spec, "tau", out, tau, d, {"tau": out})  # noqa: E731
    assert "constant factor 3" in say(3 * tau)
    assert "lacks a factor Δt" not in say(3 * tau)
    rotated = tau[:, [1, 2, 0]]  # same length, other direction
    assert "right magnitude but the wrong direction" in say(rotated)
    y_wrong = tau.copy()
    y_wrong[:, 1] += 1.0
    assert "its y component" in say(y_wrong)
    assert "NaN" in say(tau * np.nan)
    assert "zero" in say(0 * tau)
    spec2, d2 = TODOS[2], sample_inputs(2)
    f = right_answers(2, d2)["f"]
    assert "extra factor of the mass" in diagnose_output(spec2, "f", f * d2["m"][:, None], f, d2, {})


def test_update_factor_speaks_of_rate():
    spec, d = TODOS[7], sample_inputs(7)
    right = right_answers(7, d)
    L = d["L"] + 2 * d["dt"][:, None] * d["tau"]
    assert "twice the expected rate" in diagnose_output(spec, "L_new", L, right["L_new"], d, dict(right, L_new=L))
    L = d["L"] + d["dt"][:, None] ** 2 * d["tau"]
    assert "extra factor Δt" in diagnose_output(spec, "L_new", L, right["L_new"], d, dict(right, L_new=L))


def test_default_points_sum_to_90_and_points_parse():
    assert sum(DEFAULT_POINTS.values()) == 90
    assert parse_points("20,10,10,10,10,15,15")[1] == 20.0
    for bad in ("1,2,3", "a,b,c,d,e,f,g", "1,1,1,1,1,1,-1"):
        with pytest.raises(UserError):
            parse_points(bad)


def test_discover_files_folders_zips(tmp_path):
    (tmp_path / "alice.py").write_text("x = 1\n")
    nested = tmp_path / "bob" / "deep"
    nested.mkdir(parents=True)
    (nested / "rigid_body_dynamic.py").write_text("x = 2\n")
    (nested / "helper.py").write_text("x = 3\n")
    with zipfile.ZipFile(tmp_path / "3035_carol_assignment3.zip", "w") as z:
        z.writestr("__MACOSX/carol/._rigid_body_dynamic.py", "junk")
        z.writestr("carol/rigid_body_dynamic.py", "x = 4\n")
    (tmp_path / "broken_assignment3.zip").write_bytes(b"not a zip")
    (tmp_path / "notes.txt").write_text("")
    (tmp_path / "empty").mkdir()
    subs, notes = discover([tmp_path])
    by_name = {s.path.name: s for s in subs}
    assert sorted(by_name) == ["3035_carol_assignment3.zip", "alice.py", "bob", "broken_assignment3.zip", "empty"]
    assert by_name["alice.py"].read() == (b"x = 1\n", "")
    assert by_name["bob"].read() == (b"x = 2\n", "")
    assert by_name["3035_carol_assignment3.zip"].read() == (b"x = 4\n", "")
    assert by_name["3035_carol_assignment3.zip"].student == ("3035", "carol")
    assert "not a readable zip" in by_name["broken_assignment3.zip"].read()[1]
    assert "holds no rigid_body_dynamic.py" in by_name["empty"].read()[1]
    assert any("notes.txt" in n for n in notes)
    with pytest.raises(UserError):
        discover([tmp_path / "missing"])


class _Events:
    def __init__(self):
        self.log = []

    def emit(self, **fields):
        self.log.append(fields)


class _Expected:
    def trajectory(self, form):
        return np.zeros((3, 10))


def test_trajectory_blame_halves_to_the_straying_unit_and_spares_an_engine_bug(monkeypatch):
    from types import SimpleNamespace

    from rigid.grading import checks, trajectory
    from rigid.engine.units import UNIT_NAMES

    reference = SimpleNamespace(**{n: f"ref.{n}" for n in UNIT_NAMES})
    module = SimpleNamespace(**{n: f"sub.{n}" for n in UNIT_NAMES})
    runs = []

    def fake_run(units):  # TODO 3 of the submission makes the body stray; nothing else does
        runs.append(units)
        return np.ones((3, 10)) if units.total_force_term == "sub.total_force_term" else np.zeros((3, 10))

    monkeypatch.setattr(trajectory, "run", fake_run)
    events = _Events()
    results = {k: {"passed": True} for k in range(1, 8)}
    checks.check_trajectories(events, module, reference, results, _Expected())
    verdicts = {k: e["passed"] for e in events.log if e.get("event") for k in e["todos"]}
    assert verdicts == {1: True, 2: True, 3: False, 4: True, 5: True, 6: True, 7: True}
    assert len(runs) == 7  # the joint run, then halves: [1,2,3] [4..7], [1] [2,3], [2] [3]

    def broken(units):
        raise RuntimeError("engine bug")

    monkeypatch.setattr(trajectory, "run", broken)
    events = _Events()
    checks.check_trajectories(events, module, reference, {1: {"passed": True}, 2: {"passed": False}},
                              _Expected())
    (verdict,) = [e for e in events.log if e.get("event")]
    assert not verdict["passed"] and "not graded" in verdict["message"] and "engine" in verdict["message"]


def test_a_wrong_inertia_is_said_in_words_not_as_a_matrix():
    """inertia_words.describe on hand-built tensors (numbers made here, not by the grader)."""
    from rigid.grading.inertia_words import describe

    rng = np.random.default_rng(7)
    m, r = rng.uniform(0.3, 3.0, 16), rng.normal(size=(16, 3))
    rr = np.einsum("ni,nj->nij", r, r)
    dot = np.einsum("ni,ni->n", r, r)[:, None, None] * np.eye(3)
    mass = m[:, None, None]
    assert describe(mass * (dot - rr), dict(m=m, r0=r)) == ""  # right: nothing to say
    assert describe(mass * (dot + rr), dict(m=m, r0=r)) == (
        "differs from I0 = Σ m (r0ᵀr0 E − r0 r0ᵀ): it adds m r0 r0ᵀ where it must subtract it (the sign of the "
        "r0 r0ᵀ term)")
    words = describe(mass * rr + 42 * mass * np.eye(3), dict(m=m, r0=r, M_body=42 * m))  # issue 52's file
    assert "the sign of the r0 r0ᵀ term" in words and "lacks the m (r0ᵀr0) E term" in words
    assert "has an extra identity term (the body's mass M times E" in words
    assert describe(rng.normal(size=(16, 3, 3)), dict(m=m, r0=r)) == ""  # no mix of the terms: the generic words
