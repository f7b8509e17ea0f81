"""Figures for the report: plain matplotlib, one function per figure, PNG at fixed DPI.

Each takes arrays (no simulation here) and a path; the same data gives the same
bytes (Agg is deterministic and we strip the timestamped metadata).
"""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

DPI = 110
PNG_META = {"Software": None}


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=DPI, metadata=PNG_META)
    plt.close(fig)


def energy_momentum(traj: dict, title: str, path) -> None:
    """Kinetic, potential and total energy; |P| and |L| over time."""
    t = traj["t"]
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.2))
    kinetic, potential = traj["kinetic_energy"], traj["potential_energy"]
    a.plot(t, kinetic, label="kinetic")
    a.plot(t, potential, label="potential (gravity + springs)")
    a.plot(t, kinetic + potential, "k", lw=1.5, label="total")
    a.set_xlabel("t (s)"), a.set_ylabel("energy (J)"), a.legend(fontsize=7), a.set_title(title, fontsize=9)
    b.plot(t, np.linalg.norm(traj["P"], axis=1), label="|P| (kg m/s)")
    b.plot(t, np.linalg.norm(traj["L"], axis=1), label="|L| (kg m²/s)")
    b.set_xlabel("t (s)"), b.legend(fontsize=7), b.set_title("momenta", fontsize=9)
    _save(fig, path)


def side_view(traj: dict, floor: float, wall: float, path) -> None:
    """Centre of mass in the x-y plane (seen from +z), with the box."""
    fig, ax = plt.subplots(figsize=(5, 4))
    x = traj["x"]
    ax.plot(x[:, 0], x[:, 1], lw=1)
    ax.plot(x[0, 0], x[0, 1], "go", label="start")
    ax.plot(x[-1, 0], x[-1, 1], "rs", label="end")
    ax.plot([-wall, -wall, wall, wall], [1, floor, floor, 1], "k", lw=2)
    ax.set_aspect("equal"), ax.set_xlabel("x (m)"), ax.set_ylabel("y (m)"), ax.legend(fontsize=7)
    ax.set_title("thrown sphere: centre of mass, side view", fontsize=9)
    _save(fig, path)


def flip(t, omega_sim, t_ref, omega_ref, period: float, reference_period: float, path) -> None:
    """Body-frame ω components, simulator (solid) vs scipy reference (dashed)."""
    fig, ax = plt.subplots(figsize=(9, 3.2))
    for k, c in enumerate("rgb"):
        ax.plot(t, omega_sim[:, k], c, lw=1.2, label=f"ω_{'xyz'[k]} simulator")
        ax.plot(t_ref, omega_ref[:, k], c + "--", lw=1, label=f"ω_{'xyz'[k]} reference")
    ax.set_xlabel("t (s)"), ax.set_ylabel("ω, body frame (rad/s)")
    ax.set_title(f"T-handle spun about its intermediate axis: flip period {period:.3f} s "
                 f"(reference {reference_period:.3f} s)", fontsize=9)
    ax.legend(fontsize=6, ncol=3)
    _save(fig, path)


def convergence(results: dict, path) -> None:
    """Error vs Δt on log-log axes, one line per integrator, with the fitted order."""
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for name, r in results.items():
        dts, err = np.asarray(r["dts"]), np.asarray(r["errors"])
        order = np.polyfit(np.log(dts), np.log(err), 1)[0]
        ax.loglog(dts, err, "o-", label=f"{name}: order {order:.2f}")
    ax.set_xlabel("Δt (s)"), ax.set_ylabel("error of ω at t = end (rad/s)")
    ax.set_title("convergence against scipy's solve_ivp", fontsize=9)
    ax.legend(fontsize=8), ax.grid(True, which="both", alpha=0.3)
    _save(fig, path)


def many_energy(t, kinetic, potential, title: str, path) -> None:
    """Total kinetic, potential and their sum over time (left); kinetic on a log scale (right)."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.2))
    a.plot(t, kinetic, label="kinetic")
    a.plot(t, potential, label="potential (gravity + springs)")
    a.plot(t, kinetic + potential, "k", lw=1.5, label="total")
    a.set_xlabel("t (s)"), a.set_ylabel("energy (J)"), a.legend(fontsize=7), a.set_title(title, fontsize=9)
    b.semilogy(t[1:], kinetic[1:], "C0")  # row 0: at rest, 0 J
    b.set_xlabel("t (s)"), b.set_ylabel("kinetic energy (J)"), b.grid(True, which="both", alpha=0.3)
    b.set_title("kinetic energy, log scale", fontsize=9)
    _save(fig, path)
