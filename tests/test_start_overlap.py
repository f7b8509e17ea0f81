"""The start check (rigid.bodies.overlap) on many bodies, without Taichi: the close pairs it tests
come from a tree of the centres, so they are checked here against every pair tested by brute
force (scipy's distances): the same first overlapping pair is named, and a big static mesh
is found by a small body far from its centre."""
import numpy as np
import pytest
from scipy.spatial.distance import cdist

from rigid.bodies.mesh import BodyGeometry
from rigid.bodies.overlap import _close_pairs, check_start
from rigid.bodies.placement import BodySpec, world_particles
from rigid.config import SimConfig
from rigid.errors import UserError


def _ball(position, radius=0.05, static=False, points=None):
    rng = np.random.default_rng(len(position) and int(abs(position[0]) * 1e3))
    p = points if points is not None else rng.normal(size=(12, 3)) * 0.03
    geometry = BodyGeometry(p, p, np.zeros((0, 3), int))
    return BodySpec("ball", geometry, 1.0, radius, np.asarray(position, float), np.array([1.0, 0, 0, 0]),
                    np.zeros(3), np.zeros(3), static=static)


def _brute_first(bodies):
    """The first (a, b), a < b in loop order, whose particles' spheres overlap by more than 5 %."""
    points = [world_particles(b) for b in bodies]
    for a in range(len(bodies)):
        for b in range(a + 1, len(bodies)):
            if bodies[a].static and bodies[b].static:
                continue
            touch = bodies[a].radius + bodies[b].radius
            if (touch - cdist(points[a], points[b]).min()) > 0.05 * touch:
                return a, b
    return None


def test_many_bodies_the_first_overlapping_pair_is_the_brute_force_one():
    rng = np.random.default_rng(7)
    centres = rng.uniform(-1.0, 1.0, size=(400, 3))
    bodies = [_ball(c) for c in centres]
    first = _brute_first(bodies)
    assert first is not None  # 400 random balls of ~0.1 m in a 2 m cube: some overlap
    with pytest.raises(UserError, match=rf"body {first[0] + 1} \(ball\) and body {first[1] + 1} \(ball\) overlap by"):
        check_start(SimConfig(), bodies)
    # Every pair whose bounding spheres meet is among the close pairs.
    points = [world_particles(b) for b in bodies]
    reach = np.array([np.linalg.norm(p - p.mean(axis=0), axis=1).max() + b.radius for p, b in zip(points, bodies)])
    d = cdist(centres, centres)
    expected = {(a, b) for a in range(400) for b in range(a + 1, 400) if d[a, b] < reach[a] + reach[b]}
    assert {tuple(map(int, pair)) for pair in _close_pairs(points, bodies)} == expected


def test_a_small_body_inside_a_big_static_far_from_its_centre_is_found():
    plate = np.array([[x, 0.0, z] for x in np.linspace(-2, 2, 41) for z in np.linspace(-2, 2, 41)])
    big = _ball((0.0, 0.0, 0.0), radius=0.05, static=True, points=plate)
    small = [_ball((1.5 + 0.3 * i, 0.4, 0.0)) for i in range(3)] + [_ball((1.9, 0.01, 1.9))]
    assert _brute_first([big] + small) == (0, 4)
    with pytest.raises(UserError, match=r"\[\[static\]\] ball and body 5 \(ball\) overlap by"):
        check_start(SimConfig(), [big] + small)
