"""The core simulator against closed forms: particles, mass, inertia, free flight, the box."""
import numpy as np
import trimesh

from conftest import ASSETS


def test_sphere_obj_gives_42_particles_and_mass(sim_cache):
    sim = sim_cache(particle_mass=2.5)
    assert sim.model.num_particles == 42
    assert np.isclose(sim.model.mass, 42 * 2.5)


def test_obj_with_uv_and_normals_keeps_one_particle_per_v_line(tmp_path):
    from rigid.bodies.mesh import load_mesh

    s = trimesh.creation.icosphere(subdivisions=1)
    lines = [f"v {x} {y} {z}" for x, y, z in s.vertices]
    lines += [f"vt {0.5 + x / 2} {0.5 + y / 2}" for x, y, _ in s.vertices]
    lines += [f"vn {x} {y} {z}" for x, y, z in s.face_normals]
    lines += ["f " + " ".join(f"{a + 1}/{a + 1}/{i + 1}" for a in f) for i, f in enumerate(s.faces)]
    path = tmp_path / "uv.obj"
    path.write_text("\n".join(lines) + "\n")
    vertices, faces = load_mesh(path, scale=0.3)
    assert vertices.shape == (42, 3) and faces.shape == (80, 3)
    np.testing.assert_allclose(vertices, 0.3 * s.vertices, atol=1e-6)


def test_every_asset_format_loads(tmp_path):
    from rigid.bodies.mesh import load_mesh

    box = trimesh.creation.box(extents=(1, 2, 3))
    for ext in ("stl", "ply", "off", "glb"):
        box.export(tmp_path / f"b.{ext}")
        vertices, faces = load_mesh(tmp_path / f"b.{ext}")
        assert len(faces) == 12
        np.testing.assert_allclose(np.ptp(vertices, axis=0), [1, 2, 3], atol=1e-6)


def test_inertia_is_numpys_particle_sum(sim_cache):
    sim = sim_cache(mesh=str(ASSETS / "t_handle.obj"), scale=1.0, particle_mass=0.7)
    from rigid.bodies.mesh import load_mesh

    v, _ = load_mesh(ASSETS / "t_handle.obj")
    r = v - v.mean(axis=0)
    expect = 0.7 * (np.sum(r * r) * np.eye(3) - r.T @ r)
    np.testing.assert_allclose(sim.model.inertia_body_np[0], expect, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(sim.model.inertia_body_np[0] @ sim.model.inertia_body_inv_np[0], np.eye(3), atol=1e-5)


def test_free_flight_momentum_and_explicit_euler_parabola(sim_cache):
    g, v0, x0 = np.array([0.3, -9.8, 1.1]), np.array([1.0, 2.0, -0.5]), np.array([0.1, 0.2, 0.3])
    sim = sim_cache(walls=False, gravity=tuple(g), initial_velocity=tuple(v0), position=tuple(x0),
                    initial_angular_velocity=(0.0, 0.0, 0.0))
    M, dt, n = sim.model.mass, sim.config.dt, sim.substeps
    for frame in range(1, 31):
        sim.step_frame()
    s, k = sim.snapshot(), 30 * n
    assert s["P"].shape == (1, 3)  # per body, always
    # float32 round-off bound of k sequential additions: k ε max|value|.
    P = M * v0 + M * g * k * dt
    np.testing.assert_allclose(s["P"][0], P, rtol=0, atol=k * np.finfo(np.float32).eps * np.abs(P).max())
    # Explicit Euler moves x with the old velocity: x_k = x0 + v0 k dt + g dt² k(k-1)/2.
    x = x0 + v0 * k * dt + g * dt**2 * k * (k - 1) / 2
    np.testing.assert_allclose(s["x"][0], x, rtol=0, atol=k * np.finfo(np.float32).eps * np.abs(x).max())
    # ... which semi-implicit Euler, k(k+1)/2, would miss by g dt² k: far above round-off.
    assert np.abs(g * dt**2 * k).max() > 100 * k * np.finfo(np.float32).eps * np.abs(x).max()


def test_torque_free_spin_keeps_angular_momentum(sim_cache):
    sim = sim_cache(mesh=str(ASSETS / "t_handle.obj"), scale=1.0, particle_mass=0.7)
    sim.reconfigure(walls=False, gravity=(0.0, -9.8, 0.0), initial_angular_velocity=(1.0, 3.0, -2.0))
    L0 = sim.snapshot()["L"]
    for _ in range(60):
        sim.step_frame()
    s = sim.snapshot()
    assert np.linalg.norm(s["L"] - L0) <= 1e-5 * np.linalg.norm(L0)
    assert abs(np.linalg.norm(s["q"]) - 1) < 1e-6


def test_dropped_sphere_stays_above_floor_and_comes_to_rest(sim_cache):
    sim = sim_cache()  # the assignment scene: radius 0.3, dropped from rest at the origin
    lowest, speeds = np.inf, []
    for _ in range(600):
        sim.step_frame()
        lowest = min(lowest, sim.particle_positions()[:, 1].min())
        speeds.append(np.linalg.norm(sim.snapshot()["v"]))
    # Bound from energy: falling 0.7 m onto one undamped spring k gives depth d with
    # ½ k d² = M g (0.7 + d); damping only makes it shallower.
    M, k, g = sim.model.mass, sim.config.collision_stiffness, 9.8
    d_max = (M * g + np.sqrt((M * g) ** 2 + 2 * k * M * g * 0.7)) / k
    assert -1.0 - lowest < d_max
    assert max(speeds[-60:]) < 1e-3  # at rest during the 10th second
    assert abs(sim.snapshot()["x"][0, 1] - (-1.0 + 0.3)) < 0.05  # resting on the floor, not sunk


def test_thrown_sphere_stops_sliding(sim_cache):
    sim = sim_cache()
    sim.reconfigure(position=(-0.5, -0.69, 0.0), initial_velocity=(2.0, 0.0, 0.0))
    slip = []
    for _ in range(240):
        sim.step_frame()
        x, v = sim.particle_positions(), sim.particle_velocities()
        slip.append(np.linalg.norm(v[np.argmin(x[:, 1])][[0, 2]]))
    s = sim.snapshot()
    assert slip[5] > 0.5  # it starts out sliding on the floor ...
    assert max(slip[-30:]) < 0.01  # ... and friction ends the sliding
    assert np.linalg.norm(s["v"]) < 0.05  # and the polyhedral ball comes to rest
    assert s["x"][0, 0] < 1.0 - 0.3 + 0.05  # never through the wall
