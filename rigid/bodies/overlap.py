"""Bodies that start badly: behind a [[plane]], or inside one another.

A penalty contact stores ½ k δ² in every overlap present at the start and fires the bodies
apart with it on the first substeps (two boxes half-overlapping leave at 6.5 m/s; two at the
same point stay fused for good). So a scene whose bodies start overlapping is refused with
one line naming the two bodies (or the body and the plane) and the depth, and the fix.

Overlap of two bodies: the deepest overlap of two of their particles' spheres,
r_a + r_b − |p_i − p_j| (one body's particles have radius 0 unless set: their centres).
Up to ``TOLERANCE`` of the pair's reach r_a + r_b is let pass: touching at the start is not
overlapping (a lattice of copies, a stack with its gaps, the meshes of one file side by side).
The meshes of one file (a GLB's nodes) are where the file puts them and are not checked against
one another. The box's walls are checked by rigid.bodies.placement.check_inside_box.
"""
from __future__ import annotations

import numpy as np

from ..errors import UserError
from .placement import world_particles

TOLERANCE = 0.05  # of r_a + r_b: a 5 % overlap stores 0.25 % of the energy of a full one


def check_start(config, bodies) -> None:
    """Raise UserError if a body starts behind a [[plane]] or overlapping another body."""
    points = [world_particles(b) for b in bodies]
    names = [f"body {i + 1} ({b.name})" if not b.static else f"[[static]] {b.name}" for i, b in enumerate(bodies)]
    for index, plane in enumerate(config.planes):
        n, offset = np.asarray(plane["normal"]), float(np.dot(plane["normal"], plane["point"]))
        for body, p, name in zip(bodies, points, names):
            if body.static:
                continue
            depth = float(np.max(offset + body.radius - p @ n))
            if depth > TOLERANCE * max(body.radius, 1e-3):
                raise UserError(f"{name} starts {depth:.3g} m behind [[plane]] {index + 1} (point "
                                f"{list(plane['point'])}, normal {[round(v, 4) for v in plane['normal']]}); "
                                f"move it to the side the normal points to")
    centres = [p.mean(axis=0) for p in points]
    reach = [float(np.sqrt(((p - c) ** 2).sum(axis=1).max())) + b.radius for p, c, b in zip(points, centres, bodies)]
    for a in range(len(bodies)):
        for b in range(a + 1, len(bodies)):
            if bodies[a].static and bodies[b].static:
                continue
            if bodies[a].group is not None and bodies[a].group == bodies[b].group:
                continue
            if np.linalg.norm(centres[a] - centres[b]) >= reach[a] + reach[b]:
                continue
            touch = bodies[a].radius + bodies[b].radius
            depth = _deepest(points[a], points[b], touch)
            if depth > TOLERANCE * touch:
                raise UserError(f"{names[a]} and {names[b]} overlap by {depth:.3g} m at the start (their particles' "
                                f"spheres, radius {bodies[a].radius:.3g} and {bodies[b].radius:.3g} m); the "
                                f"contact would fire them apart: move them apart (position) or lower count")


def _deepest(p: np.ndarray, q: np.ndarray, touch: float) -> float:
    """max over particle pairs of touch − |p_i − q_j| (−inf if none is within touch)."""
    if touch <= 0:
        return -np.inf
    from scipy.spatial import cKDTree

    d, _ = cKDTree(q).query(p, k=1, distance_upper_bound=touch)
    d = d[np.isfinite(d)]
    return float(touch - d.min()) if len(d) else -np.inf
