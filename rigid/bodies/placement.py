"""From a config to the scene's bodies: geometry, collision radius, initial pose, copies.

A scene without ``[[body]]`` tables is one body (the top-level keys). With them,
each table is a body entry whose unset keys come from the top level, and
``count = N`` makes N copies of the entry, placed without overlap in a lattice
whose first layer is centred on the entry's ``position``: square layers as wide
as the box allows (walls on; 125 spheres of 0.15 m make 5 x 5 x 5) or a cube of
copies (walls off), layers stacked upward. Each copy gets a seeded random orientation unless ``orientation`` is
given (``seed`` + entry index: the same scene gives the same pile). A mesh file holding
several meshes (a GLB's nodes) is several bodies (rigid.bodies.group) placed as one group:
its centre of mass at ``position``, turned by ``orientation`` about it, moving as one rigid
body with the entry's velocity and angular velocity; ``count`` copies the group.

Collision radius between bodies (``particle_radius``, or from the spacing; one body has none):
half the largest nearest-neighbour distance among the body's particles, so that every sphere
touches its nearest neighbour and they leave no channel a particle of the same size could pass
through (volume particles: half a cell). The spheres lie inside the mesh, tangent to its faces
(rigid.bodies.inset), so the radius never inflates a body; it is at most a quarter of the mesh's
thinnest extent (``radius_cap``): a box's 8 vertex spheres then touch one another, a thin domino's
spheres meet in its middle. A ``particle_radius`` above that is refused. Copies are spaced, and
the start is checked, by those spheres: the mesh's geometry.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import UserError
from .budget import check_fits, simulation_bytes
from .group import entry_geometries, group_centre
from .inset import collision_centres, radius_cap
from .mesh import BodyGeometry
from .quaternion import quaternion_to_matrix_np


@dataclass
class BodySpec:
    """One body of the scene, before Taichi: geometry (shared by copies) and initial state."""

    name: str
    geometry: BodyGeometry  # particles and drawn mesh, mesh frame (not yet centred)
    particle_mass: float
    radius: float  # collision radius of each particle against other bodies, m
    position: np.ndarray  # (3,) initial centre of mass, world
    orientation: np.ndarray  # (4,) unit quaternion, scalar first
    velocity: np.ndarray  # (3,) m/s
    angular_velocity: np.ndarray  # (3,) rad/s, world
    restitution: float | None = None  # the body's e and μ (rigid.bodies.colliders; None: unset)
    friction: float | None = None
    static: bool = False  # a [[static]] mesh (rigid.bodies.statics)
    drag: float = 0.0  # linear drag c per particle, N s/m (rigid.engine.forces)
    group: tuple | None = None  # (entry, copy) of the meshes one file places together

    @classmethod
    def from_geometry(cls, config, geometry: BodyGeometry) -> "BodySpec":
        """The one body ``geometry`` at the config's pose, velocities, mass and radius."""
        return cls("body", geometry, config.particle_mass, config.particle_radius or 0.0,
                   *(np.asarray(getattr(config, k), float) for k in
                     ("position", "orientation", "initial_velocity", "initial_angular_velocity")),
                   drag=config.drag)

    @property
    def centres(self) -> np.ndarray:
        """Its particles' collision-sphere centres (N, 3), mesh frame: inside the mesh by the radius
        (rigid.bodies.inset; a static's and a radius-0 body's are its particles). Kept on the
        geometry, which copies share; rigid.engine.model makes the same."""
        if self.static or self.radius <= 0:
            return self.geometry.particles
        cache = self.geometry.__dict__.setdefault("_centres", {})
        if self.radius not in cache:
            g = self.geometry
            cache[self.radius] = collision_centres(g.particles, g.vertices, g.faces, self.radius)
        return cache[self.radius]

    @property
    def centre_of_mass(self) -> np.ndarray:
        """The mean of the collision spheres' centres: where the engine puts the body (its x)."""
        return self.centres.mean(axis=0)

    @property
    def reach(self) -> float:
        """Radius of a sphere about the centre of mass that holds the mesh and every particle's sphere."""
        c = self.centre_of_mass
        spheres = float(np.sqrt(((self.centres - c) ** 2).sum(axis=1).max())) + self.radius
        mesh = float(np.sqrt(((self.geometry.vertices - c) ** 2).sum(axis=1).max())) if len(self.geometry.vertices) else 0.0
        return max(spheres, mesh)


def scene_bodies(config) -> list[BodySpec]:
    """Every body of the scene, copies and meshes of a file expanded; raises UserError for bad
    meshes or placements. A file of several meshes is a group placed as one (rigid.bodies.group)."""
    cache: dict = {}
    bodies: list[BodySpec] = []
    particles = 0  # so far, copies included: checked against the free memory before copies are made
    for entry in range(config.num_body_entries):
        body = config.body_config(entry)
        key = (body.mesh, body.scale, body.particles, body.grid)
        if key not in cache:
            cache[key] = entry_geometries(body)
        parts = cache[key]
        stem = _stem(body.mesh)
        given = "orientation" in (config.bodies[entry] if config.bodies else {}) or \
            tuple(body.orientation) != (1.0, 0.0, 0.0, 0.0)
        rng = np.random.default_rng(config.seed + entry)
        templates = [BodySpec(part, geometry, body.particle_mass, _radius(body, geometry, config.many_bodies),
                              np.asarray(body.position, float), np.asarray(body.orientation, float),
                              np.asarray(body.initial_velocity, float),
                              np.asarray(body.initial_angular_velocity, float)) for part, geometry in parts]
        template = templates[0]
        per_copy = sum(len(t.geometry.particles) for t in templates)
        particles += per_copy * body.count
        check_fits(simulation_bytes(particles, config.many_bodies),
                   f"count = {body.count}: {body.count:,} copies of {per_copy:,} particles make {particles:,}"
                   if body.count > 1 else f"the scene has {particles:,} particles",
                   "use a smaller --count" + (" or --grid" if body.particles == "volume" else ""))
        if len(parts) == 1:
            reach = template.reach
        else:
            centre = group_centre([t.geometry for t in templates])
            offsets = [t.centre_of_mass - centre for t in templates]
            reach = max(t.reach + float(np.linalg.norm(o)) for t, o in zip(templates, offsets))
        slots = lattice(np.asarray(body.position, float), body.count, 2.0 * reach * 1.02,
                        config.wall if config.walls else None)
        for k, slot in enumerate(slots):
            q = template.orientation if given or body.count == 1 else random_orientation(rng)
            name = f"{stem}_{entry}_{k}" if body.count > 1 else f"{stem}_{entry}"
            if len(parts) == 1:
                bodies.append(BodySpec(name, template.geometry, body.particle_mass, template.radius, slot, q,
                                       template.velocity, template.angular_velocity, body.restitution, body.friction,
                                       drag=body.drag))
                continue
            R = quaternion_to_matrix_np(q)
            for t, offset in zip(templates, offsets):  # the group turned about its centre, moving rigidly
                arm = R @ offset
                bodies.append(BodySpec(f"{name}_{t.name}", t.geometry, t.particle_mass, t.radius, slot + arm, q,
                                       t.velocity + np.cross(t.angular_velocity, arm), t.angular_velocity,
                                       body.restitution, body.friction, group=(entry, k), drag=body.drag))
    if len(bodies) == 1:
        bodies[0].name = "body"
    return bodies


def _radius(body, geometry: BodyGeometry, many: bool) -> float:
    """Collision radius of the body's particles: particle_radius, or from the spacing (many bodies),
    at most ``radius_cap`` of the mesh (one line for a particle_radius above it)."""
    if not (body.particle_radius or many):
        return 0.0
    cap = radius_cap(geometry.vertices) if len(geometry.faces) else np.inf
    if body.particle_radius:
        if body.particle_radius > cap * (1 + 1e-9):
            raise UserError(f"particle_radius = {body.particle_radius:g} is more than a quarter of "
                            f"{_stem(body.mesh)}'s thinnest extent ({4 * cap:.4g} m at scale {body.scale:g}): "
                            f"its spheres cannot lie inside the mesh; use at most {cap:.4g}, or leave it unset")
        return float(body.particle_radius)
    return min(spacing_radius(geometry.particles), cap)


def spacing_radius(particles: np.ndarray) -> float:
    """Half the largest nearest-neighbour distance (see the module docstring)."""
    if len(particles) < 2:
        return 0.0
    from scipy.spatial import cKDTree

    distances, _ = cKDTree(particles).query(particles, k=2)
    return 0.5 * float(distances[:, 1].max())


def lattice(first: np.ndarray, count: int, spacing: float, wall: float | None) -> list[np.ndarray]:
    """``count`` points ``spacing`` apart: square layers centred on ``first`` (shifted to fit
    inside x, z in [-wall, wall] if walls), stacked upward from first[1]."""
    if count == 1:
        return [first.copy()]
    if wall is not None:
        room = 2.0 * wall - spacing  # the span the centres may cover
        if room < 0:
            raise UserError(f"count = {count}: one copy is {spacing:.3g} m wide with its spacing, wider "
                            f"than the box ({2 * wall:g} m); use a smaller scale or --no-walls")
        per_side = min(int(room // spacing) + 1, int(np.ceil(np.sqrt(count))))  # fill the floor
    else:
        per_side = _cube_side(count)
    if wall is not None:
        _check_height(count, per_side, spacing, wall)
    span = (per_side - 1) * spacing
    centre = first[[0, 2]].copy()
    if wall is not None:  # shift the layer so that it lies inside the walls
        limit = wall - 0.5 * spacing - 0.5 * span
        centre = np.clip(centre, -limit, limit)
    points = []
    for k in range(count):
        layer, rest = divmod(k, per_side * per_side)
        i, j = divmod(rest, per_side)
        points.append(np.array([centre[0] - 0.5 * span + i * spacing, first[1] + layer * spacing,
                                centre[1] - 0.5 * span + j * spacing]))
    return points


MAX_STACK_HEIGHT = 20.0  # m from the first layer to the last: ten times the box's width


def _check_height(count: int, per_side: int, spacing: float, wall: float) -> None:
    """Copies stack upward in layers as wide as the box: too many make a tower (100,000 spheres
    of the default size: 11,112 layers, 8.7 km) that falls for minutes before the first contact
    and strains the engine's grid. Refuse it with the most copies this size allows."""
    layers = -(-count // (per_side * per_side))
    height = (layers - 1) * spacing
    if height <= MAX_STACK_HEIGHT:
        return
    most = per_side * per_side * (int(MAX_STACK_HEIGHT // spacing) + 1)
    raise UserError(f"count = {count}: {count:,} copies {spacing:.3g} m apart make {layers:,} layers of "
                    f"{per_side} x {per_side}, {height:,.0f} m high, in a box {2 * wall:g} m wide (at most "
                    f"{MAX_STACK_HEIGHT:g} m: {most:,} copies of this size); use a smaller --count or "
                    f"--scale, or --no-walls")


def _cube_side(count: int) -> int:
    """Copies per side of a layer: a cube-like block (27 -> 3 x 3 x 3, 125 -> 5 x 5 x 5)."""
    side = int(round(count ** (1.0 / 3.0)))
    return side + 1 if side ** 3 < count else side


def random_orientation(rng) -> np.ndarray:
    """A uniformly random unit quaternion (normalised 4D Gaussian), scalar first."""
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def _stem(mesh: str) -> str:
    from pathlib import Path

    return Path(mesh).stem or "body"


def world_particles(body: BodySpec) -> np.ndarray:
    """The centres of the body's collision spheres (N, 3) at its initial pose: x + R (c - centre of mass)."""
    R = quaternion_to_matrix_np(body.orientation)
    return body.position + (body.centres - body.centre_of_mass) @ R.T


def check_inside_box(bodies: list[BodySpec], floor: float, wall: float, use_radius: bool) -> None:
    """Every body must start inside the box: a particle behind a wall at the start is shot out by
    a spring compressed from the first substep (and a body wider than the box is wedged)."""
    planes = ((1, +1.0, floor, "the floor y = {:g}"), (0, +1.0, -wall, "the wall x = -{:g}"),
              (0, -1.0, -wall, "the wall x = +{:g}"), (2, +1.0, -wall, "the wall z = -{:g}"),
              (2, -1.0, -wall, "the wall z = +{:g}"))
    for index, body in enumerate(bodies):
        points = world_particles(body)
        pad = body.radius if use_radius else 0.0
        lo, hi = points.min(axis=0) - pad, points.max(axis=0) + pad
        who = "the body" if len(bodies) == 1 else f"body {index + 1} ({body.name})"
        width = max(hi[0] - lo[0], hi[2] - lo[2])
        if width > 2 * wall:
            raise UserError(f"{who} is {width:.3g} m wide, wider than the box ({2 * wall:g} m); "
                            f"use a smaller --scale, or --no-walls")
        for axis, sign, offset, label in planes:
            depth = offset - sign * (lo[axis] if sign > 0 else hi[axis])
            if depth > 1e-9:
                what = label.format(floor if axis == 1 else wall)
                fix = ("a higher --position y" if axis == 1 else
                       f"a position inside (|{'xyz'[axis]}| <= {wall - 0.5 * (hi[axis] - lo[axis]):.3g} "
                       f"for this size)")
                raise UserError(f"{who} starts {depth:.3g} m past {what}, outside the box; use {fix}, "
                                f"a smaller --scale, or --no-walls")
