"""A scene's materials and static colliders: ``restitution``, ``friction``, [[plane]], [[static]].

Keys (contract, ../shared/DESIGN.md "materials and static colliders"):
- ``restitution`` e (0 <= e <= 1) and ``friction`` μ (Coulomb, >= 0): at the top level they are
  every body's and every static collider's (the box, the planes, the static meshes); a
  [[body]], [[plane]] or [[static]] table sets its own.
- [[plane]]: ``point`` (a point of the plane) and ``normal`` (into the free side; normalised
  here), and its own ``friction`` / ``restitution``. Planes come after the box's five (if
  ``walls``), in file order.
- [[static]]: ``mesh``, ``scale``, ``position`` (where the mesh's centre of its vertices goes),
  ``orientation`` (scalar-first quaternion), ``friction``, ``restitution``: a mesh that never moves.

A pair combines its two values (rigid.engine.materials): e = max(e_a, e_b), μ = √(μ_a μ_b).

Plain Python (no Taichi, no numpy at import). rigid.config reads the tables and checks the
top-level values; ``check_colliders`` checks the tables (the Simulator calls it first).
"""
from __future__ import annotations

import math

from ..config import MATERIAL_KEYS
from ..errors import UserError

MAX_PLANES = 16  # rigid.engine.state.MAX_PLANES: the box's five and up to eleven [[plane]] tables
PLANE_KEYS = {"point", "normal", *MATERIAL_KEYS}
STATIC_KEYS = {"mesh", "scale", "position", "orientation", *MATERIAL_KEYS}


def uses_materials(config) -> bool:
    """Whether the scene uses the material contact (restitution, friction, [[plane]] or
    [[static]] anywhere); without, the contact is the handout's (rigid.engine.contact)."""
    tables = (config, *config.bodies, *config.planes, *config.statics)
    return bool(config.planes or config.statics) or any(
        (t.get(k) if isinstance(t, dict) else getattr(t, k)) is not None for t in tables for k in MATERIAL_KEYS)


def check_colliders(config):
    """Check the [[plane]] and [[static]] tables (one UserError line), the planes' normals made unit
    vectors in place; returns the config."""
    object.__setattr__(config, "planes", tuple(check_plane(i, p) for i, p in enumerate(config.planes)))
    object.__setattr__(config, "statics", tuple(check_static(i, t) for i, t in enumerate(config.statics)))
    check_plane_count(config.planes, config.walls)
    return config


def check_material(where: str, table: dict) -> None:
    """One line for a restitution outside [0, 1] or a negative friction (``where``: the table)."""
    e, mu = table.get("restitution"), table.get("friction")
    if e is not None and not (_number(e) and 0.0 <= e <= 1.0):
        raise UserError(f"{where}restitution = {e!r}: use a number from 0 (no bounce) to 1 (elastic), e.g. 0.5")
    if mu is not None and not (_number(mu) and math.isfinite(mu) and mu >= 0.0):
        raise UserError(f"{where}friction = {mu!r}: use zero or a positive Coulomb coefficient, e.g. 0.3")


def check_plane(index: int, table: dict) -> dict:
    """A [[plane]] table checked, its normal made a unit vector (tuples of floats)."""
    where = f"[[plane]] {index + 1}: "
    unknown = sorted(set(table) - PLANE_KEYS)
    if unknown:
        raise UserError(f"{where}unknown key {unknown[0]!r}; plane keys: {', '.join(sorted(PLANE_KEYS))}")
    for key in ("point", "normal"):
        if key not in table:
            raise UserError(f"{where}needs '{key}' (three numbers), e.g. point = [0, -1, 0], normal = [0, 1, 0]")
        value = table[key]
        if not (isinstance(value, (list, tuple)) and len(value) == 3 and all(_number(v) and math.isfinite(v)
                                                                             for v in value)):
            raise UserError(f"{where}{key} = {value!r}: use three finite numbers X Y Z")
    norm = math.sqrt(sum(float(v) ** 2 for v in table["normal"]))
    if norm < 1e-12:
        raise UserError(f"{where}normal = {list(table['normal'])} has no direction; give the direction "
                        f"into the free side, e.g. [0, 1, 0] for a floor")
    check_material(where, table)
    out = dict(table)
    out["point"] = tuple(float(v) for v in table["point"])
    out["normal"] = tuple(float(v) / norm for v in table["normal"])
    return out


def check_static(index: int, table: dict) -> dict:
    """A [[static]] table's keys checked (the mesh is read, and its path resolved, by the caller)."""
    where = f"[[static]] {index + 1}: "
    unknown = sorted(set(table) - STATIC_KEYS)
    if unknown:
        raise UserError(f"{where}unknown key {unknown[0]!r}; static keys: {', '.join(sorted(STATIC_KEYS))}")
    if "mesh" not in table:
        raise UserError(f"{where}needs 'mesh' (a mesh file, e.g. mesh = \"bowl.obj\")")
    scale = table.get("scale", 1.0)
    if not (_number(scale) and math.isfinite(scale) and scale > 0):
        raise UserError(f"{where}scale = {scale!r}: use a positive number")
    check_material(where, table)
    return dict(table)


def check_plane_count(planes: tuple, walls: bool) -> None:
    total = len(planes) + (5 if walls else 0)
    if total > MAX_PLANES:
        raise UserError(f"the scene has {total} planes ({len(planes)} [[plane]] tables"
                        f"{' and the box' if walls else ''}); at most {MAX_PLANES}: remove planes"
                        f"{' or set walls = false' if walls else ''}")


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)
