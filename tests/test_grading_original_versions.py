"""The original handout format's pieces, without the sandbox (continued from test_grading_original.py,
which reads the TODO regions): bonus parameters, edits of the given code, versions of a file, meshes,
the headless window and the harness's kernels, the warm-up versions, a wrong --original-handout.
The end-to-end grading of such files is in test_grading_batch.py."""
import pytest

from conftest import ROOT, SOLUTION
from grading_original_variants import SOLVED, make
from test_grading_original import code_of
from rigid.grading.original import headless
from rigid.grading.original.detect import detect
from rigid.grading.original.meshes import plan
from rigid.grading.original import given
from rigid.grading.original.variants import FileModel

SPHERE = (ROOT / "assets" / "sphere.obj").read_bytes()



def test_bonus_parameters_are_zero_in_every_version_and_edits_of_given_code_are_noted():
    model = FileModel(make("bonus_inside"))
    assert model.bonus == {"velocity_damping_stiffness": 1e3, "friction_stiffness": 0.1, "air_drag": 0.02,
                           "linear_damping": 0.5}
    graded = model.build(student=range(1, 8)).text
    for name in model.bonus:
        assert f"\n{name} = 0.0\n" in graded, name
    assert model.build(student=range(1, 8), keep_bonus=True).text == model.text
    assert "air_drag * particle_velocities[i]" in code_of(model, 2)[0]  # the bonus term stays in TODO 2
    edits = FileModel(make("given_edits"))
    note = given.note(edits.text, edits.regions)
    for words in ("ti.init(arch=ti.cpu, debug=False)", "substeps = int(1 / 120 // dt)", "(640, 640)",
                  "body_angular_velocity[None].cross(ri)"):
        assert words in note, words
    physics, _, elsewhere = note.partition("; elsewhere: ")  # the wall's sign error first, the window after
    assert "in the simulation (they change the physics): line 158: f_collision = collision_stiffness * " \
           "(particle_vertices[i][0] + 1)" in physics and "substeps = int(1 / 120 // dt)" in physics
    assert elsewhere.startswith("line 9: ti.init(arch=ti.cpu, debug=False)") and "(640, 640)" in elsewhere
    assert given.note(model.text, model.regions).count("line ") == 3  # friction (2 lines) and the body's damping
    assert given.note(SOLVED, FileModel(SOLVED).regions) == ""


def test_the_fingerprints_of_the_given_code_are_the_fixtures():
    unsolved = make("unsolved")
    assert given.hashes_of(unsolved, FileModel(unsolved).regions) == given.HASHES
    assert given.fingerprint('x = f("a",\n      b,)') == given.fingerprint("x = f('a', b)")


def test_versions_keep_everything_outside_the_todos():
    model = FileModel(make("bonus_friction"))
    assert model.build(student=range(1, 8)).text != model.text  # its friction_stiffness is 0 while grading
    assert model.build(student=range(1, 8), keep_bonus=True).text == model.text  # all the student's: the file
    params, notes = model.perturbed()
    assert not notes and params["particle_mass"] == 0.7 and params["dt"] == 8e-4
    changed = model.build(student=range(1, 8), params=params, keep_bonus=True)
    diff = [(a, b) for a, b in zip(model.text.splitlines(), changed.text.splitlines()) if a != b]
    assert [b for _, b in diff] == ["particle_mass = 0.7", "initial_velocity = ti.Vector([2.5, 0.0, 1.5])",
                                    "initial_angular_velocity = ti.Vector([4.0, -3.0, 6.0])", "dt = 0.0008"]
    reference = model.build()
    assert "total_force += particle_force[i]" in reference.text and "friction_stiffness * f_collision" in reference.text
    line = next(i for i, t in enumerate(reference.text.splitlines(), 1) if "ref6_q = " in t)
    assert reference.student_line(line) is None and reference.student_line(1) == 1


def test_meshes_from_the_submission_the_handout_or_ours_with_a_note(tmp_path):
    files, renames, notes = plan('read_obj_file("sphere.obj", scale=0.3)')  # issue 52: never silently ours
    assert files == {"sphere.obj": SPHERE} and not renames
    assert notes == ["the file reads sphere.obj, which the submission does not include: graded with the project's "
                     "sphere.obj (its 42-vertex icosphere has the handout's vertex and face counts but other "
                     "coordinates and orientation, so spins and bonus figures can differ from the student's run)"]
    (tmp_path / "sphere.obj").write_bytes(b"v 1 2 3\n")  # the handout's own mesh, beside --original-handout
    assert plan('read_obj_file("sphere.obj")', {}, tmp_path) == ({"sphere.obj": b"v 1 2 3\n"}, {}, [])
    files, _, notes = plan("read_obj_file('bunny.obj')", {"bunny.obj": b"v 0 0 0\n"})
    assert files == {"bunny.obj": b"v 0 0 0\n"} and not notes
    files, _, notes = plan("read_obj_file('teapot.obj')")
    assert files == {"teapot.obj": SPHERE} and "teapot.obj" in notes[0]
    assert "project's sphere.obj (its 42-vertex" in notes[0]
    files, renames, _ = plan(r"read_obj_file('C:\Users\amy\sphere.obj')")
    assert renames == {r"C:\Users\amy\sphere.obj": "sphere.obj"} and files == {"sphere.obj": SPHERE}
    files, renames, _ = plan("read_obj_file('/home/amy/../x/box.obj')")
    assert list(files) == ["box.obj"] and renames


def test_headless_window_runs_n_frames_and_stops_a_loop_that_ignores_it():
    recorder = headless.Recorder(3, snapshot=lambda: len(recorder.rows))
    headless.State.recorder = recorder
    try:
        window = headless.Window("x", (64, 64))
        gui = window.get_gui()
        frames = 0
        while window.running:
            with gui.sub_window("panel", 0, 0, 1, 1):
                assert gui.slider_float("dt", 0.5, 0, 1) == 0.5 and not gui.button("kick")
            assert not window.is_pressed(headless._UI("ui").SPACE) and window.get_events() == []
            frames += 1
            window.show()
        assert frames == 3 and recorder.rows == [0, 1, 2, 3]
        recorder = headless.State.recorder = headless.Recorder(2, snapshot=lambda: 0)
        with pytest.raises(headless.StopRun):
            for _ in range(100):  # while True: ... gui.show()
                headless.Window().show()
        assert len(recorder.rows) == 3
    finally:
        headless.State.recorder = None


def test_harness_kernels_parse_and_know_when_they_cannot_vary_dt():
    import ast

    import numpy as np

    from rigid.engine.rotation import quaternion_to_matrix_np
    from rigid.grading.original import harness

    model = FileModel(make("bonus_friction"))
    for k in model.regions:
        source = "".join(harness.kernel(k, model))
        ast.parse(source)
        assert f"def grader_todo{k}(dt: ti.f64, particle_mass: ti.f64, gravity:" in source
    assert "total_force = ti.Vector([grader_in[" in "".join(harness.kernel(5, model))  # the student's name
    todo3 = "".join(harness.kernel(3, model))  # declared before the given loop, as the handout does
    assert todo3.index("    total_force = ti.Vector([0.0, 0.0, 0.0])") < todo3.index("    for i in ti.grouped(")
    text = SOLVED.replace("dt = 1e-3\n", "dt = 1e-3\nhalf_dt = 0.5 * dt\n\n\ndef scaled(x):\n    return dt * x\n")
    assert harness.blocked_by(text, ["body_cm_position[None] += half_dt * body_velocity[None]"]) == "half_dt"
    assert harness.blocked_by(text, ["body_cm_position[None] += scaled(body_velocity[None])"]) == "scaled"
    assert harness.blocked_by(text, ["body_cm_position[None] += dt * body_velocity[None]  # half_dt"]) is None
    q = np.array([0.3, -0.5, 0.1, 0.8]) / np.linalg.norm([0.3, -0.5, 0.1, 0.8])
    assert np.allclose(quaternion_to_matrix_np(harness.matrix_to_quaternion(quaternion_to_matrix_np(q))),
                       quaternion_to_matrix_np(q))


def test_the_handouts_warm_up_versions_hold_the_reference_in_every_todo_in_both_orders():
    from rigid.grading.expected import FORMS
    from rigid.grading.original.warm import solved_version

    unsolved = (ROOT / "tests" / "data" / "original_handout" / "unsolved.py").read_text()
    versions = [solved_version(unsolved, form) for form in FORMS]  # position-first, velocity-first
    assert versions[0] == FileModel(unsolved).reference_text and solved_version(unsolved) == versions[1]
    models = [FileModel(v) for v in versions]
    assert all(detect(v) == "original" and not m.problems for v, m in zip(versions, models))
    for k in range(1, 8):  # only TODO 5's order differs, and no TODO is left unsolved
        same = code_of(models[0], k) == code_of(models[1], k)
        assert same == (k != 5), k
        assert code_of(models[0], k) != code_of(FileModel(unsolved), k), k


@pytest.mark.parametrize("content, words", [
    (None, "cannot read it"),
    ("project", "not a file in the course's original handout format"),
])
def test_a_wrong_original_handout_is_refused_in_one_line(tmp_path, content, words):
    from rigid.errors import UserError
    from rigid.grading.original.warm import prepare_original

    path = tmp_path / "handout.py"
    if content == "project":
        path.write_text(SOLUTION.read_text())
    with pytest.raises(UserError) as err:
        prepare_original(None, path)
    assert words in str(err.value) and "\n" not in str(err.value) and str(path) in str(err.value)


def test_does_not_run_is_said_only_when_the_students_own_file_fails(monkeypatch, tmp_path):
    import numpy as np
    from rigid.grading.original import child
    from rigid.grading.original.runner import Run

    model = FileModel(make("no_markers").replace("        is_in_contact = False\n", "        is_in_contact, n = False, 0\n"))
    assert model.kept[2] == (["        is_in_contact, n = False, 0\n"], [])  # a tuple of locals stays too
    runs = []
    monkeypatch.setattr(child, "run", lambda variant, path: runs.append(variant.text) or own)
    own = Run(np.zeros((31, 16)))
    message = child._does_not_run(model, tmp_path, "TaichiNameError: Name \"x\" is not defined (line 150)")
    assert message.startswith("the file runs as submitted, but not with the grader's reference lines in its TODOs "
                              "(TaichiNameError") and message.endswith("grade it by hand")
    assert runs == [model.build(range(1, 8)).text]  # the student's own code in every TODO
    own = Run(None, "ZeroDivisionError: division by zero (x.py, line 12)")
    assert child._does_not_run(model, tmp_path, "…") == "the file does not run: ZeroDivisionError: division by " \
                                                         "zero (x.py, line 12)"


def test_the_first_version_guesses_todo_5s_order_and_a_version_is_run_once(monkeypatch, tmp_path):
    """child.likely_form picks the first version's order of TODO 5 (so that it doubles as the reference run);
    runner.run reuses a run of the same text, but a failed one only where its error names the same lines."""
    import numpy as np
    from rigid.grading.original import runner
    from rigid.grading.original.child import likely_form
    from rigid.grading.original.warm import solved_version

    assert [likely_form(FileModel(make(n))) for n in ("solved", "black_formatted", "bonus_friction", "unsolved")] == \
        ["velocity-first", "velocity-first", "position-first", "position-first"]
    model = FileModel(solved_version(make("unsolved")))  # the reference lines as the student's code
    reference, own = model.build((), "velocity-first"), model.build(range(1, 8), "velocity-first")
    assert reference.text == own.text and reference.origin != own.origin
    for rows, runs in ((np.zeros((31, 16)), 1), (None, 2)):
        ran = []
        monkeypatch.setattr(runner, "_DONE", {})
        monkeypatch.setattr(runner, "_run", lambda variant, path, frames: ran.append(path) or runner.Run(rows, "x"))
        results = [runner.run(v, tmp_path / f"v{i}.py") for i, v in enumerate((reference, reference, own))]
        assert len(ran) == runs and results[0] is results[1] and (results[2] is results[0]) == (runs == 1), rows
