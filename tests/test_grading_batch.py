"""The grader end to end through scripts/grade.py, in three batches run one after the other.

Main batch (a folder of .py files, a subfolder and a zip): the handout scores 0
on every TODO (the solution's 90/90: test_handout_zero), each wrong variant loses exactly its
TODO's points with a message naming the mistake (several variants to a file,
on different TODOs: grading_variants.COMBINED), two correct-but-different
variants score full marks. Misbehaving batch (--timeout TIMEOUT): a crash, a
sys.exit, an endless loop at import and a memory hog each lose every TODO,
within the time limit; one file (grading_variants.HANG_SYNTAX_FLOOD) with an
endless loop inside TODO 6 and a syntax error in TODO 4 loses only those two,
and its print flood and writes to HOME cost nothing. Original batch: files in
the course's original handout format (tests/data/original_handout/ in the real
handout's shape, and grading_original_variants.py's variants of it, detected as
such; graded with --original-handout, so each child starts from the kernels of
the handout solved): bonus terms inside TODOs with other parameters, in a file
formatted by black, score 90/90 with their notes, unsolved 0, and files that
carry several variants each (grading_original_variants.COMBINED) lose exactly
the TODOs of their mistakes, known or not, a lost marker, a syntax error and an
endless loop in TODO 6 (within the time limit), while edits of the given code
cost nothing (their note is kept); a zip brings its own mesh, and the batch
summary is written beside the CSV. All write JSON and CSV. The self-check
(--check) then runs on the main batch's files and must agree with grade.py on each.
"""
import csv
import json
import re
import subprocess
import sys
import time
import zipfile
from pathlib import Path

import pytest

import grading_original_variants as original
from conftest import ROOT
from grading_variants import COMBINED as MAIN_COMBINED, CORRECT, HANG_SYNTAX_FLOOD, SOLUTION, WRONG, make
from rigid.grading.handout import make_handout

MISBEHAVING = ("crash_at_import", "exit_at_import", "hang_at_import", "memory_hog", HANG_SYNTAX_FLOOD)
# A stage's limit in CPU seconds (rigid.grading.sandbox), the same on a loaded machine; an endless
# sleep is stopped after as many wall seconds. The graders' children compile with quick compile
# (rigid.grading.checks): measured on 2 cores with an empty kernel cache, no stage of these batches
# used more than 0.8 CPU-s (project format: the trajectory, the engine compiled with the file's
# units) or 1.4 CPU-s (original format: the first stage, the whole file compiled and run), so the
# limits leave ~3x for a slower or loaded machine (a throttled one ran the suite's CPU 2x slower).
# The endless loops spin up to them, so they are the batch's largest cost (10 and 20 s before quick
# compile, then 4 and 6).
TIMEOUT = 3
ORIGINAL_TIMEOUT = 4
# End to end, the original format's variants folded into few files: each grading costs ~4 CPU-s (the
# file's kernels compile for each version of it), whatever the file holds. Every variant of
# grading_original_variants.py is graded as one of these files, or one of its parts, or is left out here:
ORIGINAL_FULL = ("bonus_inside_friction",)
ORIGINAL_WRONG = ("marker_syntax_unrotated", "unknown_mistakes_edits_hang6", "mistakes_ab")
ZIPPED = "mistakes_ab"  # in dan's zip, with the mesh it reads
ORIGINAL = (*ORIGINAL_FULL, "unsolved", *(n for n in ORIGINAL_WRONG if n != ZIPPED))
LEFT_OUT = {  # variant: why it is not graded end to end
    # mistakes_ab's slips, one per TODO, with the same messages (the other TODOs full: the other files)
    **dict.fromkeys(("t1_no_mass", "t2_no_mass", "t3_sign", "t4_swapped_cross", "t5_no_dt", "t6_no_half", "t7_order"),
                    "mistakes_ab"),
    "marker_variants": "their regions: test_grading_original.py, line by line", "layout": "the same",
    # black_formatted is bonus_inside_friction's base, graded as that file: one full-marks grading for both
    # (measured: the same verdicts, messages and notes, but line numbers, as that file before black).
    # solved.py is the base of the wrong files, whose right TODOs pass velocity-first, and the batch's
    # warm-up (--original-handout) grades the handout solved end to end
    "black_formatted": "bonus_inside_friction", "solved": "black_formatted, and the warm-up",
    "bonus_inside": "bonus_inside_friction", "bonus_friction": "bonus_inside_friction",
}


def parts(name: str) -> set:
    """The variants file ``name`` holds (grading_original_variants.COMBINED, nested), itself included."""
    return {name}.union(*(parts(p) for p in original.COMBINED.get(name, ())))


assert {p for n in (*ORIGINAL, ZIPPED) for p in parts(n)} | set(LEFT_OUT) >= set(original.WRONG) | set(original.FULL)
HANDOUT = ROOT / "tests" / "data" / "original_handout" / "unsolved.py"  # the original batch's warm cache (--original-handout)


def _grade(folder: Path, out: Path, *extra, jobs: int = 1) -> list:
    return [sys.executable, str(ROOT / "scripts" / "grade.py"), str(folder), "--jobs", str(jobs),
            "--json", str(out / "grades.json"), "--csv", str(out / "grades.csv"), *extra]


@pytest.fixture(scope="module")
def batches(tmp_path_factory):
    base = tmp_path_factory.mktemp("grading")
    main, bad, orig = base / "main", base / "bad", base / "original"
    for folder in (main, bad, orig):
        folder.mkdir()
    for name in MAIN_COMBINED:
        (main / f"{name}.py").write_text(make(name))
    (main / "handout.py").write_text(make_handout(SOLUTION))
    nested = main / "bob_folder" / "work"
    nested.mkdir(parents=True)
    (nested / "rigid_body_dynamic.py").write_text(make(CORRECT[1]))
    with zipfile.ZipFile(main / "3035123456_alice_assignment3.zip", "w") as z:
        z.writestr("alice/rigid_body_dynamic.py", make(CORRECT[0]))
        z.writestr("__MACOSX/alice/._rigid_body_dynamic.py", "junk")
    for name in MISBEHAVING:
        (bad / f"{name}.py").write_text(make(name))
    for name in ORIGINAL:
        (orig / f"{name}.py").write_text(original.make(name))
    with zipfile.ZipFile(orig / "3035000002_dan_assignment3.zip", "w") as z:
        z.writestr("dan/rigid_body_dynamic.py", original.make(ZIPPED))
        z.writestr("dan/dan_brick.obj", (ROOT / "assets" / "brick.obj").read_bytes())
    checked = {n: main / f"{n}.py" for n in [*MAIN_COMBINED, "handout"]}  # for the self-check
    checked["bob_folder"] = nested / "rigid_body_dynamic.py"
    checked["3035123456_alice_assignment3"] = base / "alice.py"
    checked["3035123456_alice_assignment3"].write_text(make(CORRECT[0]))
    probe = Path.home() / "grader_probe.txt"
    probe.unlink(missing_ok=True)
    # One process at a time, one child each but the main batch's two (grade.py's --jobs path) and the
    # misbehaving batch's two (hang_at_import sleeps, using no CPU, beside the others): the suite's
    # other worker has the other core. Side by side (seven Taichi processes on two cores,
    # with the other worker's) the batches cost more CPU time, theirs and the rest of the suite's:
    # measured on a fresh clone, 2 cores, interleaved: the whole suite 264 s (516 CPU-s) side by side,
    # 229 and 238 s (444 and 464 CPU-s) this way.
    commands = {"main": _grade(main, main, jobs=2), "bad": _grade(bad, bad, "--timeout", str(TIMEOUT), jobs=2),
                "original": _grade(orig, orig, "--timeout", str(ORIGINAL_TIMEOUT), "--original-handout", str(HANDOUT)),
                "selfcheck": [sys.executable, str(ROOT / "tests" / "grading_selfcheck_worker.py"),
                              str(base / "selfcheck.json"), *map(str, checked.values())]}
    start = time.monotonic()
    outputs = {}
    for k, command in commands.items():
        proc = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=600)
        assert proc.returncode == 0, proc.stderr
        outputs[k] = (proc.stdout, proc.stderr)
    elapsed = time.monotonic() - start
    folders = dict(main=main, bad=bad, original=orig)
    result = {k: {Path(r["submission"]).stem: r for r in json.loads((folder / "grades.json").read_text())}
              for k, folder in folders.items()}
    selfcheck = json.loads((base / "selfcheck.json").read_text())
    return dict(result=result, stdout={k: o[0] for k, o in outputs.items()}, folders=folders,
                elapsed=elapsed, probe=probe, selfcheck={n: selfcheck[str(f)] for n, f in checked.items()})


def points(r):
    return {int(k): t["points"] for k, t in r["todos"].items()}


def test_handout_zero(batches):
    # The solution's full marks: batch.prepare grades it like a submission (a child, every TODO must
    # pass) before a grader version grades anything, and test_grading_sandbox's sibling (the solution
    # and a comment) scores 90 in the sandbox, as the correct variants below do.
    res = batches["result"]["main"]
    assert res["handout"]["total"] == 0
    assert all("placeholder" in t["message"] for t in res["handout"]["todos"].values())


def combined_file(name: str) -> str:
    return next(file for file, parts in MAIN_COMBINED.items() if name in parts)


@pytest.mark.parametrize("name", sorted(WRONG))
def test_wrong_variant_loses_exactly_its_todo(batches, name):
    todo, words = WRONG[name]
    file = combined_file(name)
    r = batches["result"]["main"][file]
    got = points(r)
    lost = {WRONG[part][0] for part in MAIN_COMBINED[file]}
    assert got[todo] == 0 and not r["todos"][str(todo)]["passed"]
    assert all(got[k] == r["todos"][str(k)]["max"] > 0 for k in got if k not in lost), r["todos"]
    message = r["todos"][str(todo)]["message"]
    assert message.startswith(f"TODO {todo}:") and all(w in message for w in words), message


def test_correct_but_different_variants_score_full(batches):
    res = batches["result"]["main"]
    for name in ("bob_folder", "3035123456_alice_assignment3"):
        assert res[name]["total"] == 90, (name, res[name]["todos"])
    assert "velocity-first" in res["3035123456_alice_assignment3"]["todos"]["5"]["message"]


def test_misbehaving_submissions_lose_only_their_points_within_the_limit(batches):
    res = batches["result"]["bad"]
    for name, words in (("crash_at_import", "RuntimeError"), ("exit_at_import", "sys.exit"),
                        ("hang_at_import", f"did not finish within {TIMEOUT} s"), ("memory_hog", "memory")):
        assert res[name]["total"] == 0, name
        assert all(words in t["message"] for t in res[name]["todos"].values()), res[name]["todos"]
    hang6 = res[HANG_SYNTAX_FLOOD]  # the other TODOs graded in a fresh process; the flood costs nothing
    assert points(hang6) == {1: 15, 2: 10, 3: 10, 4: 0, 5: 10, 6: 0, 7: 15}, hang6["todos"]
    assert "update_orientation did not finish" in hang6["todos"]["6"]["message"]
    assert "TODO 4: the code between '# TODO 4:' and '# END TODO 4' has a syntax error at line" in \
        hang6["todos"]["4"]["message"]
    out = hang6["output"]
    assert len(out) < 5000 and "bytes of output left out" in out  # 20 MB of prints, truncated
    assert not batches["probe"].exists()  # HOME pointed into the child's temporary folder
    # Hang guards, not timings: stopped after about the limit, not left to run (generous for a loaded
    # machine, where the import before the endless loop and the other stages are slow in wall time).
    assert res["hang_at_import"]["seconds"] < 60
    assert hang6["seconds"] < 120
    orig6 = batches["result"]["original"]["unknown_mistakes_edits_hang6"]  # the original format: the same isolation
    assert points(orig6)[6] == 0 and orig6["format"] == "original" and points(orig6)[4] == 15
    assert f"the code under '# TODO 6:' did not finish within {ORIGINAL_TIMEOUT} s" in orig6["todos"]["6"]["message"]


def test_csv_has_a_row_per_submission_and_a_column_per_todo(batches):
    folder = batches["folders"]["main"]
    rows = list(csv.DictReader((folder / "grades.csv").open(encoding="utf-8")))
    assert len(rows) == len(batches["result"]["main"]) == len(MAIN_COMBINED) + 3
    assert list(rows[0]) == ["submission", "uid", "name", *(f"todo{k}" for k in range(1, 8)), "total",
                             "max_total", "feedback"]
    alice = next(r for r in rows if r["submission"].endswith(".zip"))
    assert (alice["uid"], alice["name"], alice["total"]) == ("3035123456", "alice", "90")
    wrong = next(r for r in rows if r["submission"].endswith(f"{combined_file('t3_sign')}.py"))  # TODOs 1, 3, 5, 7 lost
    assert (wrong["todo1"], wrong["todo2"], wrong["todo3"], wrong["todo4"], wrong["total"]) == ("0", "10", "0", "15", "40")
    assert all(f"TODO {k}" in wrong["feedback"] for k in (1, 3, 5, 7)) and "TODO 2" not in wrong["feedback"]
    assert "points per TODO" in batches["stdout"]["main"] and "total 90" in batches["stdout"]["main"]
    print(f"three batches ({len(rows)} + {len(MISBEHAVING)} + {len(ORIGINAL) + 1} submissions): "
          f"{batches['elapsed']:.1f} s")


@pytest.mark.parametrize("name", ORIGINAL_FULL)
def test_original_format_right_files_score_full_with_their_notes(batches, name):
    r = batches["result"]["original"][name]
    assert r["format"] == "original" and r["total"] == 90, (name, r["todos"])
    for words in original.NOTES.get(name, []):
        assert any(words in n for n in r["notes"]), (words, r["notes"])
    if name not in original.NOTES:
        assert r["notes"] == [], r["notes"]


def test_original_format_unsolved_zero_and_the_details(batches):
    res = batches["result"]["original"]
    assert all(r["format"] == "project" for r in batches["result"]["main"].values())
    black = res["bonus_inside_friction"]  # in black's layout: its multi-line TODOs run as the reference's
    assert all("agree with the reference lines" in t["message"] for t in black["todos"].values()), black["todos"]
    assert "position-first" in black["todos"]["5"]["message"]
    assert "velocity-first" in res["marker_syntax_unrotated"]["todos"]["5"]["message"]  # the 2023 hint's order
    bonus = next(n for n in black["notes"] if n.startswith("bonus terms"))
    assert "(TODO 2)" in bonus and "(TODO 5)" in bonus and "set to 0" in bonus
    # The given code's edits are the bonus's own, the same as in the file before black: black's
    # reformatting of the given code is no edit of it
    edits = next(n for n in black["notes"] if n.startswith("edits of the given code"))
    assert re.findall(r"line \d+: ([^;]*)", edits) == [
        "v_t = particle_velocities[i] - ti.Vector([0.0, particle_velocities[i][1], 0.0])",
        "particle_force[i] -= friction_stiffness * f_collision * v_t", "total_force = ti.Vector([0.0, 0.0, 0.0])",
        "total_force -= 1e-3 * velocity_damping_stiffness * body_velocity[None]"], edits
    assert edits.endswith("; 1 given line of the handout removed or rewritten") and "elsewhere" not in edits, edits
    assert res["unsolved"]["total"] == 0
    assert all("not done" in t["message"] for t in res["unsolved"]["todos"].values())


def test_batch_summary_beside_the_csv(batches):
    text = (batches["folders"]["original"] / "grades.summary.txt").read_text(encoding="utf-8")
    assert text.startswith(f"Batch summary: {len(batches['result']['original'])} submissions")
    assert "Scores:" in text and "TODOs lost most often:" in text and "Not graded at all: 0" in text
    assert "TODO 7 (update L, I⁻¹ and ω): lost by" in text and "x the new quaternion q changes at twice" in text
    assert "Batch summary" in batches["stdout"]["original"]


@pytest.mark.parametrize("name", ORIGINAL_WRONG)
def test_original_format_mistakes_lose_exactly_their_todos(batches, name):
    res = batches["result"]["original"]
    r = res[name] if name != ZIPPED else res["3035000002_dan_assignment3"]
    for k, t in r["todos"].items():
        words = original.WRONG[name].get(int(k))
        assert t["passed"] == (words is None), (k, t["message"])
        assert words is None or all(w in t["message"] for w in words), t["message"]
    for words in original.NOTES.get(name, []):  # a combined file's parts' notes (given_edits')
        assert any(words in n for n in r["notes"]), (words, r["notes"])
    if name == ZIPPED:  # two ti.init calls and a ti.GUI loop that never checks gui.running; no note on the
        # mesh (the zip brings the one it reads), only on those edits of the given code
        assert any("ti.init 2 times" in n for n in r["notes"]) and r["student"] == {"uid": "3035000002", "name": "dan"}
        assert all("ti.init 2 times" in n or n.startswith("edits of the given code") for n in r["notes"]), r["notes"]
    rows = list(csv.DictReader((batches["folders"]["original"] / "grades.csv").open(encoding="utf-8")))
    assert len(rows) == len(res) and any("note: " in row["feedback"] for row in rows)


def test_self_check_agrees_with_grade_py(batches):
    """--check's verdicts (rigid.grading.selfcheck, on the answers file beside the solution; run by
    tests/grading_selfcheck_worker.py after the batches) equal grade.py's on every file both saw."""
    res = batches["result"]["main"]
    assert len(batches["selfcheck"]) == len(MAIN_COMBINED) + 3
    for name, mine in batches["selfcheck"].items():
        theirs = res[name]["todos"]
        assert not mine["joint"], (name, mine["joint"])
        everything = all(t["passed"] for t in mine["results"].values())
        for k, t in mine["results"].items():
            assert t["passed"] == theirs[k]["passed"], (name, k, t, theirs[k])
            if everything or not t["passed"]:
                assert t["message"] == theirs[k]["message"], (name, k)
            else:  # grade.py adds its simulation's verdict, which --check runs once all 7 pass
                assert theirs[k]["message"].startswith(t["message"]), (name, k)
