"""The project's reference code of each TODO, written for the original handout's names.

``lines_for(k, region, shared, form)`` returns the lines (indented for the
region) that replace a student's TODO k when another TODO is graded, or every
TODO for the reference run. They use only the handout's global fields and
parameters, plus the locals handed between TODOs, whose names come from the
student's own file (``shared``: {1: inertia, 3: total force, 4: total torque}).
The quaternion product is written out, so a student's edit of the given helper
functions cannot change the reference. Lever arms are ``particle_vertices[i] -
body_cm_position[None]``: in the handout ``particle_origin_vertices`` holds the
mesh's original world positions (offsets are taken from ``body_origin_cm_position``
by the given particle update), and p − x = R r0 holds after every substep. The particle loop is the enclosing given
loop when the TODO sits in one, else a loop of its own. Locals of these lines
start with ``ref_`` and differ between TODOs, so two of them never clash.

TODO 5 comes in both orders accepted today (alternatives.py): "position-first"
(explicit Euler, the slides) and "velocity-first" (semi-implicit).
"""
DECLARE = {1: "ti.Matrix.zero(float, 3, 3)", 3: "ti.Vector([0.0, 0.0, 0.0])", 4: "ti.Vector([0.0, 0.0, 0.0])"}


def _per_particle(k: int) -> list:
    if k == 1:
        return ["ref1_r = particle_vertices[{i}] - body_cm_position[None]",
                "{I} += particle_mass * (ref1_r.dot(ref1_r) * ti.Matrix.identity(float, 3) "
                "- ref1_r.outer_product(ref1_r))"]
    if k == 2:
        return ["particle_force[{i}] = particle_mass * ti.Vector([gravity[0], gravity[1], gravity[2]])"]
    if k == 3:
        return ["{F} += particle_force[{i}]"]
    return ["ref4_arm = particle_vertices[{i}] - body_cm_position[None]",
            "{T} += ref4_arm.cross(particle_force[{i}])"]


def _body(k: int, form: str) -> list:
    if k == 5:
        x = "body_cm_position[None] += dt * body_velocity[None]"
        v = "body_velocity[None] += dt * {F} / body_mass[None]"
        return [x, v] if form == "position-first" else [v, x]
    if k == 6:
        return ["ref6_w = body_angular_velocity[None]",
                "ref6_q = body_rotation_quaternion[None]",
                "body_rotation_quaternion[None] = ref6_q + 0.5 * dt * ti.Vector([",
                "    -ref6_w[0] * ref6_q[1] - ref6_w[1] * ref6_q[2] - ref6_w[2] * ref6_q[3],",
                "    ref6_q[0] * ref6_w[0] + ref6_w[1] * ref6_q[3] - ref6_w[2] * ref6_q[2],",
                "    ref6_q[0] * ref6_w[1] + ref6_w[2] * ref6_q[1] - ref6_w[0] * ref6_q[3],",
                "    ref6_q[0] * ref6_w[2] + ref6_w[0] * ref6_q[2] - ref6_w[1] * ref6_q[1]])"]
    return ["body_angular_momentum[None] += dt * {T}",
            "ref7_R = body_rotation[None]",
            "ref7_inverse_inertia = ref7_R @ body_origin_inverse_inertia[None] @ ref7_R.transpose()",
            "body_angular_velocity[None] = ref7_inverse_inertia @ body_angular_momentum[None]"]


def lines_for(k: int, region, shared: dict, form: str = "position-first") -> list:
    """The reference lines of TODO k for ``region`` (a regions.Region), each ending in a newline."""
    names = dict(I=shared.get(1) or "inertia", F=shared.get(3) or "body_force", T=shared.get(4) or "body_torque")
    out = []
    if k in (1, 2, 3, 4):
        local = names.get({1: "I", 3: "F", 4: "T"}.get(k))
        if local and not region.loop_var and not _declared(region, local):
            out.append(f"{local} = {DECLARE[k]}")
        if region.loop_var:
            out += [line.format(i=region.loop_var, **names) for line in _per_particle(k)]
        else:
            out.append("for ref_i in particle_vertices:")
            out += ["    " + line.format(i="ref_i", **names) for line in _per_particle(k)]
    else:
        out += [line.format(**names) for line in _body(k, form)]
    return [f"{region.indent}{line}\n" for line in out]


def _declared(region, name: str) -> bool:
    """Whether the given code before the TODO declares the local ``name`` at the TODO's level."""
    return any(line.strip().startswith(f"{name} ") or line.strip().startswith(f"{name}=") for line in region.context)
