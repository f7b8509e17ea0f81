"""Physics experiments on a Simulator, each judged against ``rigid.science.reference``.

Every function takes ``get_sim(**config) -> Simulator`` (a reconfigured, reset
simulator, e.g. ``SimulatorCache`` below or the tests' ``sim_cache``) and
returns plain numbers (floats, lists): the measurement beside its reference.
The physics tests (in a float64 subprocess) and scripts/validate.py call these.

The bodies: the T-handle (assets/t_handle.obj, vertex particles, principal
axes = coordinate axes, I_x < I_y < I_z, so y is the intermediate axis) in free
flight, and the handout's sphere bouncing in the box.
"""
from __future__ import annotations

import numpy as np

from . import reference as ref
from ..config import ASSETS, SimConfig

# particle_mass 0.7, not 1: a missing mass factor would hide behind m = 1.
T_HANDLE = dict(mesh=str(ASSETS / "t_handle.obj"), scale=1.0, walls=False, particle_mass=0.7)
FLIP_W0 = (0.0, 6.0, 1.5)  # rad/s: about the intermediate axis y, far enough from the separatrix
#                            that the flip period is not hypersensitive (as in tumbling_t_handle.toml)
TUMBLE_W0 = (0.4, 0.3, 3.0)  # rad/s, world = body at t = 0: a generic tumble near the stable axis 3


class SimulatorCache:
    """get(**config) -> Simulator, compiled once per (mesh, particles, integrator, ...)."""

    def __init__(self, units, fp64: bool):
        self.units, self.fp64, self.sims = units, fp64, {}

    def __call__(self, **config):
        from ..engine.simulator import Simulator

        runtime = {k: v for k, v in config.items() if k in Simulator.RUNTIME_KEYS}
        fixed = {k: v for k, v in config.items() if k not in Simulator.RUNTIME_KEYS}
        key = tuple(sorted((k, repr(v)) for k, v in fixed.items()))
        if key not in self.sims:
            self.sims[key] = Simulator(SimConfig(fp64=self.fp64, **fixed).validate(), self.units)
        defaults = SimConfig()
        reset = {k: getattr(defaults, k) for k in Simulator.RUNTIME_KEYS}
        return self.sims[key].reconfigure(**{**reset, **runtime})


def body_row(snapshot: dict, body: int = 0) -> dict:
    """One body's part of a snapshot: its vectors (3,) and (4,) instead of (B, 3) and (B, 4)."""
    return {key: (value[body] if isinstance(value, np.ndarray) and value.ndim == 2 else value)
            for key, value in snapshot.items()}


def record(sim, rows: int, substeps_per_row: int) -> dict:
    """Snapshots at rows + 1 times (row 0 = now), float64 arrays; adds R (3x3) and n (substeps)."""
    out = {}
    for i in range(rows + 1):
        if i:
            sim.step_frame(substeps_per_row)
        snap = dict(body_row(sim.snapshot()), R=sim.state.R.to_numpy()[0].astype(np.float64), n=i * substeps_per_row)
        for key, value in snap.items():
            out.setdefault(key, []).append(value)
    return {key: np.asarray(value, dtype=np.float64) for key, value in out.items()}


def rotation_health(traj: dict) -> dict:
    """Largest | |q| − 1 | and ‖RᵀR − E‖₂ (spectral norm) over a recorded trajectory."""
    q_norm = np.abs(np.linalg.norm(traj["q"], axis=1) - 1.0)
    orth = np.linalg.norm(np.einsum("tji,tjk->tik", traj["R"], traj["R"]) - np.eye(3), ord=2, axis=(1, 2))
    return dict(q_norm_error=float(q_norm.max()), orthonormality_error=float(orth.max()))


def free_fall(get_sim, integrator: str, dt: float = 1e-3, rows: int = 20, substeps: int = 50) -> dict:
    """Free flight under gravity: P against P0 + M g t, x against both Euler parabolas and the true one."""
    g, x0, v0 = (0.7, -9.8, 0.4), (0.1, 0.2, -0.3), (0.5, 3.0, -1.0)
    sim = get_sim(**T_HANDLE, integrator=integrator, dt=dt, gravity=g, position=x0,
                  initial_velocity=v0, initial_angular_velocity=(0.3, 1.0, 2.0))
    traj = record(sim, rows, substeps)
    mass, n, t = sim.model.mass, traj["n"], traj["n"] * dt
    p_exact = mass * (np.asarray(v0) + np.outer(t, g))
    x_continuous = np.asarray(x0) + np.outer(t, v0) + 0.5 * np.outer(t * t, g)
    scale_p, scale_x = np.abs(p_exact).max(), np.abs(x_continuous).max()
    return dict(
        momentum_error=float(np.abs(traj["P"] - p_exact).max() / scale_p),
        explicit_parabola_error=float(np.abs(traj["x"] - ref.explicit_euler_free_fall(x0, v0, g, dt, n)).max() / scale_x),
        semi_implicit_parabola_error=float(np.abs(traj["x"] - ref.semi_implicit_free_fall(x0, v0, g, dt, n)).max() / scale_x),
        continuous_parabola_error=float(np.linalg.norm(traj["x"] - x_continuous, axis=1).max()),
        continuous_bound=float(0.5 * np.linalg.norm(g) * dt * t[-1]),  # |g| Δt t / 2: the Euler parabolas' offset
        energy_drift=_relative_drift(traj), mass=float(mass),
        energy_change=float(traj["kinetic_energy"][-1] + traj["potential_energy"][-1]
                            - traj["kinetic_energy"][0] - traj["potential_energy"][0]),
    )


def angular_momentum_drift(get_sim, integrator: str = "euler", duration: float = 10.0, dt: float = 1e-3,
                           body: dict = T_HANDLE) -> dict:
    """Torque-free (gravity on, no walls): max |L(t) − L0| / |L0| over ``duration``.

    Thrown off the origin and sideways, so x is never parallel to g: a torque taken about
    the world origin (p × f instead of r × f) would change L by x × M g.
    """
    sim = get_sim(**body, integrator=integrator, dt=dt, gravity=(0.0, -9.8, 0.0),
                  position=(0.3, 0.2, -0.1), initial_velocity=(1.0, 2.0, 0.5),
                  initial_angular_velocity=TUMBLE_W0)
    rows = 50
    traj = record(sim, rows, int(round(duration / dt / rows)))
    drift = np.linalg.norm(traj["L"] - traj["L"][0], axis=1) / np.linalg.norm(traj["L"][0])
    return dict(L_drift=float(drift.max()), **rotation_health(traj))


def rotational_energy_drift(get_sim, integrator: str, dts, duration: float = 10.0) -> dict:
    """Torque-free: relative change of ½ L·ω over ``duration`` at each Δt, and the ratios per halving."""
    drifts = []
    for dt in dts:
        sim = get_sim(**T_HANDLE, integrator=integrator, dt=dt, gravity=(0.0, 0.0, 0.0),
                      initial_angular_velocity=TUMBLE_W0)
        e0 = 0.5 * body_row(sim.snapshot())["L"].dot(body_row(sim.snapshot())["omega"])
        sim.step_frame(int(round(duration / dt)))
        snap = body_row(sim.snapshot())
        drifts.append(float((0.5 * snap["L"].dot(snap["omega"]) - e0) / e0))
    return dict(dts=list(dts), drifts=drifts, ratios=[a / b for a, b in zip(drifts, drifts[1:])])


def accuracy(get_sim, integrator: str, dts, duration: float = 2.0, checkpoints: int = 4,
             omega0=TUMBLE_W0) -> dict:
    """Errors of ω(t) and q(t) against scipy's Euler equations; max over the checkpoints."""
    times = duration * np.arange(1, checkpoints + 1) / checkpoints
    w_ref = q_ref = None
    errors_w, errors_q = [], []
    for dt in dts:
        sim = get_sim(**T_HANDLE, integrator=integrator, dt=dt, gravity=(0.0, 0.0, 0.0),
                      initial_angular_velocity=tuple(omega0))
        if w_ref is None:
            w_ref, q_ref, _ = ref.torque_free_rotation(sim.model.inertia_body_np[0], omega0, times)
        traj = record(sim, checkpoints, int(round(duration / checkpoints / dt)))
        errors_w.append(float(np.linalg.norm(traj["omega"][1:] - w_ref, axis=1).max() / np.linalg.norm(omega0)))
        errors_q.append(float(ref.quaternion_distance(traj["q"][1:], q_ref).max()))
    return dict(dts=list(dts), omega_errors=errors_w, q_errors=errors_q,
                omega_orders=ref.order_of_convergence(dts, errors_w),
                q_orders=ref.order_of_convergence(dts, errors_q))


def body_omega(traj: dict) -> np.ndarray:
    """ω in the body frame, Rᵀ ω, (T, 3)."""
    return np.einsum("tji,tj->ti", traj["R"], traj["omega"])


def flip(get_sim, integrator: str = "euler", dt: float = 1e-3, omega0=FLIP_W0,
         duration: float = 9.0) -> dict:
    """The intermediate-axis flip: period of ω_y (body) from its zero crossings vs Landau's K(k)."""
    sim, traj = flip_run(get_sim, integrator, dt, omega0, duration)
    return flip_period(sim, traj, omega0)


def flip_run(get_sim, integrator: str = "euler", dt: float = 1e-3, omega0=FLIP_W0,
             duration: float = 9.0) -> tuple:
    """The T-handle spun about its intermediate axis, without gravity: (sim, its trajectory sampled
    every 10 ms), for ``flip_period`` and for a figure of the same run."""
    sim = get_sim(**T_HANDLE, integrator=integrator, dt=dt, gravity=(0.0, 0.0, 0.0),
                  initial_angular_velocity=tuple(omega0))
    rows = int(round(duration * 100))  # a sample every 10 ms
    return sim, record(sim, rows, int(round(0.01 / dt)))


def flip_period(sim, traj: dict, omega0=FLIP_W0) -> dict:
    """``flip``'s numbers from a ``flip_run``."""
    crossings = ref.zero_crossings(traj["t"], body_omega(traj)[:, 1])
    # Two sign changes per period: the full periods are crossings[i + 2] − crossings[i].
    measured = float(np.mean(crossings[2:] - crossings[:-2])) if len(crossings) >= 3 else float("nan")
    inertia = np.diag(sim.model.inertia_body_np[0])
    return dict(crossings=crossings.tolist(), period=measured,
                reference_period=ref.torque_free_period(inertia, omega0),
                off_diagonal_inertia=float(np.abs(sim.model.inertia_body_np[0] - np.diag(inertia)).max()))


def axis_stability(get_sim, axis: int, integrator: str = "euler", dt: float = 1e-3, spin: float = 6.0,
                   tilt: float = 0.05, duration: float = 9.0) -> dict:
    """Spin about body axis ``axis`` tilted by ``tilt`` rad: the largest angle ω_body makes with it."""
    omega0 = np.full(3, spin * tilt / np.sqrt(2))
    omega0[axis] = spin
    sim = get_sim(**T_HANDLE, integrator=integrator, dt=dt, gravity=(0.0, 0.0, 0.0),
                  initial_angular_velocity=tuple(omega0))
    traj = record(sim, int(round(duration * 20)), int(round(0.05 / dt)))
    w = body_omega(traj)
    angle = np.arccos(np.clip(np.abs(w[:, axis]) / np.linalg.norm(w, axis=1), -1.0, 1.0))
    return dict(initial_angle=float(angle[0]), max_angle=float(angle.max()))


def bounce_energy(get_sim, integrator: str | None = None, duration: float = 10.0, damping: bool = True,
                  **extra) -> dict:
    """The handout's sphere thrown into the box: total energy (kinetic + gravity + springs) per frame.

    ``integrator`` None keeps the config's default (explicit Euler) and so shares its compiled sim.
    """
    config = dict(position=(0.0, 0.3, 0.0), initial_velocity=(2.0, 1.0, -1.5),
                  initial_angular_velocity=(1.0, -2.0, 3.0), **extra)
    if integrator is not None:
        config["integrator"] = integrator
    if not damping:
        config.update(velocity_damping_stiffness=0.0, friction_stiffness=0.0)
    sim = get_sim(**config)
    traj = record(sim, int(round(duration * 60)), sim.substeps)
    energy = traj["kinetic_energy"] + traj["potential_energy"]
    return dict(energy=energy.tolist(), initial_kinetic=float(traj["kinetic_energy"][0]),
                mass=float(sim.model.mass), dt=float(sim.config.dt),
                substeps=int(sim.substeps), gravity=list(sim.config.gravity), **rotation_health(traj),
                relative_change=float((energy[-1] - energy[0]) / abs(energy[0])))


def symmetric_drop(get_sim, integrator: str = "euler", duration: float = 3.0, grid: int = 10,
                   position=(0.3, 0.2, -0.2)) -> dict:
    """The handout's sphere, volume-sampled (a flat base: a stable rest), dropped with no spin
    on the vertical line through ``position`` (off the box's centre, so a torque taken about the
    world origin instead of the centre of mass would show). Largest horizontal drift and |ω|."""
    sim = get_sim(particles="volume", grid=grid, integrator=integrator, position=tuple(position))
    traj = record(sim, int(round(duration * 60)), sim.substeps)
    drift = np.linalg.norm(traj["x"][:, [0, 2]] - np.asarray(position)[[0, 2]], axis=1)
    spin = np.linalg.norm(traj["omega"], axis=1)
    return dict(max_horizontal_drift=float(drift.max()), max_spin=float(spin.max()),
                final_spin=float(spin[-1]), lowest_y=float(traj["x"][:, 1].min()),
                particles=int(sim.model.num_particles), **rotation_health(traj))


def _relative_drift(traj: dict) -> float:
    energy = traj["kinetic_energy"] + traj["potential_energy"]
    return float((energy[-1] - energy[0]) / abs(energy[0]))
