"""The original handout format's pieces, without the sandbox: detection and the TODO regions (the
handout's shape, marker spellings, layout, a lost marker, tabs, a syntax error). Bonus parameters,
versions, meshes and the headless window are in test_grading_original_versions.py; the end-to-end
grading of such files (every variant of grading_original_variants.py) is in test_grading_batch.py."""
import pytest

from conftest import SOLUTION
from grading_original_variants import SOLVED, make
from rigid.grading.cli import build_parser
from rigid.grading.handout import make_handout
from rigid.grading.original.detect import detect
from rigid.grading.original import given
from rigid.grading.original.regions import MARKER, RegionError
from rigid.grading.original.variants import FileModel


def code_of(model, k):
    return [line.strip() for line in model.regions[k].code(model.text.splitlines())
            if line.strip() and not line.strip().startswith("#")]


def test_format_detected_per_file_and_forced_by_flag():
    solution = SOLUTION.read_text()
    assert detect(solution) == detect(make_handout(solution)) == "project"
    for name in ("solved", "unsolved", "bonus_friction", "mistakes_a", "marker_variants", "black_formatted"):
        assert detect(make(name)) == "original", name
    assert detect("print('hello')\n") == "project"  # graded as today: 'no function particle_inertia'
    assert build_parser().parse_args(["x", "--format", "original"]).format == "original"
    assert build_parser().parse_args(["x"]).format == "auto"


SOLVED_CODE = {  # the code lines of each TODO in solved.py (the handout's shape)
    1: ["for i in ti.grouped(particle_vertices):", "r = particle_vertices[i] - body_cm_position[None]",
        "inertia += particle_mass * (r.dot(r) * ti.Matrix.identity(float, 3) - r.outer_product(r))"],
    2: ["particle_force[i] = particle_mass * gravity"],
    3: ["body_force += particle_force[i]"],
    4: ["arm = particle_vertices[i] - body_cm_position[None]", "body_torque += ti.math.cross(arm, particle_force[i])"],
    5: ["body_velocity[None] += dt * body_force / body_mass[None]", "body_cm_position[None] += dt * body_velocity[None]"],
}


def test_regions_of_the_handouts_shape_and_its_locals_declared_before_the_loops():
    model = FileModel(SOLVED)
    assert not model.problems and model.bonus == {}  # the handout declares the bonus parameters, never reads them
    for k, code in SOLVED_CODE.items():
        assert code_of(model, k) == code, k
    assert code_of(model, 6)[-1] == "body_rotation_quaternion[None] += dt * d_q"  # not the given normalising
    assert code_of(model, 7)[-1] == "body_angular_velocity[None] = body_inverse_inertia @ body_angular_momentum[None]"
    assert [model.regions[k].loop_var for k in range(1, 8)] == [None, "i", "i", "i", None, None, None]
    assert model.regions[3].outer == ["    body_force = ti.Vector([0.0, 0.0, 0.0])"]  # declared before its loop
    assert model.shared == {1: "inertia", 3: "body_force", 4: "body_torque"}
    unsolved = FileModel(make("unsolved"))
    assert all(not r.has_code(unsolved.text.splitlines()) or code_of(unsolved, r.k) == ["pass"] or
               code_of(unsolved, r.k)[-1] == "pass" for r in unsolved.regions.values())
    assert unsolved.shared == model.shared
    bonus = FileModel(make("bonus_friction"))
    assert bonus.shared[3] == "total_force"  # the student's own name, declared before the loop, read by TODO 5
    assert not any("friction" in line for k in bonus.regions for line in code_of(bonus, k))  # bonus stays given


def test_marker_spellings_and_a_moved_marker_are_read():
    model = FileModel(make("marker_variants"))
    assert not model.problems, model.problems
    for k in (1, 2, 3, 5):
        assert code_of(model, k) == SOLVED_CODE[k], k
    assert code_of(model, 4)[:2] == ["body_torque = ti.Vector([0.0, 0.0, 0.0])",
                                     "for i in ti.grouped(particle_vertices):"]  # moved above the given loop
    assert model.regions[4].loop_var is None and model.shared[4] == "body_torque"
    from rigid.grading.original.reference import lines_for
    ref = "".join(lines_for(4, model.regions[4], model.shared))
    assert ref.startswith("    body_torque = ti.Vector([0.0, 0.0, 0.0])\n    for ref_i in particle_vertices:")
    for spelling in ("# TODO: 1: Compute", "#TODO 1", "# todo 1:", "## TODO(1)", "# TODO #1 -", "#  TODO  1."):
        assert MARKER.match("    " + spelling)["k"] == "1", spelling
    assert not MARKER.match("    # TODO 12: later") and not MARKER.match("    x = 1  # TODO 1")


def test_layout_inside_a_region_never_ends_it_early():
    model = FileModel(make("layout"))
    assert code_of(model, 5) == SOLVED_CODE[5]  # across a comment at 3 spaces and blank lines
    assert code_of(model, 4) == SOLVED_CODE[4]  # a comment at 6 spaces inside the 8-space loop
    assert code_of(model, 7)[1].endswith("\\") and len(code_of(model, 7)) == 4  # the backslash's line stays
    assert code_of(model, 1)[-1] == "pass"
    black = FileModel(make("black_formatted"))
    assert not black.problems and black.shared == FileModel(SOLVED).shared
    assert code_of(black, 7)[1:6] == ["body_inverse_inertia = (", "body_rotation[None]",
                                      "@ body_origin_inverse_inertia[None]", "@ body_rotation[None].transpose()", ")"]
    assert given.note(black.text, black.regions) == ""  # black's reformatting is not an edit of the given code


def test_lost_reworded_or_deleted_markers_are_found_by_the_given_code_and_a_students_local_stays():
    model = FileModel(make("missing_marker_3"))
    assert not model.problems and code_of(model, 3) == SOLVED_CODE[3]
    assert code_of(model, 4) == SOLVED_CODE[4] and code_of(model, 2) == SOLVED_CODE[2]
    assert model.notes == ["TODO comments missing (TODO 3): found by its place among the handout's given code "
                           "(TODO 3: lines 173-174)"]
    bare = FileModel(make("no_markers"))  # every comment gone or reworded (issue 52: 0/90 before)
    assert not bare.problems and bare.notes == [
        "TODO comments missing (TODOs 1, 2, 3, 4, 5, 6, 7): found by their place among the handout's given code "
        "(TODO 1: lines 98-101; TODO 2: lines 148-151; TODO 3: lines 176-177; TODO 4: lines 182-185; "
        "TODO 5: lines 191-192; TODO 6: lines 196-198; TODO 7: lines 208-210)"]
    assert code_of(bare, 2) == ["is_in_contact = False"] + SOLVED_CODE[2]
    for k in (1, 3, 4, 5):
        assert code_of(bare, k) == SOLVED_CODE[k], k
    assert code_of(bare, 6)[-1] == "body_rotation_quaternion[None] += dt * d_q" and len(code_of(bare, 6)) == 3
    assert code_of(bare, 7)[0] == "body_angular_momentum[None] += dt * body_torque" and len(code_of(bare, 7)) == 3
    assert bare.shared == {1: "inertia", 3: "body_force", 4: "body_torque"}
    reference = bare.build().text  # the student's local, read by the given collision code, is kept
    assert "        is_in_contact = False\n        particle_force[i] = particle_mass * ti.Vector([gravity" in reference
    assert "particle_force[i] = particle_mass * gravity\n" not in reference
    assert FileModel(SOLVED).kept == {k: ([], []) for k in range(1, 8)}
    bare_text = make("no_markers")  # out of the handout's order: no place, so not graded rather than misread
    merged = FileModel(bare_text.replace(SOLVED_CODE[4][0], "pass").replace(SOLVED_CODE[4][1], "").replace(
        SOLVED_CODE[3][0], SOLVED_CODE[3][0] + "\n        " + SOLVED_CODE[4][1].replace("arm", "particle_vertices[i]")))
    assert sorted(merged.problems) == [3, 4] and sorted(merged.regions) == [1, 2, 5, 6, 7]
    five, six = "\n".join(f"    {line}" for line in SOLVED_CODE[5]), "    body_rotation_quaternion[None] += dt * d_q"
    swapped = FileModel(bare_text.replace(five + "\n", "").replace(six, six + "\n" + five))
    assert sorted(swapped.problems) == [5, 6] and "expected '# TODO 5: update the center" in swapped.problems[5]


def test_tab_indented_code_gets_reference_lines_indented_like_it():
    lines = SOLVED.splitlines(keepends=True)  # substep's code indented with tabs, its comments with spaces
    start = next(i for i, line in enumerate(lines) if line.startswith("def substep"))
    end = next(i for i, line in enumerate(lines) if line.startswith("# drawing"))
    for i in range(start + 1, end):
        body = lines[i].lstrip(" ")
        if body.strip() and not body.startswith("#"):
            lines[i] = "\t" * ((len(lines[i]) - len(body)) // 4) + body
    model = FileModel("".join(lines))
    compile(model.text, "student.py", "exec")  # the student's file is consistent
    for student in ((), (5,), (2, 6)):
        compile(model.build(student).text, "version.py", "exec")  # a TabError before (issue 52)


def test_an_error_in_a_version_names_the_students_file_and_line(tmp_path):
    from rigid.grading.original import runner
    from rigid.grading.original.variants import Variant

    variant = Variant("x = 1\nif x:\n        y = 2\n\ty = 3\n", [None, 185, 186, 187])
    path = tmp_path / "todos_5_10.py"
    try:
        compile(variant.text, str(path), "exec")
    except SyntaxError as err:
        runner.FILE_NAME[0] = "alice_rigid_body_dynamic.py"
        message = runner.describe(err, variant, path)
    assert message == ("TabError: inconsistent use of tabs and spaces in indentation "
                       "(alice_rigid_body_dynamic.py, line 187)")


def test_a_syntax_error_costs_only_its_todo():
    broken = FileModel(make("syntax_error_todo4"))
    assert not broken.problems and code_of(broken, 5) == SOLVED_CODE[5]
    from rigid.grading.original.child import _syntax_error
    assert "syntax error at line 184" in _syntax_error(broken, 4) and not _syntax_error(broken, 5)
    text = SOLVED.replace(SOLVED_CODE[4][1], SOLVED_CODE[4][1][:-1])  # an unclosed bracket in TODO 4
    assert code_of(FileModel(text), 5) == SOLVED_CODE[5]  # stays there
    with pytest.raises(RegionError, match="syntax error at line 2"):
        FileModel("import taichi as ti\nx = (\n" + SOLVED)  # outside the TODOs: nothing can run
