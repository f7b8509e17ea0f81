"""Float64 many-body measurements, printed as JSON (run in a subprocess: one ti.init per process).

- momentum:     head-on box and sphere, free space, explicit Euler: total P over the run
- angular:      the same, off-centre with friction: Σ (L_b + x_b × P_b) under symplectic Euler,
                and explicit Euler's drift at two Δt
- restitution:  two octahedra meeting tip to tip (one particle pair, along the line of centres)
- springs:      two octahedra joined by a [[spring]] between off-centre points: total P and J
"""
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import rigid  # noqa: E402,F401
from rigid.bodies.mesh import BodyGeometry  # noqa: E402
from rigid.bodies.placement import BodySpec  # noqa: E402
from rigid.config import SimConfig, load_scene  # noqa: E402
from rigid.engine.simulator import Simulator  # noqa: E402
from rigid.engine.units import load_units  # noqa: E402
from rigid.runtime import init_taichi  # noqa: E402

FREE = dict(walls=False, gravity=(0.0, 0.0, 0.0), fp64=True)


def run(sim, frames):
    rows = [sim.snapshot()]
    for _ in range(frames):
        sim.step_frame()
        rows.append(sim.snapshot())
    return rows


def head_on_simulator(units, integrator):
    values = load_scene(ROOT / "assets" / "scenes" / "head_on.toml")
    values.update(FREE, integrator=integrator)
    return Simulator(SimConfig(**values).validate(), units)


def head_on(sim, dt, frames, friction):
    """Run the head-on scene (Δt and friction changed without a recompile)."""
    rows = run(sim.reconfigure(dt=dt, friction_stiffness=friction), frames)
    P = np.array([r["P"].sum(axis=0) for r in rows])
    J = np.array([(r["L"] + np.cross(r["x"], r["P"])).sum(axis=0) for r in rows])
    touched = any(np.abs(r["omega"][0]).max() > 1e-6 for r in rows)  # the box was hit
    return dict(P_drift=float(np.abs(P - P[0]).max()), P_scale=float(np.abs(rows[0]["P"]).max()),
                J_drift=float(np.abs(J - J[0]).max()), J_scale=float(np.abs(J[0]).max()),
                touched=bool(touched))


def octahedron(radius):
    a = 0.5
    points = np.array([[a, 0, 0], [-a, 0, 0], [0, a, 0], [0, -a, 0], [0, 0, a], [0, 0, -a]], float)
    return BodyGeometry(points, points, np.zeros((0, 3), np.int32))


K, RADIUS = 1e4, 0.05


def octahedra_simulator(units):
    """Two 6-particle octahedra (1 kg particles) along x, tips meeting at 1 m/s closing speed."""
    config = SimConfig(**FREE, collision_stiffness=K, friction_stiffness=0.0, integrator="symplectic",
                       dt=1e-4, count=2).validate()
    geometry = octahedron(RADIUS)
    bodies = [BodySpec(f"oct{i}", geometry, 1.0, RADIUS, np.array([sign * 0.56, 0.0, 0.0]),
                       np.array([1.0, 0, 0, 0]), np.array([-sign * 0.5, 0.0, 0.0]), np.zeros(3))
              for i, sign in enumerate((-1.0, 1.0))]
    return Simulator(config, units, bodies=bodies)


def restitution(sim, damping):
    k = K
    rows = run(sim.reconfigure(velocity_damping_stiffness=damping), 20)
    v_in = rows[0]["v"][1, 0] - rows[0]["v"][0, 0]
    v_out = rows[-1]["v"][1, 0] - rows[-1]["v"][0, 0]
    spin = max(float(np.abs(r["omega"]).max()) for r in rows)
    M = 6.0
    m_eff = M * M / (M + M)
    zeta = damping / (2.0 * np.sqrt(k * m_eff))
    expected = float(np.exp(-np.pi * zeta / np.sqrt(1.0 - zeta ** 2)))
    return dict(measured=float(-v_out / v_in), expected=expected, zeta=float(zeta), spin=spin)


def spring_pair_simulator(units):
    """Two octahedra far apart in free space, spinning and drifting, joined by a damped spring
    between off-centre points (symplectic Euler): nothing outside acts on the pair."""
    spring = dict(bodies=[0, 1], points=[[0.3, 0.1, 0.0], [-0.2, 0.0, 0.25]], stiffness=40.0, damping=0.5,
                  rest_length=0.8)
    config = SimConfig(**FREE, integrator="symplectic", count=2, springs=(spring,)).validate()
    geometry = octahedron(RADIUS)
    bodies = [BodySpec(f"oct{i}", geometry, 1.0, RADIUS, np.array([sign * 1.2, 0.0, 0.0]), np.array([1.0, 0, 0, 0]),
                       np.array([0.0, sign * 0.4, 0.3]), np.array([0.5, -1.0 * sign, 2.0]))
              for i, sign in enumerate((-1.0, 1.0))]
    return Simulator(config, units, bodies=bodies)


def spring_pair(sim, frames):
    rows = run(sim, frames)
    P = np.array([r["P"].sum(axis=0) for r in rows])
    J = np.array([(r["L"] + np.cross(r["x"], r["P"])).sum(axis=0) for r in rows])
    turned = float(np.abs(rows[-1]["omega"] - rows[0]["omega"]).max())  # the spring's torques acted
    return dict(P_drift=float(np.abs(P - P[0]).max()), P_scale=float(np.abs(rows[0]["P"]).max()),
                J_drift=float(np.abs(J - J[0]).max()), J_scale=float(np.abs(J[0]).max()), turned=turned)


def main():
    # Taichi's advanced IR optimisations off (rigid.runtime's quick_compile): these runs judge the
    # method (orders, conservation, closed forms) to tolerances far above round-off, and with them
    # off the float64 kernels compile ~3x faster in a fresh clone (the many-body worker: 83 -> 22 s,
    # the physics worker: 31 -> 12 s; every number the tests read agrees to round-off). Float32
    # tests and the command line run the default set-up.
    init_taichi("cpu", fp64=True, quick_compile=True)
    units = load_units(ROOT / "rigid_body_dynamic.py")
    euler, symplectic = head_on_simulator(units, "euler"), head_on_simulator(units, "symplectic")
    octahedra = octahedra_simulator(units)
    out = dict(momentum=head_on(euler, 1e-3, 60, 0.0),
               angular=head_on(symplectic, 1e-3, 60, 0.5),
               euler_coarse=head_on(euler, 1e-3, 60, 0.5),
               euler_fine=head_on(euler, 5e-4, 60, 0.5),
               restitution=[restitution(octahedra, c) for c in (10.0, 20.0)],
               springs=spring_pair(spring_pair_simulator(units), 60))
    print(json.dumps(out))


if __name__ == "__main__":
    main()
