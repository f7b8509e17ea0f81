"""Submissions in the course's original handout format, for the grader's tests.

tests/data/original_handout/solved.py and unsolved.py were written for these
tests in the shape of the course's assignment_3/rigid_body_dynamic.py (2024,
github.com/Shimingyi/COMP3360_Data_Driven_Animation): the same given statements
in the same order, ``body_force`` and ``body_torque`` declared by the given code
before the loops that hold TODOs 3 and 4, the ``pass`` lines, the hint comments
(TODO 5's velocity first, TODO 7's local ``body_inverse_inertia``, as changed in
April 2023), ``sphere.obj`` read from the working folder and the window loop.
Every other file here is made from them by ``make(name)``, replacing lines that
must each occur exactly once, so a change of the fixtures that breaks a variant
fails loudly instead of testing something else.

WRONG[name] = {TODO that must lose its points: words of its message}; every
other TODO of that file must pass. FULL: files that must score full marks
(with NOTES[name]: words one of the file's notes must contain).
"""
from pathlib import Path

FOLDER = Path(__file__).resolve().parent / "data" / "original_handout"
SOLVED = (FOLDER / "solved.py").read_text()
FILES = ("solved", "unsolved", "black_formatted")  # black_formatted: solved.py after black 26.10

L1 = "        inertia += particle_mass * (r.dot(r) * ti.Matrix.identity(float, 3) - r.outer_product(r))\n"
L2 = "        particle_force[i] = particle_mass * gravity\n"
L3 = "        body_force += particle_force[i]\n"
L4 = "        body_torque += ti.math.cross(arm, particle_force[i])\n"
L5V = "    body_velocity[None] += dt * body_force / body_mass[None]\n"
L5X = "    body_cm_position[None] += dt * body_velocity[None]\n"
L6 = "    d_q = 0.5 * quaternion_multiplication(ti.Vector([0, w[0], w[1], w[2]]), body_rotation_quaternion[None])\n"
L7L = "    body_angular_momentum[None] += dt * body_torque\n"
L7I = ("    body_inverse_inertia = body_rotation[None] @ body_origin_inverse_inertia[None] @ "
       "body_rotation[None].transpose()\n")
M = {k: line for k, line in (  # the marker lines of solved.py
    (1, "    # TODO 1: Compute the inertia tensor of the body\n"), (2, "        # TODO 2: gravity\n"),
    (3, "        # TODO 3: compute the force for rigid body\n"), (4, "        # TODO 4: compute the torque for rigid body\n"),
    (5, "    # TODO 5: update the center of mass position and velocity\n"),
    (6, "    # TODO 6: update the rotation quaternion\n"),
    (7, "    # TODO 7: update, the angular momentum, inertia tensor and angular velocity\n"))}
WINDOW = SOLVED[SOLVED.index("window = ti.ui.Window("):]
WALL_LEFT = "            f_collision = collision_stiffness * (-1 - particle_vertices[i][0])\n"
AFTER_WALLS = "\n    # computer the force for rigid body\n"
WALL_FLOOR = ("            f_collision = collision_stiffness * (-1 - particle_vertices[i][1])\n"
              "            particle_force[i] += ti.Vector([0, f_collision, 0])\n")

# name: (file it starts from, {text of that file: replacement})
SUBSTITUTIONS = {
    # one mistake each, in one TODO: only that TODO loses its points
    "t1_no_mass": ("solved", {L1: L1.replace("particle_mass * (", "(")}),
    "t2_no_mass": ("solved", {L2: L2.replace("particle_mass * gravity", "gravity")}),
    "t3_sign": ("solved", {L3: L3.replace("+=", "-=")}),
    "t4_swapped_cross": ("solved", {L4: L4.replace("cross(arm, particle_force[i])", "cross(particle_force[i], arm)")}),
    "t5_no_dt": ("solved", {L5X: L5X.replace("dt * ", "")}),
    "t6_no_half": ("solved", {L6: L6.replace("0.5 * ", "")}),
    "t7_order": ("solved", {L7I: "    body_inverse_inertia = body_rotation[None].transpose() @ "
                                 "body_origin_inverse_inertia[None] @ body_rotation[None]\n"}),
    # mistakes the table of known mistakes does not list: a generic message naming what differs
    "t1_outer_plus_mass_identity": ("solved", {L1: "        inertia += particle_mass * r.outer_product(r) + "
                                                   "particle_mass * ti.Matrix.identity(float, 3)\n"}),
    "t3_extra_mass": ("solved", {L3: "        body_force += particle_mass * particle_force[i]\n"}),
    "t7_drops_old_L": ("solved", {L7L: "    body_angular_momentum[None] = dt * body_torque\n"}),
    "t7_unrotated": ("solved", {L7I: "    body_inverse_inertia = body_origin_inverse_inertia[None]\n"}),
    # what students hand in: every TODO right, written their way
    "marker_variants": ("solved", {
        M[1]: "    # TODO: 1: Compute the inertia tensor of the body\n", M[2]: "        #TODO 2 gravity\n",
        M[3]: "        # todo 3: compute the force for rigid body\n", M[5]: "    # TODO #5 - update the center of mass\n",
        M[6]: "    ## TODO(6): update the rotation quaternion\n",
        M[7]: "    # TODO 7. update, the angular momentum, inertia tensor and angular velocity\n",
        # TODO 4's marker moved above the given declaration and its loop
        "    body_torque = ti.Vector([0.0, 0.0, 0.0])\n    for i in ti.grouped(particle_vertices):\n" + M[4]:
            M[4].replace("        ", "    ") + "    body_torque = ti.Vector([0.0, 0.0, 0.0])\n"
            "    for i in ti.grouped(particle_vertices):\n"}),
    "layout": ("solved", {  # odd comment indentation, blank lines, a backslash, the pass kept
        L1: L1 + "        pass\n",
        L5V + L5X: L5V + "\n   # the position moves with the new velocity\n\n" + L5X,
        L4: "      # torque about the centre of mass\n" + L4,
        L7I: "    body_inverse_inertia = body_rotation[None] @ body_origin_inverse_inertia[None] \\\n"
             "        @ body_rotation[None].transpose()\n"}),
    "bonus_inside": ("solved", {  # damping inside TODOs 2 and 5 and after TODO 4's loop, friction at the floor
        "dt = 1e-3\n": "dt = 1e-3\nair_drag = 0.02\nlinear_damping = 0.5\n",
        L2: "        particle_force[i] = particle_mass * gravity - air_drag * particle_velocities[i]\n",
        L5V: L5V + "    body_velocity[None] -= dt * linear_damping * body_velocity[None]\n",
        "    # update the rigid body\n": "    # damping of the whole body (bonus)\n"
                                       "    body_force -= 1e-3 * velocity_damping_stiffness * body_velocity[None]\n\n"
                                       "    # update the rigid body\n",
        WALL_FLOOR: WALL_FLOOR + "            v_t = particle_velocities[i] - ti.Vector([0.0, particle_velocities[i][1], 0.0])\n"
                                 "            particle_force[i] -= friction_stiffness * f_collision * v_t\n"}),
    "given_edits": ("solved", {  # edits of the given code cost nothing; the wall's sign error is listed first
        "ti.init(arch=ti.cpu, debug=True)": "ti.init(arch=ti.cpu, debug=False)",
        WALL_LEFT: WALL_LEFT.replace("(-1 - particle_vertices[i][0])", "(particle_vertices[i][0] + 1)"),
        "substeps = int(1 / 60 // dt)": "substeps = int(1 / 120 // dt)",
        '(1024, 1024),\n                      vsync=True)': "(640, 640), vsync=True)",
        "        particle_velocities[i] = body_velocity[None] + ti.math.cross(body_angular_velocity[None], ri)\n":
            "        particle_velocities[i] = body_velocity[None] + body_angular_velocity[None].cross(ri)\n"}),
    "missing_marker_3": ("solved", {M[3]: ""}),
    # unseen students' shapes (issue 52): every TODO comment deleted or reworded, a local of the student's
    # under TODO 2 that the given collision code reads; all seven found by their place in the given code
    "no_markers": ("solved", {
        **{M[k]: "" for k in (1, 3, 4, 6, 7)}, M[2]: "        # gravity on each particle\n",
        M[5]: "    # Task: move the centre of mass\n",
        L2: "        is_in_contact = False\n" + L2, WALL_FLOOR: WALL_FLOOR + "            is_in_contact = True\n",
        AFTER_WALLS: "        if is_in_contact:\n            particle_force[i] += 0.0 * particle_velocities[i]\n"
                     + AFTER_WALLS}),
    "t2_accumulates": ("solved", {L2: L2.replace("particle_force[i] =", "particle_force[i] +=")}),
    "syntax_error_todo4": ("solved", {L4: L4.replace("ti.math.cross(arm,", "ti.math..cross(arm,")}),
    # the grader's older fixtures, now in the handout's shape: other parameters, a mesh the file does not
    # include, its own local name for the total force, position-first TODO 5, friction outside the TODOs
    "bonus_friction": ("solved", {
        "particle_mass = 1\n": "particle_mass = 0.5\n",
        "initial_velocity = ti.Vector([0.0, 0.0, 0.0])": "initial_velocity = ti.Vector([1.0, 0.0, -0.5])",
        "initial_angular_velocity = ti.Vector([0.0, 0, 0.0])": "initial_angular_velocity = ti.Vector([0.0, 3.0, 1.0])",
        'file_path = "sphere.obj"': 'file_path = "my_bunny.obj"',
        "    body_force = ti.Vector([0.0, 0.0, 0.0])\n": "    total_force = ti.Vector([0.0, 0.0, 0.0])\n",
        L3: "        total_force += particle_force[i]\n",
        L5V + L5X: L5X + L5V.replace("body_force", "total_force"),
        WALL_FLOOR: WALL_FLOOR + "            v_t = particle_velocities[i] - ti.Vector([0.0, particle_velocities[i][1], 0.0])\n"
                                 "            particle_force[i] -= friction_stiffness * f_collision * v_t\n"}),
    # TODOs 2, 4, 6 wrong, ti.init twice, a legacy ti.GUI loop that never checks gui.running; the handout's
    # particle_mass = 1 hides TODO 2's slip in the file's own run (not in the perturbed one)
    "mistakes_a": ("solved", {
        "ti.init(arch=ti.cpu, debug=True)": "ti.init(arch=ti.cpu, debug=True)\nti.init(arch=ti.cpu)",
        L2: L2.replace("particle_mass * gravity", "gravity"),
        L4: L4.replace("cross(arm, particle_force[i])", "cross(particle_force[i], arm)"),
        L6: L6.replace("0.5 * ", ""),
        WINDOW: "gui = ti.GUI('Rigid Body Simulation', (512, 512))\nsubsteps = int(1 / 60 // dt)\n\nwhile True:\n"
                "    for i in range(substeps):\n        substep()\n"
                "    gui.circles(particle_vertices.to_numpy()[:, :2] * 0.4 + 0.5, radius=2)\n    gui.show()\n"}),
    "mistakes_b": ("solved", {  # TODOs 1, 3, 5, 7 wrong; it reads its own mesh, dan_brick.obj
        L1: L1.replace("particle_mass * (", "("),
        L3: L3.replace("+=", "-="),
        L5X: L5X.replace("dt * ", ""),
        L7I: "    body_inverse_inertia = body_rotation[None].transpose() @ body_origin_inverse_inertia[None] @ "
             "body_rotation[None]\n",
        'file_path = "sphere.obj"': 'file_path = "dan_brick.obj"'}),
    # bonus_inside's terms in bonus_friction's file (its own name total_force, TODO 5 position-first), in
    # black_formatted's layout (black's lines in TODOs 1, 6, 7 and in the given code): one file for all three
    "bonus_inside_friction": ("black_formatted", {
        "particle_mass = 1\n": "particle_mass = 0.5\n",
        "initial_velocity = ti.Vector([0.0, 0.0, 0.0])": "initial_velocity = ti.Vector([1.0, 0.0, -0.5])",
        "initial_angular_velocity = ti.Vector([0.0, 0, 0.0])": "initial_angular_velocity = ti.Vector([0.0, 3.0, 1.0])",
        'file_path = "sphere.obj"': 'file_path = "my_bunny.obj"',
        "dt = 1e-3\n": "dt = 1e-3\nair_drag = 0.02\nlinear_damping = 0.5\n",
        L2: "        particle_force[i] = particle_mass * gravity - air_drag * particle_velocities[i]\n",
        "    body_force = ti.Vector([0.0, 0.0, 0.0])\n": "    total_force = ti.Vector([0.0, 0.0, 0.0])\n",
        L3: "        total_force += particle_force[i]\n",
        L5V + L5X: L5X + L5V.replace("body_force", "total_force")
                   + "    body_velocity[None] -= dt * linear_damping * body_velocity[None]\n",
        "    # update the rigid body\n": "    # damping of the whole body (bonus)\n"
                                       "    total_force -= 1e-3 * velocity_damping_stiffness * body_velocity[None]\n\n"
                                       "    # update the rigid body\n",
        WALL_FLOOR: WALL_FLOOR + "            v_t = particle_velocities[i] - ti.Vector([0.0, particle_velocities[i][1], 0.0])\n"
                                 "            particle_force[i] -= friction_stiffness * f_collision * v_t\n"}),
    # TODO 6 loops forever (the grader's time limit stops it; the other TODOs are graded in a fresh process)
    "hang_in_todo6": ("solved", {
        "    body_rotation_quaternion[None] += dt * d_q\n":
            "    while body_rotation_quaternion[None].norm() > 0.5:\n        body_rotation_quaternion[None] *= 1.0\n"}),
}
WRONG = {
    "t1_no_mass": {1: ["mass"]}, "t2_no_mass": {2: ["mass"]}, "t3_sign": {3: ["sign"]},
    "t4_swapped_cross": {4: ["cross product"]}, "t5_no_dt": {5: ["does not depend on Δt"]},
    "t6_no_half": {6: ["twice the expected rate"]}, "t7_order": {7: ["order"]},
    "t1_outer_plus_mass_identity": {1: ["the sign of the r0 r0ᵀ term", "extra identity term (the body's mass M"]},
    "t3_extra_mass": {3: ["factor of the mass"]},
    "t7_drops_old_L": {7: ["lacks the old L"]},
    "t7_unrotated": {7: ["body-frame I0⁻¹"]},
    "t2_accumulates": {2: ["the force is accumulated across substeps", "assign, don't add"]},
    "syntax_error_todo4": {4: ["syntax error at line"]},
    "hang_in_todo6": {6: ["the code under '# TODO 6:' did not finish within"]},  # the time limit (--timeout)
    "mistakes_a": {2: ["mass"], 4: ["cross product"], 6: ["twice the expected rate"]},
    "mistakes_b": {1: ["mass"], 3: ["sign"], 5: ["does not depend on Δt"], 7: ["order"]},
}
FULL = ("solved", "marker_variants", "layout", "black_formatted", "bonus_inside", "given_edits", "bonus_friction",
        "missing_marker_3", "no_markers", "bonus_inside_friction")
NOTES = {
    "bonus_inside": ["bonus", "air_drag", "linear_damping", "velocity_damping_stiffness"],
    "given_edits": ["given code", "substeps", "edits of the given code (they cost nothing: the grader runs them in "
                    "every version it compares): in the simulation (they change the physics): line 158: f_collision"],
    "missing_marker_3": ["TODO comments missing (TODO", "found by", "TODO 3: lines"],
    "no_markers": ["TODO comments missing (TODOs 1, 2, 3, 4, 5, 6, 7)"],
    "bonus_friction": ["my_bunny.obj"],
}
NOTES["bonus_inside_friction"] = NOTES["bonus_inside"] + NOTES["bonus_friction"]
# Files that carry several of the variants above at once, in TODOs (or given code) of their own, as
# mistakes_a and mistakes_b do: each part's TODO must lose (or keep) its points with the same words,
# and the file must carry every part's notes. A batch grades one such file where it would grade each
# part (an original-format file costs ~6 CPU-s to grade, whatever it holds).
# (The given-code note lists six edited lines, then "and N more": given_edits goes with mistakes in
# TODOs, not with bonus_inside, whose floor friction is given code too.)
COMBINED = {
    "unknown_mistakes_given_edits": ("t1_outer_plus_mass_identity", "t2_accumulates", "t3_extra_mass", "t7_drops_old_L",
                                     "given_edits"),
    "marker_syntax_unrotated": ("missing_marker_3", "no_markers", "syntax_error_todo4", "t7_unrotated"),
    "unknown_mistakes_edits_hang6": ("unknown_mistakes_given_edits", "hang_in_todo6"),  # a combined file as a part
    "mistakes_ab": ("mistakes_a", "mistakes_b"),  # every TODO wrong, each its own way
}
for _name, _parts in COMBINED.items():
    SUBSTITUTIONS[_name] = ("solved", {old: new for part in _parts for old, new in SUBSTITUTIONS[part][1].items()})
    WRONG[_name] = {k: words for part in _parts for k, words in WRONG.get(part, {}).items()}
    if any(part in NOTES for part in _parts):
        NOTES[_name] = [words for part in _parts for words in NOTES.get(part, [])]


def make(name: str) -> str:
    if name in FILES:
        return (FOLDER / f"{name}.py").read_text()
    base, replacements = SUBSTITUTIONS[name]
    text = make(base)
    for old, new in replacements.items():
        assert text.count(old) == 1, f"{base}.py: text not found exactly once: {old!r}"
        text = text.replace(old, new)
    return text
