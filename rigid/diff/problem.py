"""A scene as the differentiable pass reads it: fixed geometry and the values it differentiates.

The bodies are placed by the engine's own host code (rigid.bodies.placement.scene_bodies), the
planes and their materials are listed as rigid.engine.state.Params lists them (box first, then
the [[plane]] tables, each plane's (μ, e) from its table or the top level, −1 where unset), so
the pass sees the very numbers rigid.Simulator uploads. ``values`` holds every differentiable
input as float64 numpy, by the name of the field that takes it (rigid.diff.tape).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..bodies.colliders import check_colliders, uses_materials
from ..bodies.inset import collision_centres
from ..bodies.placement import scene_bodies
from ..config import FRAME_TIME
from ..engine.materials import UNSET, damping_table, friction_value


@dataclass
class Problem:
    config: object
    materials: bool  # the materials' contact law (restitution, friction or [[plane]] in the scene)
    scheme: str  # "euler" or "symplectic"
    dt: float
    substeps: int  # per frame, as rigid.Simulator: int(1/60 // dt)
    r0: np.ndarray  # (N, 3) body-frame offsets of the collision spheres' centres from each body's centre of mass
    particle_body: np.ndarray  # (N,) int
    body_count: np.ndarray  # (B,) particles of each body
    radius: np.ndarray  # (B,) particle radius against the planes
    reach: np.ndarray  # (B,) the farthest particle from the centre of mass (pair-contact check)
    planes: np.ndarray  # (P, 4) normal into the free side, offset n·point
    plane_from_top: np.ndarray  # (P, 2) bool: plane's (μ, e) is the top level's
    table: np.ndarray  # the scheme's damping table, flat (materials only)
    values: dict = field(default_factory=dict)
    r0_mass: np.ndarray = None  # (N, 3) the particles' own offsets (TODO 1's inertia), as rigid.engine.model

    @property
    def num_bodies(self) -> int:
        return len(self.body_count)

    @property
    def num_particles(self) -> int:
        return len(self.r0)


def plane_list(config) -> tuple[np.ndarray, list, np.ndarray]:
    """(planes (P, 4), their (μ, e, ...) rows, whether each takes the top level's μ and e)."""
    rows, materials, from_top = [], [], []
    top = (friction_value(config.friction), friction_value(config.restitution))
    if config.walls:
        f, w = config.floor, config.wall
        rows += [[0, 1, 0, f], [1, 0, 0, -w], [-1, 0, 0, -w], [0, 0, 1, -w], [0, 0, -1, -w]]
        materials += [top] * 5
        from_top += [(True, True)] * 5
    for p in config.planes:
        rows.append(list(p["normal"]) + [float(np.dot(p["normal"], p["point"]))])
        own = (p.get("friction"), p.get("restitution"))
        materials.append(tuple(friction_value(o) if o is not None else t for o, t in zip(own, top)))
        from_top.append(tuple(o is None for o in own))
    return np.array(rows, np.float64).reshape(-1, 4), materials, np.array(from_top, bool).reshape(-1, 2)


def build_problem(config) -> Problem:
    """The Problem of a checked scene (rigid.diff.scope), placed on the host (no Taichi)."""
    config = check_colliders(config)
    bodies = scene_bodies(config)
    materials = uses_materials(config)
    # As the engine's model: a body in company touches with spheres set inside its mesh
    # (rigid.bodies.inset), their mean its centre of mass; its inertia is its particles' own.
    centres = [collision_centres(b.geometry.particles, b.geometry.vertices, b.geometry.faces, b.radius)
               for b in bodies]
    r0 = [c - c.mean(axis=0) for c in centres]
    r0_mass = np.concatenate([np.asarray(b.geometry.particles, np.float64) - c.mean(axis=0)
                              for b, c in zip(bodies, centres)])
    counts = np.array([len(r) for r in r0])
    planes, plane_materials, from_top = plane_list(config)
    dt = float(config.dt)
    problem = Problem(config, materials, config.integrator, dt, max(1, int(FRAME_TIME // dt)),
                      np.concatenate(r0), np.repeat(np.arange(len(bodies)), counts), counts,
                      np.array([b.radius for b in bodies], np.float64),
                      np.array([np.linalg.norm(r, axis=1).max() for r in r0]), planes, from_top,
                      damping_table(config.integrator).reshape(-1) if materials else np.zeros(1))
    problem.r0_mass = r0_mass
    pm = np.array(plane_materials, np.float64).reshape(-1, 2)
    problem.values = dict(
        x0=np.array([b.position for b in bodies], np.float64),
        q0=np.array([b.orientation for b in bodies], np.float64),
        v0=np.array([b.velocity for b in bodies], np.float64),
        w0=np.array([b.angular_velocity for b in bodies], np.float64),
        m=np.array([b.particle_mass for b in bodies], np.float64),
        drag=np.array([b.drag for b in bodies], np.float64),
        e_b=np.array([friction_value(b.restitution) for b in bodies], np.float64),
        mu_b=np.array([friction_value(b.friction) for b in bodies], np.float64),
        e_p=pm[:, 1] if len(pm) else np.full(1, UNSET),
        mu_p=pm[:, 0] if len(pm) else np.full(1, UNSET),
        k=np.float64(config.collision_stiffness),
        c_world=np.float64(config.velocity_damping_stiffness),
        mu_world=np.float64(config.friction_stiffness),
        g=np.array(config.gravity, np.float64),
    )
    return problem
