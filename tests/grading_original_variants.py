"""Submissions in the course's original handout format, for the grader's tests.

The files under tests/data/original_handout/ were written for these tests from
the description in issue 14 (the course's own file is not in this repository):
solved.py, unsolved.py (as handed out), bonus_friction.py (solved, with other
parameters, a mesh it does not include, its own local names, velocity-first
TODO 5 and bonus damping and friction outside the TODOs) and
window_and_double_init.py (solved; ti.init twice, legacy ti.GUI, a loop that
never checks gui.running). ``make(name)`` also builds variants of them with
mistakes; WRONG[name] = {TODO that must lose its points: words of its message}.
"""
from pathlib import Path

FOLDER = Path(__file__).resolve().parent / "data" / "original_handout"
SOLVED = (FOLDER / "solved.py").read_text()
FILES = ("solved", "unsolved", "bonus_friction", "window_and_double_init")

# name: (file it starts from, {line of that file: replacement})
SUBSTITUTIONS = {
    # TODOs 2, 4, 6 wrong, in the file with two ti.init calls and a ti.GUI loop; the handout's
    # particle_mass = 1 hides TODO 2's slip in the file's own run (not in the perturbed one)
    "mistakes_a": ("window_and_double_init", {
        "particle_force[i] = particle_mass * gravity": "particle_force[i] = gravity",
        "body_torque += arm.cross(particle_force[i])": "body_torque += particle_force[i].cross(arm)",
        "body_rotation_quaternion[None] += 0.5 * dt * quaternion_multiplication(omega_q, body_rotation_quaternion[None])":
            "body_rotation_quaternion[None] += dt * quaternion_multiplication(omega_q, body_rotation_quaternion[None])",
    }),
    "mistakes_b": ("solved", {  # TODOs 1, 3, 5, 7 wrong; it reads its own mesh, dan_brick.obj
        "inertia += particle_mass * (r.dot(r) * ti.Matrix.identity(float, 3) - r.outer_product(r))":
            "inertia += r.dot(r) * ti.Matrix.identity(float, 3) - r.outer_product(r)",
        "body_force += particle_force[i]": "body_force -= particle_force[i]",
        "body_cm_position[None] += dt * body_velocity[None]": "body_cm_position[None] += body_velocity[None]",
        "world_inverse_inertia = body_rotation[None] @ body_origin_inverse_inertia[None] @ body_rotation[None].transpose()":
            "world_inverse_inertia = body_rotation[None].transpose() @ body_origin_inverse_inertia[None] @ body_rotation[None]",
        'read_obj_file("sphere.obj", scale=0.3)': 'read_obj_file("dan_brick.obj", scale=0.3)',
    }),
    # TODO 6 loops forever (the grader's time limit stops it; the other TODOs are graded in a fresh process)
    "hang_in_todo6": ("solved", {
        "body_rotation_quaternion[None] += 0.5 * dt * quaternion_multiplication(omega_q, body_rotation_quaternion[None])":
            "while body_rotation_quaternion[None].norm() > 0.5:\n        body_rotation_quaternion[None] *= 1.0",
    }),
}
WRONG = {
    "mistakes_a": {2: ["mass"], 4: ["cross product"], 6: ["twice the expected rate"]},
    "mistakes_b": {1: ["mass"], 3: ["sign"], 5: ["does not depend on Δt"], 7: ["order"]},
}


def make(name: str) -> str:
    if name in FILES:
        return (FOLDER / f"{name}.py").read_text()
    base, replacements = SUBSTITUTIONS[name]
    text = make(base)
    for old, new in replacements.items():
        assert text.count(old) == 1, f"{base}.py line not found exactly once: {old}"
        text = text.replace(old, new)
    return text
