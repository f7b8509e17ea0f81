"""What the differentiable mode takes, checked on the host before anything compiles.

Every refusal is one ``UserError`` line naming the feature or the input, so that a user learns
at once (not after a minute of compiling) that a scene, a ``wrt`` name or a cotangent does not
fit. The mode differentiates one or several bodies, each on its own against the box and the
[[plane]]s (the plain contact law or the materials' law with sticking friction), with drag and
gravity, under explicit or symplectic Euler. Contact between bodies is checked while the pass
runs (rigid.diff.passes), as only the trajectory tells whether two bodies meet.
"""
from __future__ import annotations

import numpy as np

from ..errors import UserError

# The scene keys a gradient may be taken with respect to, and whether each is a body's value.
WRT_KEYS = {
    "position": "body", "orientation": "body", "initial_velocity": "body", "initial_angular_velocity": "body",
    "particle_mass": "body", "drag": "body", "restitution": "material", "friction": "material",
    "collision_stiffness": "world", "velocity_damping_stiffness": "world", "gravity": "world",
}
ROW_KEYS = {"x": 3, "v": 3, "q": 4, "omega": 3, "P": 3, "L": 3}


def check_scene(config) -> None:
    """One line for a scene feature the mode does not differentiate."""
    if config.integrator not in ("euler", "symplectic"):
        raise UserError(f"integrator = {config.integrator!r} is not differentiated here; "
                        f"gradients take 'euler' (the default) or 'symplectic'")
    if config.statics:
        raise UserError("[[static]] meshes are not differentiated (their contact is a pair contact); "
                        "use [[plane]]s or the box")
    if config.springs:
        raise UserError("[[spring]]s are not differentiated; remove them for rigid.gradient and rigid.fit")
    entries = config.bodies or ({},)
    if any(entry.get("count", config.count) != 1 for entry in entries):
        raise UserError("count > 1 (copies placed in a lattice, turned at random) is not differentiated; "
                        "write one [[body]] table per body")
    from ..config import mesh_count

    if any(mesh_count(entry.get("mesh", config.mesh)) > 1 for entry in entries):
        raise UserError("a mesh file of several meshes (a group) is not differentiated; one mesh a body")
    if len(entries) > 1 and config.sleep and config.restitution is None and config.friction is None \
            and not config.planes and not any(set(e) & {"restitution", "friction"} for e in entries):
        raise UserError("sleep = true with several bodies: a sleeping body is set at rest, which has no "
                        "gradient; set sleep = false")


def check_wrt(config, wrt) -> tuple:
    """The ``wrt`` names as a tuple; one line for an unknown name or a material the scene leaves unset."""
    names = (wrt,) if isinstance(wrt, str) else tuple(wrt)
    if not names:
        raise UserError("wrt is empty: name at least one scene key, e.g. wrt=['initial_velocity']")
    for name in names:
        if name not in WRT_KEYS:
            raise UserError(f"wrt {name!r} is not a key the gradient takes; use one of {', '.join(WRT_KEYS)}")
        if WRT_KEYS[name] == "material" and getattr(config, name) is None \
                and not any(entry.get(name) is not None for entry in config.bodies):
            raise UserError(f"wrt {name!r}: the scene sets no {name}, so the contact does not use it; "
                            f"set {name} = ... in the scene to differentiate with respect to it")
    return names


def check_cotangents(cotangents: dict, frames: int, bodies: int) -> dict:
    """The cotangents as float64 arrays (frames + 1, B, width); one line for a wrong key or shape."""
    if not isinstance(cotangents, dict) or not cotangents:
        raise UserError("cotangents must be a dict of arrays keyed by row names (x, v, q, omega, P, L)")
    out = {}
    for key, value in cotangents.items():
        if key not in ROW_KEYS:
            raise UserError(f"cotangent {key!r} is not a row; use keys among {', '.join(ROW_KEYS)}")
        array = np.asarray(value, np.float64)
        want = (frames + 1, bodies, ROW_KEYS[key])
        if array.shape != want:
            raise UserError(f"cotangent {key!r} has shape {array.shape}; the rows of advance({frames}) "
                            f"are {want} (frames + 1, bodies, {ROW_KEYS[key]})")
        if not np.all(np.isfinite(array)):
            raise UserError(f"cotangent {key!r} holds NaN or infinity")
        out[key] = array
    return out


def check_frames(frames) -> int:
    if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < 1:
        raise UserError(f"frames = {frames!r}: use a positive whole number of frames")
    return int(frames)
