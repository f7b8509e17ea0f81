"""A convex [[static]] mesh touched at its faces (rigid.engine.static_faces), against closed forms.

- the face planes of a static box (turned and moved), coplanar triangles merged: its six faces
  at ±half its side; an open mesh (the bowl) and a dented, non-convex box have none (they keep
  the particles' contact);
- a box (side 0.2) on a static box (side 0.6) tilted 30°, μ = 0.3, slides down its top face at
  g (sin θ − μ cos θ) within 5 % (Coulomb, a flat face on a flat face), its centre within 2 mm
  of the height the faces touch at all the way (no hop over the static's particles), the
  static's particles out of the pair stage (the box has no pair contact);
- with μ = 0.7 > tan 30° it holds: < 2 mm in 2 s;
- the start's overlap check measures a body against the faces: sunk 1 cm is refused, 0.1 mm
  clear at the face's edge is not.
"""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from conftest import ASSETS

BOX = str(ASSETS / "box.obj")
THETA = math.radians(30)
NORMAL = np.array([-math.sin(THETA), math.cos(THETA), 0.0])  # the tilted box's top face
DOWN = np.array([-math.cos(THETA), -math.sin(THETA), 0.0])  # down that face
TURN = (math.cos(THETA / 2), 0.0, 0.0, math.sin(THETA / 2))  # turns +y to NORMAL
TOUCH = 0.3 + 0.1  # the box's centre above the static's centre when their faces touch


def _static(vertices, faces, position=(0.0, 0.0, 0.0), orientation=(1.0, 0.0, 0.0, 0.0)):
    geometry = SimpleNamespace(vertices=np.asarray(vertices, float), faces=np.asarray(faces),
                               particles=np.asarray(vertices, float))
    return SimpleNamespace(geometry=geometry, position=np.asarray(position, float) + geometry.particles.mean(axis=0),
                           orientation=np.asarray(orientation, float), static=True, friction=None, restitution=None)


def test_face_planes_of_a_convex_static_only():
    from rigid.bodies.mesh import read_mesh
    from rigid.bodies.statics import face_planes

    box = read_mesh(BOX, 0.6)
    planes = face_planes(_static(box.vertices, box.faces, (1.0, 2.0, 3.0), TURN))
    assert planes.shape == (6, 4)
    assert np.allclose(np.linalg.norm(planes[:, :3], axis=1), 1.0)
    assert np.allclose(planes[:, 3] - planes[:, :3] @ np.array([1.0, 2.0, 3.0]), 0.3)  # each face 0.3 out
    assert np.isclose(np.max(planes[:, :3] @ NORMAL), 1.0), "the top face turned with the box"
    dented = box.vertices.copy()
    dented[np.argmax(dented.sum(axis=1))] *= 0.2  # a corner pushed in: closed, not convex
    assert face_planes(_static(dented, box.faces)) is None
    bowl = read_mesh(str(ASSETS / "bowl.obj"), 0.5)
    assert face_planes(_static(bowl.vertices, bowl.faces)) is None


@pytest.fixture(autouse=True)
def _taichi(units):
    """One Taichi runtime for the module (conftest)."""


def _on_tilted_box(mu, uphill, clear=1e-4):
    """A 0.2 box (corner spheres of radius 0.02) on the top face of a 0.6 [[static]] box turned
    30° about z, ``uphill`` of the face's middle, ``clear`` of it."""
    from rigid.config import SimConfig
    from rigid.engine.simulator import Simulator

    position = (TOUCH + clear) * NORMAL - uphill * DOWN
    return Simulator(SimConfig(mesh=BOX, scale=0.2, particle_radius=0.02, position=tuple(position), orientation=TURN,
                               friction=mu, restitution=0.3, walls=False, collision_stiffness=1e5, particle_mass=0.1,
                               dt=2e-4, statics=(dict(mesh=BOX, scale=0.6, orientation=TURN),)).validate())


def test_box_slides_on_a_tilted_static_box_at_the_closed_form():
    from rigid.engine.arrays import download

    mu = 0.3
    sim = _on_tilted_box(mu, 0.18)
    assert download(sim.model.body_material)[:, 2].tolist() == [0.0, 2.0], "the static is touched at its faces"
    sim.advance_frames(5)  # settled on the face
    t, v, height, pairs = [], [], [], []
    for _ in range(28):  # 0.47 s: 0.33 m down the face, the box still wholly on it
        sim.advance_frames(1)
        s = sim.snapshot()
        t.append(s["t"])
        v.append(s["v"][0] @ DOWN)
        height.append(s["x"][0] @ NORMAL - TOUCH)
        contacts = download(sim._scratch_arrays["contacts"])
        pairs.append(contacts[sim.num_particles + 2 * sim.model.num_blocks + 1])  # body 0's pair contacts
    along = (v[-1] - v[0]) / (t[-1] - t[0])
    expected = 9.8 * (math.sin(THETA) - mu * math.cos(THETA))
    print(f"tilted static box: acceleration / g (sin - mu cos) {along / expected:.4f}, off the face "
          f"{min(height) * 1e3:.3f}..{max(height) * 1e3:.3f} mm")
    assert abs(along - expected) < 0.05 * expected
    assert max(np.abs(height)) < 2e-3, "no hop: a flat face on a flat face"
    assert max(pairs) == 0, "the static's particles are out of the pair stage"


def test_box_holds_on_a_tilted_static_box_face():
    sim = _on_tilted_box(0.7, 0.1)
    sim.advance_frames(12)  # 0.2 s: settled
    a = sim.snapshot()["x"][0]
    sim.advance_frames(120)  # 2 s
    moved = np.linalg.norm(sim.snapshot()["x"][0] - a)
    print(f"tilted static box, mu 0.7: moved {moved * 1e3:.4f} mm in 2 s")
    assert moved < 2e-3


def test_a_box_sunk_into_the_faces_is_refused_and_one_clear_of_them_is_not():
    """The start's check measures a body's spheres against the faces the contact uses: 1 cm into
    the top face is refused; 0.1 mm clear near the face's edge runs (the static's particle spheres
    near that edge reach past the face, and refused it)."""
    from rigid.errors import UserError

    with pytest.raises(UserError, match=r"particle spheres inside the static's faces"):
        _on_tilted_box(0.3, 0.0, -0.01)
    assert _on_tilted_box(0.3, 0.2).num_bodies == 2
