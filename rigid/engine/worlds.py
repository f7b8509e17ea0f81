"""Many worlds in one simulator: W copies of a scene stepped by the same launches.

``Simulator(config, worlds=W, vary={...})`` builds the scene's bodies (and static meshes) once,
then W copies, world by world: body b of world w is body w · B_w + b. Nothing else changes in
the pipeline: every stage already runs over all bodies, so 1,000 thrown spheres are one
launch over 1,000 bodies. What keeps worlds apart:

- no contact across worlds: the neighbour lists' builds take a candidate only from the same
  world (``grid.same_world``), so no pair consumer ever sees another world's particle, and the
  motion test (motion.py) looks at its own world's bodies only;
- each world's cells are shifted in the grid (``cell_shifts``): copies of one place would
  otherwise crowd the same cells and every build would pass over every world's particles;
- the energies are per world (rows.py writes each world's contact energy).

``vary`` gives each world its own initial conditions or body values, keys of ``VARY_KEYS``:
an array of shape (W,) + the key's shape (every body of a world alike) or (W, B_w) + shape
(each body its own). World-level keys (gravity, stiffness, Δt, materials) are one value for
all worlds: ``python -m rigid sweep`` varies those with a process per run.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ..bodies.overlap import check_start
from ..bodies.placement import check_inside_box
from ..errors import UserError

# scene key -> (BodySpec field, shape of one value)
VARY_KEYS = {"position": ("position", (3,)), "orientation": ("orientation", (4,)),
             "initial_velocity": ("velocity", (3,)), "initial_angular_velocity": ("angular_velocity", (3,)),
             "particle_mass": ("particle_mass", ()), "drag": ("drag", ())}


def check_worlds(worlds, vary: dict | None, bodies_per_world: int) -> dict:
    """``vary`` as {BodySpec field: array (W, B_w) + shape}; raises UserError (one line) for a bad
    world count, an unknown key or a wrong shape."""
    if isinstance(worlds, bool) or not isinstance(worlds, (int, np.integer)) or worlds < 1:
        raise UserError(f"worlds must be a whole number >= 1, not {worlds!r}")
    out = {}
    for key, values in (vary or {}).items():
        if key not in VARY_KEYS:
            raise UserError(f"vary: '{key}' cannot differ between worlds (one of: {', '.join(VARY_KEYS)}); "
                            "vary world keys with python -m rigid sweep")
        field, shape = VARY_KEYS[key]
        array = np.asarray(values, np.float64)
        if array.shape == (worlds,) + shape:
            array = np.repeat(array[:, None], bodies_per_world, axis=1)
        if array.shape != (worlds, bodies_per_world) + shape:
            raise UserError(f"vary: '{key}' has shape {np.shape(values)}; give {(worlds,) + shape} (one value a "
                            f"world) or {(worlds, bodies_per_world) + shape} (one a body)")
        if not np.all(np.isfinite(array)):
            raise UserError(f"vary: '{key}' holds a NaN or an infinity")
        if key in ("particle_mass",) and np.any(array <= 0):
            raise UserError("vary: 'particle_mass' must be > 0 in every world")
        if key == "drag" and np.any(array < 0):
            raise UserError("vary: 'drag' must be >= 0 in every world")
        if key == "orientation":
            norms = np.linalg.norm(array, axis=-1, keepdims=True)
            if np.any(norms == 0):
                raise UserError("vary: an 'orientation' is the zero quaternion")
            array = array / norms
        out[field] = array
    return out


def replicate(bodies: list, worlds: int, vary: dict) -> list:
    """W copies of one world's ``bodies`` (BodySpec), world by world, with ``vary``'s values
    (check_worlds' form) in place of theirs. The geometry is shared, not copied."""
    out = []
    for w in range(worlds):
        for b, body in enumerate(bodies):
            changes = {field: (values[w, b] if values.ndim > 2 else float(values[w, b]))
                       for field, values in vary.items()}
            out.append(dataclasses.replace(body, **changes))
    return out


def world_table(worlds: int, bodies_per_world: int, shifts: np.ndarray) -> np.ndarray:
    """model.body_world's rows (B, 4): each body's world's cell shift (``shifts`` (B, 3), packed
    10 bits an axis: the grid wraps at D <= 256 cells, a divisor of 1024), its world, the world's
    first body and its number of bodies."""
    packed = (shifts[:, 0] % 1024) + (shifts[:, 1] % 1024) * 1024 + (shifts[:, 2] % 1024) * 1024 * 1024
    world = np.repeat(np.arange(worlds), bodies_per_world)
    return np.column_stack([packed, world, world * bodies_per_world, np.full(len(world), bodies_per_world)])


def cell_shifts(worlds: int, bodies_per_world: int, span_cells: int) -> np.ndarray:
    """(W · B_w, 3) integer cell shifts: world w at (i, j, k) · (span_cells + 2) with (i, j, k) its
    place in a cube of worlds, so that no two worlds share a cell within ``span_cells`` of
    their start (past that, the grid's wrap may alias them: then only ``same_world`` parts them)."""
    side = max(1, int(np.ceil(worlds ** (1.0 / 3.0) - 1e-9)))
    w = np.arange(worlds)
    place = np.column_stack([w % side, (w // side) % side, w // (side * side)])
    return np.repeat(place * (int(span_cells) + 2), bodies_per_world, axis=0)


def all_worlds(config, bodies: list, springs: list, worlds: int, varied: dict):
    """Every world's bodies and springs (``varied``: check_worlds' form), each world's start
    checked where ``vary`` moves its bodies."""
    per_world = len(bodies)
    out = replicate(bodies, worlds, varied)
    if {"position", "orientation"} & set(varied):
        for w in range(worlds):
            world = out[w * per_world:(w + 1) * per_world]
            if config.walls:
                check_inside_box([b for b in world if not b.static], config.floor, config.wall, use_radius=True)
            check_start(config, world)
    return out, replicate_springs(springs, worlds, per_world)


def replicate_springs(springs: list, worlds: int, bodies_per_world: int) -> list:
    """Each world's copy of one world's springs (rigid.bodies.springs.Spring), their bodies
    renumbered into the world (−1, the world's fixed point, stays)."""
    out = []
    for w in range(worlds):
        for spring in springs:
            a, b = (i if i < 0 else i + w * bodies_per_world for i in (spring.a, spring.b))
            out.append(dataclasses.replace(spring, a=a, b=b))
    return out


def by_world(rows: dict, worlds: int) -> dict:
    """Rows (k, W · B_w, width) as (k, W, B_w, width): a world axis before the body axis."""
    return {key: value.reshape(value.shape[0], worlds, -1, value.shape[-1]) for key, value in rows.items()}


def span_in_cells(bodies: list, config, cell: float) -> int:
    """How many grid cells one world spans: the box's width with walls, else its bodies' extent at
    the start (bodies that fly further may share cells with another world's: only slower)."""
    if config.walls:
        return int(np.ceil(2.0 * config.wall / cell))
    positions = np.array([b.position for b in bodies])
    reach = max(b.reach for b in bodies)
    return int(np.ceil((np.ptp(positions, axis=0).max() + 2 * reach) / cell))
