"""Static meshes touched at their faces: a convex [[static]] mesh (a box, a ramp) as its planes.

A static mesh of particles (rigid.bodies.statics) is an envelope of spheres: a body sliding on
it rides over their bumps, and friction comes out of the bumps, not μ. A convex closed mesh is
exactly the intersection of its face planes, so the engine touches it there instead: its faces
are planes of the world (``world.planes``, after the box's and the [[plane]] tables', one slot
of the MAX_PLANES each, Params.set_faces), under the planes' own law (plane_terms.material_planes:
the material damper, Coulomb friction with a sticking spring per (particle, face) in
``state.plane_slip``), bounded by the mesh: a particle's sphere touches the face f of mesh g when

    f = argmax over g's faces of (n·p − d)      the face its centre is most in front of
    and  r − (n_f·p − d_f) > 0                   the sphere overlaps that face's plane,

i.e. the mesh's signed distance max_f (n_f·p − d_f) (exact in front of a face and inside; within
a factor √3 off an edge or a corner, where the contact begins a little early) is below the
particle's radius, and the force acts along that face's normal. Ties go to the lower slot.

Each face plane's row of materials in ``world.values`` (MATERIALS + 4 j: μ, e, then here) holds
its mesh's first plane and its number of planes; a free plane (the box, a [[plane]]) has 0 there
and acts wherever its sphere overlaps it. Such a mesh's body is flagged 2 in
``model.body_material[b][2]`` (1: a static of particles) and its particles are left out of the
pair stage (material_stages), so no contact is counted twice. A face out of reach of a block
(stages.planes_in_reach) leaves its particles clear of the mesh, whichever face is the argmax.
"""
import taichi as ti

from .state import MATERIALS

FACED = 1.5  # model.body_material[b][2] above this: a static touched at its faces


@ti.func
def faced(model: ti.template(), b):
    """Whether body b is a static mesh touched at its faces (its particles out of the pair stage)."""
    return model.body_material[b][2] > FACED


@ti.func
def on_face(world: ti.template(), j, p):
    """1 if plane j may act on a particle at p (a free plane; a static mesh's face that is the
    argmax of its mesh's n·p − d), else 0."""
    first = ti.cast(world.values[MATERIALS + 4 * j + 2], ti.i32)
    count = ti.cast(world.values[MATERIALS + 4 * j + 3], ti.i32)
    plane = world.planes[j]
    h = plane[0] * p[0] + plane[1] * p[1] + plane[2] * p[2] - plane[3]
    result = 1
    for f in range(first, first + count):
        other = world.planes[f]
        h_f = other[0] * p[0] + other[1] * p[1] + other[2] * p[2] - other[3]
        if h_f > h or (h_f == h and f < j):
            result = 0
    return result
