"""A particle's contacts with the static planes, under each of the two laws (contact.py).

The one force loop (force_loop.py) asks ``planes(c, i, p, r, f)`` for particle i at p (offset r
from the centre of mass) and gets f with the planes' forces added, in index order; ``c`` is what
the block loaded once for its loop (a namedtuple: Taichi inlines it). Which law is compiled in:

- ``plain_planes`` (PlainPlanes): the handout's law with the world's k, k_d, μ, on up to
  three planes in reach held in plain vectors (``count`` of them, chosen per block: 0, 1 or
  3; -1: every plane of the world), so that LLVM keeps them in registers and vectorises;
- ``material_planes`` (MaterialPlanes): each plane's own damper from the two sides'
  restitution and the load (materials.py), Coulomb friction with a sticking spring whose
  stretch lives in ``state.plane_slip`` [N · MAX_PLANES], and the block's contacts counted
  (for the next evaluation's m_eff); a plane out of reach has its spring cleared, and so has a
  static mesh's face the particle is not in front of most (static_faces.on_face: a convex
  [[static]] mesh touched at its faces under this same law).
"""
from collections import namedtuple

import taichi as ti

from .contact import plane_force, plane_force_sticking
from .materials import pair_mu, pair_restitution, plane_damping
from .matvec import ZERO3, cross, dot
from .state import MATERIAL_TABLE, MATERIALS, MAX_PLANES, NUM_PLANES
from .static_faces import on_face

PlainPlanes = namedtuple("PlainPlanes", "world v omega radius stiffness kd mu plane0 plane1 plane2 count")


@ti.func
def plain_planes(c: ti.template(), i, p, r, f):
    """f + the forces of the planes c holds on the particle at p (its velocity from the body's v, ω)."""
    if ti.static(c.count > 0):
        pv = c.v + cross(c.omega, r)
        fc, _e = plane_force(p, pv, c.radius, c.plane0, c.stiffness, c.kd, c.mu)
        f += fc
        if ti.static(c.count > 1):
            fc1, _e1 = plane_force(p, pv, c.radius, c.plane1, c.stiffness, c.kd, c.mu)
            fc2, _e2 = plane_force(p, pv, c.radius, c.plane2, c.stiffness, c.kd, c.mu)
            f += fc1
            f += fc2
    elif ti.static(c.count < 0):
        pv = c.v + cross(c.omega, r)
        for j in range(ti.cast(c.world.values[NUM_PLANES], ti.i32)):
            fc, _e = plane_force(p, pv, c.radius, c.world.planes[j], c.stiffness, c.kd, c.mu)
            f += fc
    return f


MaterialPlanes = namedtuple("MaterialPlanes", "state world v omega radius stiffness dt g near mat m_eff ct c_world "
                                              "mu_world step touch_part contacts")


@ti.func
def material_planes(c: ti.template(), i, p, r, f):
    """f + the material contacts of the planes in reach (bits of ``near``) on the particle at p,
    their sticking springs carried in state.plane_slip and the touching ones counted."""
    pv = c.v + cross(c.omega, r)
    for j in range(ti.cast(c.world.values[NUM_PLANES], ti.i32)):
        slot = i * MAX_PLANES + j
        active = 0
        if c.near & (1 << j):
            active = on_face(c.world, j, p)
        if active:
            plane = c.world.planes[j]
            normal = ti.Vector([plane[0], plane[1], plane[2]])
            slip = c.state.plane_slip[slot]
            damper, memory = plane_damping(pair_restitution(c.mat[1], c.world.values[MATERIALS + 4 * j + 1]),
                                           c.stiffness, c.m_eff, c.dt, -dot(c.g, normal), dot(normal, slip),
                                           dot(normal, pv), plane[3] + c.radius - dot(normal, p), c.world.values,
                                           MATERIALS + MATERIAL_TABLE, c.c_world, c.touch_part)
            mu = pair_mu(c.mat[0], c.world.values[MATERIALS + 4 * j], c.mu_world)
            fc, slip, touching = plane_force_sticking(p, pv, c.radius, plane, c.stiffness, damper, c.ct, mu, slip,
                                                      c.step)
            f += fc
            c.state.plane_slip[slot] = slip + (memory * touching) * normal  # zero once clear
            c.contacts += touching
        else:
            c.state.plane_slip[slot] = ZERO3
    return f
