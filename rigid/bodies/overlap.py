"""Bodies that start badly: behind a [[plane]], or inside one another.

A penalty contact stores ½ k δ² in every overlap present at the start and fires the bodies
apart with it on the first substeps (two boxes half-overlapping leave at 6.5 m/s; two at the
same point stay fused for good). So a scene whose bodies start overlapping is refused with
one line naming the two bodies (or the body and the plane) and the depth, and the fix.

Overlap of two bodies: with a static mesh touched at its faces (rigid.engine.static_faces), the
deepest of the other's spheres in its faces, r − max_f (n_f·p − d_f), as the contact sees it;
else the deepest overlap of two of their particles' spheres,
r_a + r_b − |p_i − p_j| (one body's particles have radius 0 unless set: their centres). The
spheres lie inside the meshes, tangent to their faces (rigid.bodies.inset), so this is how deep
the meshes' surfaces cut into each other where the contact will push, and what it would store:
meshes that do not touch never overlap (the copies of ``count``, placed by the same spheres).
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


def check_start(config, bodies, faces: dict | None = None) -> None:
    """Raise UserError if a body starts behind a [[plane]] or overlapping another body (``faces``:
    rigid.bodies.statics.static_faces, the statics touched at their faces, measured by them)."""
    faces = faces or {}
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
    for a, b in _close_pairs(points, bodies):
        touch = bodies[a].radius + bodies[b].radius
        if a in faces or b in faces:  # a moving body's spheres in the static's faces
            face, mover = (a, b) if a in faces else (b, a)
            touch = bodies[mover].radius
            planes = faces[face][0]
            depth = float(np.max(touch - np.max(points[mover] @ planes[:, :3].T - planes[:, 3], axis=1)))
            what = f"{names[mover].split(' (')[0]}'s particle spheres inside the static's faces"
            allowed = TOLERANCE * max(touch, 1e-3)
        else:
            depth = _deepest(points[a], points[b], touch)
            what, allowed = _spheres(bodies[a], bodies[b], names[a], names[b]), TOLERANCE * touch
        if depth > allowed:
            raise UserError(f"{names[a]} and {names[b]} overlap by {depth:.3g} m at the start "
                            f"({what}); the contact would fire them apart: {_fix(config)}")


def _spheres(a, b, name_a: str, name_b: str) -> str:
    """What overlaps: both bodies' surfaces (their spheres inside the meshes), or one's particle
    centres in the other's spheres (a lone body's particles have no radius: "radius 0" read as a
    mistake)."""
    if a.radius > 0 and b.radius > 0:
        return (f"their surfaces, by the collision spheres inside their meshes, radius {a.radius:.3g} "
                f"and {b.radius:.3g} m")
    point, sized = (name_a, b) if a.radius == 0 else (name_b, a)
    return f"{point.split(' (')[0]}'s particles inside the other's particle spheres of radius {sized.radius:.3g} m"


def _fix(config) -> str:
    """Move them apart; a smaller count only where copies were asked for (the lattice of one
    entry's copies never overlaps itself, but it may reach another body)."""
    counts = [config.body_config(e).count for e in range(config.num_body_entries)]
    return "move them apart (position)" + (" or use a smaller count" if max(counts, default=1) > 1 else "")


def _close_pairs(points, bodies) -> np.ndarray:
    """(a, b) with a < b, in that order, of the bodies whose bounding spheres (about their particles'
    centre, holding every particle's sphere) meet, leaving out two statics and the meshes of one
    file. A tree of the centres finds them: testing every pair in Python grows as the square."""
    if len(bodies) < 2:  # (a lone body's run never imports scipy: ~0.2 s of every start)
        return np.zeros((0, 2), int)
    from scipy.spatial import cKDTree

    centres = np.array([p.mean(axis=0) for p in points])
    reach = np.array([np.sqrt(((p - c) ** 2).sum(axis=1).max()) + b.radius
                      for p, c, b in zip(points, centres, bodies)])
    # Each body's neighbours within its reach plus the largest: a big static mesh finds the small
    # bodies near it, which do not all find one another.
    around = cKDTree(centres).query_ball_point(centres, reach + reach.max())
    pairs = np.array(sorted((a, b) for a, near in enumerate(around) for b in near if b > a), int).reshape(-1, 2)
    a, b = pairs[:, 0], pairs[:, 1]
    near = np.linalg.norm(centres[a] - centres[b], axis=1) < reach[a] + reach[b]
    static = np.array([body.static for body in bodies])
    group = [body.group for body in bodies]
    keep = near & ~(static[a] & static[b])
    keep &= np.array([group[i] is None or group[i] != group[j] for i, j in pairs], bool).reshape(-1)
    return pairs[keep]


def _deepest(p: np.ndarray, q: np.ndarray, touch: float) -> float:
    """max over particle pairs of touch − |p_i − q_j| (−inf if none is within touch)."""
    if touch <= 0:
        return -np.inf
    from scipy.spatial import cKDTree

    d, _ = cKDTree(q).query(p, k=1, distance_upper_bound=touch)
    d = d[np.isfinite(d)]
    return float(touch - d.min()) if len(d) else -np.inf
