"""The shape of the course's original handout, as regions.py reads it: tables only, no logic.

- MARKER, END_MARKER  a ``# TODO k: title`` line in any reasonable spelling, and an ``# END TODO`` line
- TITLES        the handout's title of each TODO (picks the marker when a number appears on two comment lines)
- EXPECTED      where the handout has each marker (the message when one is missing)
- SHARED        the default names of the locals TODOs 1, 3 and 4 hand on to the code after them
- GIVEN_WORDS   first words of a comment that starts given code ("# Collision force ...", "# update ...")
- JOB           what each TODO's code does, to tell a student's own comment from the given code's
- WRITES        a code line that does TODO 5, 6 or 7's job (ends an earlier region when that marker is missing)
- ANCHORS       given code that follows each TODO in the handout
- NORMALISE     the quaternion's normalisation after TODO 6's update

Imports nothing from rigid.
"""
import re

MARKER = re.compile(r"^(?P<indent>[ \t]*)#+\s*TODO\s*[:#.(\[-]?\s*(?P<k>[1-7])(?![0-9]|\.[0-9])\s*[:.)\]-]?\s*"
                    r"(?P<title>.*)$", re.IGNORECASE)
END_MARKER = re.compile(r"^\s*#\s*END\s+TODO", re.IGNORECASE)
GIVEN_WORDS = ("collision", "comput", "update", "normali", "given", "render", "draw")
SHARED = {1: "inertia", 3: "body_force", 4: "body_torque"}  # default names of the locals handed on
TITLES = {  # the handout's titles, to pick the marker when a TODO's number appears on two comment lines
    1: "Compute the inertia tensor of the body", 2: "gravity", 3: "compute the force for rigid body",
    4: "compute the torque for rigid body", 5: "update the center of mass position and velocity",
    6: "update the rotation quaternion", 7: "update, the angular momentum, inertia tensor and angular velocity",
}
EXPECTED = {  # where the handout has each marker, for the message when one is missing
    1: "in initial(), after `inertia = ti.Matrix(...)`",
    2: "in substep(), first in the loop over the particles, before the collision force",
    3: "in substep(), inside the loop after `body_force = ti.Vector([0.0, 0.0, 0.0])`",
    4: "in substep(), inside the loop after `body_torque = ti.Vector([0.0, 0.0, 0.0])`",
    5: "in substep(), after the torque loop",
    6: "in substep(), before `# normalize the quaternion to avoid numerical error`",
    7: "in substep(), after `body_rotation[None] = quaternion_to_matrix(...)`, before `# update the particles`",
}
JOB = {  # what the code of each TODO does, to tell a student's comment from the given code's
    1: r"outer_product|particle_origin_vertices|particle_vertices",
    2: r"\bgravity\b",
    3: r"particle_force\s*\[",
    4: r"cross",
    5: r"\b(body_cm_position|body_velocity)\s*\[\s*None\s*\]\s*[-+*/]?=(?!=)",
    6: r"\bdt\b",
    7: r"\b(body_angular_momentum|body_angular_velocity)\s*\[\s*None\s*\]\s*[-+*/]?=(?!=)",
}
WRITES = {  # a code line that does TODO k's job (ends an earlier region when TODO k's marker is missing)
    5: re.compile(r"^(body_cm_position|body_velocity)\s*\[\s*None\s*\]\s*[-+*/]?=(?!=)"),
    6: re.compile(r"^body_rotation_quaternion\s*\[\s*None\s*\]\s*[-+*/]?=(?!=)"),
    7: re.compile(r"^(body_angular_momentum|body_angular_velocity)\s*\[\s*None\s*\]\s*[-+*/]?=(?!=)"),
}
ANCHORS = {  # given code that follows each TODO in the handout (a code line no more indented than the marker)
    1: re.compile(r"^(body_origin_inverse_inertia|body_angular_momentum|body_velocity)\s*\[|^body_force\s*=(?!=)"
                  r"|^body_torque\s*=(?!=)"),
    2: re.compile(r"^if\s+particle_vertices\s*\[|^body_force\s*=(?!=)|^body_torque\s*=(?!=)"),
    3: re.compile(r"^body_torque\s*=(?!=)"),
    6: re.compile(r"^body_rotation\s*\[\s*None\s*\]\s*=(?!=)"),
    7: re.compile(r"^for\b.*\bparticle_vertices\b|^particle_vertices\s*\["),
}
NORMALISE = re.compile(r"^body_rotation_quaternion\s*\[\s*None\s*\]\s*(/=|=).*\b(norm|normalized)\s*\(")
