"""The original handout format's pieces, without the sandbox: detection, TODO regions, versions of a
file, meshes, the headless window. The end-to-end grading of such files is in test_grading_batch.py."""
import pytest

from conftest import ROOT, SOLUTION
from grading_original_variants import SOLVED, make
from rigid.grading.cli import build_parser
from rigid.grading.handout import make_handout
from rigid.grading.original import headless
from rigid.grading.original.detect import detect
from rigid.grading.original.meshes import plan
from rigid.grading.original.regions import RegionError
from rigid.grading.original.variants import FileModel

SPHERE = (ROOT / "assets" / "sphere.obj").read_bytes()


def code_of(model, k):
    return [line.strip() for line in model.regions[k].code(model.text.splitlines())
            if line.strip() and not line.strip().startswith("#")]


def test_format_detected_per_file_and_forced_by_flag():
    solution = SOLUTION.read_text()
    assert detect(solution) == detect(make_handout(solution)) == "project"
    for name in ("solved", "unsolved", "bonus_friction", "window_and_double_init", "mistakes_a"):
        assert detect(make(name)) == "original", name
    assert detect("print('hello')\n") == "project"  # graded as today: 'no function particle_inertia'
    assert build_parser().parse_args(["x", "--format", "original"]).format == "original"
    assert build_parser().parse_args(["x"]).format == "auto"


def test_regions_hold_exactly_the_todo_code_and_name_the_shared_locals():
    model = FileModel(SOLVED)
    assert not model.problems
    assert code_of(model, 2) == ["particle_force[i] = particle_mass * gravity"]
    assert code_of(model, 5) == ["body_cm_position[None] += dt * body_velocity[None]",
                                 "body_velocity[None] += dt * body_force / body_mass[None]"]
    assert code_of(model, 6)[-1].startswith("body_rotation_quaternion[None] += 0.5 * dt")  # not the normalising
    assert model.regions[2].loop_var == "i" and model.regions[3].loop_var is None
    assert model.shared == {1: "inertia", 3: "body_force", 4: "body_torque"}
    bonus = FileModel(make("bonus_friction"))
    assert bonus.shared[3] == "total_force"  # the student's own name, read by their TODO 5
    assert not any("friction" in line for k in bonus.regions for line in code_of(bonus, k))  # bonus stays given
    unsolved = FileModel(make("unsolved"))
    assert all(not r.has_code(unsolved.text.splitlines()) for r in unsolved.regions.values())


def test_a_students_comment_a_syntax_error_or_a_lost_marker_cost_only_their_todo():
    text = SOLVED.replace("    body_cm_position[None] += dt * body_velocity[None]\n",
                          "    # update the position with the old velocity\n"
                          "    body_cm_position[None] += dt * body_velocity[None]\n")
    text = text.replace("body_torque += arm.cross(particle_force[i])", "body_torque += arm.cross(particle_force[i]")
    text = text.replace("    # TODO 3: compute the force for rigid body\n", "")
    model = FileModel(text)
    assert len(code_of(model, 5)) == 2  # its own '# update ...' comment did not end TODO 5
    assert set(model.problems) == {3} and "no '# TODO 3:'" in model.problems[3]
    assert code_of(model, 6) == code_of(FileModel(SOLVED), 6)  # the unclosed bracket in TODO 4 stays there
    with pytest.raises(RegionError, match="syntax error at line 2"):
        FileModel("import taichi as ti\nx = (\n" + SOLVED)  # outside the TODOs: nothing can run


def test_versions_keep_everything_outside_the_todos():
    model = FileModel(make("bonus_friction"))
    assert model.build(student=range(1, 8)).text == model.text  # all the student's: the file itself
    params, notes = model.perturbed()
    assert not notes and params["particle_mass"] == 0.7 and params["dt"] == 8e-4
    changed = model.build(student=range(1, 8), params=params)
    diff = [(a, b) for a, b in zip(model.text.splitlines(), changed.text.splitlines()) if a != b]
    assert [b for _, b in diff] == ["particle_mass = 0.7", "initial_velocity = ti.Vector([2.5, 0.0, 1.5])",
                                    "initial_angular_velocity = ti.Vector([4.0, -3.0, 6.0])", "dt = 0.0008"]
    reference = model.build()
    assert "total_force" in reference.text and "friction_stiffness * normal_force" in reference.text
    line = next(i for i, t in enumerate(reference.text.splitlines(), 1) if "ref6_q = " in t)
    assert reference.student_line(line) is None and reference.student_line(1) == 1


def test_meshes_from_the_submission_the_assets_or_ours_with_a_note():
    files, renames, notes = plan('read_obj_file("sphere.obj", scale=0.3)')
    assert files == {"sphere.obj": SPHERE} and not renames and not notes
    files, _, notes = plan("read_obj_file('bunny.obj')", {"bunny.obj": b"v 0 0 0\n"})
    assert files == {"bunny.obj": b"v 0 0 0\n"} and not notes
    files, _, notes = plan("read_obj_file('teapot.obj')")
    assert files == {"teapot.obj": SPHERE} and "teapot.obj" in notes[0] and "42-vertex sphere.obj" in notes[0]
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
    text = SOLVED.replace("dt = 1e-3\n", "dt = 1e-3\nhalf_dt = 0.5 * dt\n\n\ndef scaled(x):\n    return dt * x\n")
    assert harness.blocked_by(text, ["body_cm_position[None] += half_dt * body_velocity[None]"]) == "half_dt"
    assert harness.blocked_by(text, ["body_cm_position[None] += scaled(body_velocity[None])"]) == "scaled"
    assert harness.blocked_by(text, ["body_cm_position[None] += dt * body_velocity[None]  # half_dt"]) is None
    q = np.array([0.3, -0.5, 0.1, 0.8]) / np.linalg.norm([0.3, -0.5, 0.1, 0.8])
    assert np.allclose(quaternion_to_matrix_np(harness.matrix_to_quaternion(quaternion_to_matrix_np(q))),
                       quaternion_to_matrix_np(q))
