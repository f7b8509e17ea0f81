"""Submissions for the grader's tests, made from the solution by replacing lines of one TODO.

``make(name)`` returns the text of variant ``name``. Each substitution names
a line of the solution exactly, so a change of the solution that breaks a
variant fails loudly here rather than testing something else.
WRONG[name] = (TODO that must lose its points, words its message must contain);
COMBINED[file] = the WRONG variants one file holds (each on its own TODO).
"""
from pathlib import Path

SOLUTION = (Path(__file__).resolve().parent.parent / "rigid_body_dynamic.py").read_text()

L_INERTIA = "inertia = particle_mass * (r0.dot(r0) * ti.Matrix.identity(float, 3) - r0.outer_product(r0))"
L_GRAVITY = "force = particle_mass * gravity"
L_TERM = "term = particle_force"
L_R, L_TORQUE = "r = rotation @ r0", "term = r.cross(particle_force)"
L_X, L_P = "new_position = position + dt * momentum / mass", "new_momentum = momentum + dt * force"
L_DQ = "dq = 0.5 * quaternion_multiplication(ti.Vector([0.0, omega[0], omega[1], omega[2]]), q)"
L_Q, L_NORM = "new_q = q + dt * dq", "new_q = new_q / new_q.norm()"
L_L = "new_L = angular_momentum + dt * torque"
L_IINV = "inertia_inv = rotation @ inertia_body_inv @ rotation.transpose()"
L_OMEGA = "omega = inertia_inv @ new_L"

SUBSTITUTIONS = {
    # wrong: exactly one TODO
    "t1_no_mass": {L_INERTIA: "inertia = r0.dot(r0) * ti.Matrix.identity(float, 3) - r0.outer_product(r0)"},
    "t1_no_identity": {L_INERTIA: "inertia = particle_mass * (r0.dot(r0) - r0.outer_product(r0))"},
    "t2_no_mass": {L_GRAVITY: "force = gravity"},
    "t2_sign": {L_GRAVITY: "force = -particle_mass * gravity"},
    "t3_sign": {L_TERM: "term = -particle_force"},
    "t3_drops_z": {L_TERM: "term = ti.Vector([particle_force[0], particle_force[1], 0.0])"},
    "t4_swapped_cross": {L_TORQUE: "term = particle_force.cross(r)"},
    "t4_unrotated": {L_R: "r = r0"},
    "t4_syntax_error": {L_TORQUE: "term = r..cross(particle_force)"},  # not in WRONG: --check cannot import it
    "t5_no_dt": {L_X: "new_position = position + momentum / mass"},
    "t5_force_over_mass": {L_P: "new_momentum = momentum + dt * force / mass"},
    "t6_no_half": {L_DQ: L_DQ.replace("0.5 * ", "")},
    "t6_no_renormalisation": {L_NORM: ""},
    "t7_order": {L_IINV: "inertia_inv = rotation.transpose() @ inertia_body_inv @ rotation"},
    "t7_old_L": {L_OMEGA: "omega = inertia_inv @ angular_momentum"},
    # right, written differently
    "ok_alt_a": {
        L_R: "r = particle_position - body_position",
        L_X: "new_momentum = momentum + dt * force\n    new_position = position + dt * new_momentum / mass",
        L_P: "",
        L_DQ: "w = omega\n    big_omega = ti.Matrix([[0.0, -w[0], -w[1], -w[2]], [w[0], 0.0, -w[2], w[1]],\n"
              "                           [w[1], w[2], 0.0, -w[0]], [w[2], -w[1], w[0], 0.0]])",
        L_Q: "new_q = q + 0.5 * dt * (big_omega @ q)",
        L_NORM: "new_q = new_q.normalized()",
        L_IINV: "inertia_inv = (rotation @ inertia_body_inv) @ rotation.transpose()",
        L_OMEGA: "omega = rotation @ (inertia_body_inv @ (rotation.transpose() @ new_L))",
    },
    "ok_alt_b": {
        L_INERTIA: "x, y, z = r0[0], r0[1], r0[2]\n    inertia = particle_mass * ti.Matrix([\n"
                   "        [y * y + z * z, -x * y, -x * z], [-x * y, x * x + z * z, -y * z],\n"
                   "        [-x * z, -y * z, x * x + y * y]])",
        L_GRAVITY: "force = ti.Vector([gravity[0], gravity[1], gravity[2]]) * particle_mass",
        L_TERM: "term = particle_force + ti.Vector.zero(float, 3)",
        L_R: "",
        L_TORQUE: "term = ti.math.cross(rotation @ r0, particle_force)",
        L_X: "v = momentum / mass\n    new_position = position + v * dt",
        L_P: "new_momentum = force * dt + momentum",
        L_DQ: "",
        L_Q: "new_q = q + dt * 0.5 * quaternion_multiplication(ti.Vector([0.0, omega[0], omega[1], omega[2]]), q)",
        L_NORM: "new_q = new_q / ti.sqrt(new_q.dot(new_q))",
        L_L: "new_L = dt * torque + angular_momentum",
        L_IINV: "rt = rotation.transpose()\n    inertia_inv = rotation @ (inertia_body_inv @ rt)",
    },
}

WRONG = {
    "t1_no_mass": (1, ["mass"]),
    "t1_no_identity": (1, ["identity"]),
    "t2_no_mass": (2, ["mass"]),
    "t2_sign": (2, ["against gravity"]),
    "t3_sign": (3, ["sign"]),
    "t3_drops_z": (3, ["z component"]),
    "t4_swapped_cross": (4, ["cross product"]),
    "t4_unrotated": (4, ["without rotating"]),
    "t5_no_dt": (5, ["position", "does not depend on Δt"]),
    "t5_force_over_mass": (5, ["momentum", "divides the force by the mass"]),
    "t6_no_half": (6, ["twice the expected rate"]),
    "t6_no_renormalisation": (6, ["not renormalised"]),
    "t7_order": (7, ["R I0⁻¹ Rᵀ", "order"]),
    "t7_old_L": (7, ["old L"]),
}
CORRECT = ("ok_alt_a", "ok_alt_b")
# The wrong variants graded end to end (test_grading_batch.py), several to a file: one mistake in
# each of several TODOs, with right TODOs between them, each TODO checked on its own, so every
# mistake must still cost exactly its TODO with its message, and the right TODOs keep full marks.
# A graded file costs ~2 CPU-s (it compiles the engine with its units), so 14 one-mistake files
# cost 11 more gradings than these 3 and show no more.
COMBINED = {
    "mistakes_1357_a": ("t1_no_mass", "t3_sign", "t5_no_dt", "t7_order"),
    "mistakes_12346": ("t1_no_identity", "t2_no_mass", "t3_drops_z", "t4_swapped_cross", "t6_no_half"),
    "mistakes_24567": ("t2_sign", "t4_unrotated", "t5_force_over_mass", "t6_no_renormalisation", "t7_old_L"),
}
assert sorted(n for parts in COMBINED.values() for n in parts) == sorted(WRONG)
assert all(len({WRONG[n][0] for n in parts}) == len(parts) for parts in COMBINED.values())  # a TODO each

# Whole-file additions: processes that misbehave (appended after the solution).
APPENDED = {
    "crash_at_import": "\nraise RuntimeError('student code is broken')\n",
    "exit_at_import": "\nimport sys\nsys.exit(3)\n",
    # Waits forever without burning CPU (the stage timer treats a busy loop the same; see hang_in_todo6).
    "hang_at_import": "\nimport time\nwhile True:\n    time.sleep(1)\n",
    "memory_hog": "\nhog = bytearray(64 * 1024 ** 3)\n",
    # 20 MB of prints, and files written to HOME and to the working folder: harmless, full marks.
    "flood_and_writes": "\nfrom pathlib import Path\n(Path.home() / 'grader_probe.txt').write_text('hi')\n"
                        "Path('relative_probe.txt').write_text('hi')\n"
                        "for _ in range(20000):\n    print('x' * 1000)\n",
}
# TODO 6 loops forever at run time (a realistic "while |q| != 1" slip).
HANG_IN_TODO6 = {L_NORM: "while new_q.norm() > 0.5:\n        new_q = new_q * 1.0"}
# One file for what costs a file only its own points, or nothing: the hang in TODO 6, a syntax error in
# TODO 4 (--check cannot import it), and flood_and_writes at import (each child of the file does it).
HANG_SYNTAX_FLOOD = "hang6_syntax4_flood"


def substitute(replacements: dict) -> str:
    """Replace whole solution lines (matched stripped, each exactly once) by new text ("" deletes)."""
    out, seen = [], []
    for line in SOLUTION.splitlines(keepends=True):
        key = line.strip()
        if key in replacements:
            seen.append(key)
            new = replacements[key]
            indent = line[:len(line) - len(line.lstrip())]
            out.append(f"{indent}{new}\n" if new else "")
        else:
            out.append(line)
    for key in replacements:
        assert seen.count(key) == 1, f"solution line not found exactly once: {key}"
    return "".join(out)


def make(name: str) -> str:
    if name in COMBINED:
        return substitute({line: text for part in COMBINED[name] for line, text in SUBSTITUTIONS[part].items()})
    if name in APPENDED:
        return SOLUTION + APPENDED[name]
    if name == "hang_in_todo6":
        return substitute(HANG_IN_TODO6)
    if name == HANG_SYNTAX_FLOOD:
        return substitute({**HANG_IN_TODO6, **SUBSTITUTIONS["t4_syntax_error"]}) + APPENDED["flood_and_writes"]
    return substitute(SUBSTITUTIONS[name])
