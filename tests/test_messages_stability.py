"""The blow-up hint's Δt bound (issue 15, item 2): spring and damper together, per integrator,
checked against the spectral radius of each scheme's amplification matrix; the term that
limits it is named."""
import numpy as np
import pytest

CASES = [  # (k, c, m): the handout's defaults (overdamped), underdamped, critical, one term alone
    (1e4, 1e3, 1.0), (1e4, 50.0, 1.0), (1e4, 200.0, 1.0), (1e4, 1e3, 0.05), (3e5, 40.0, 2.0),
    (1e4, 0.0, 1.0), (0.0, 1e3, 1.0)]


def amplification(scheme, h, k, c, m):
    """One step's map of (x, v) for m x'' = -k x - c x', built from the scheme itself."""
    J = np.array([[0.0, 1.0], [-k / m, -c / m]])
    if scheme == "euler":
        return np.eye(2) + h * J
    if scheme == "symplectic":  # v first, then x with the new v
        kick = np.array([[1.0, 0.0], [-h * k / m, 1 - h * c / m]])
        drift = np.array([[1.0, h], [0.0, 1.0]])
        return drift @ kick
    Z = h * J
    return np.eye(2) + Z + Z @ Z / 2 + Z @ Z @ Z / 6 + Z @ Z @ Z @ Z / 24


def radius(scheme, h, k, c, m):
    return max(abs(np.linalg.eigvals(amplification(scheme, h, k, c, m))))


@pytest.mark.parametrize("scheme", ["euler", "symplectic", "rk4"])
@pytest.mark.parametrize("k, c, m", CASES)
def test_bound_is_where_the_spectral_radius_passes_one(scheme, k, c, m):
    from rigid.run.stability import stable_dt

    bound = stable_dt(k, c, m, scheme).dt
    if scheme == "euler" and c == 0:  # explicit Euler on an undamped spring: no stable step
        assert bound == 0
        assert all(radius(scheme, h, k, c, m) > 1 for h in (1e-6, 1e-4, 1e-2))
        return
    assert 0 < bound < np.inf
    for h in np.linspace(0.01, 0.999, 40) * bound:
        assert radius(scheme, h, k, c, m) <= 1 + 1e-9, (h, bound)
    assert radius(scheme, 1.002 * bound, k, c, m) > 1 + 1e-9


def test_bound_holds_for_any_set_of_touching_particles():
    """A rigid body's contact modes are no lighter than one particle: the eigenvalues of
    J_c M^-1 J_c^T are at most 1/m for random bodies and random touching subsets."""
    rng = np.random.default_rng(1)
    for _ in range(50):
        n, m = rng.integers(4, 40), rng.uniform(0.1, 3.0)
        r = rng.normal(size=(n, 3)) * rng.uniform(0.1, 2.0, size=3)
        r -= r.mean(axis=0)
        inertia = m * (np.eye(3) * np.einsum("ij,ij", r, r) - r.T @ r)
        mass = np.block([[m * n * np.eye(3), np.zeros((3, 3))], [np.zeros((3, 3)), inertia]])
        rows = []  # each touching particle pushed along the floor's and maybe a wall's normal
        for i in rng.choice(n, size=rng.integers(1, n + 1), replace=False):
            for normal in np.eye(3)[rng.choice(3, size=rng.integers(1, 3), replace=False)]:
                rows.append(np.concatenate([normal, np.cross(r[i], normal)]))  # n . (v + w x r)
        Jc = np.array(rows)
        g = np.linalg.eigvalsh(Jc @ np.linalg.solve(mass, Jc.T))
        assert g.max() <= 1 / m * (1 + 1e-9)


def test_issue_case_names_the_damping():
    """--dt 0.015 --v0 0 -20 0 blew up and was told dt < 2/sqrt(k/m) = 0.02 s; the damper limits."""
    from rigid.config import SimConfig
    from rigid.run.diagnostics import stability_hint

    hint = stability_hint(SimConfig(dt=0.015, initial_velocity=(0, -20, 0)).validate())
    assert hint.startswith("try --dt 0.001 (now 0.015): explicit Euler keeps the wall contacts stable")
    assert "dt < 0.00202 s" in hint and "normal damping limits it" in hint
    assert "velocity_damping_stiffness" in hint and "0.02 s" not in hint


@pytest.mark.parametrize("changes, words", [
    (dict(velocity_damping_stiffness=50.0), ["dt < 0.005 s", "contact spring limits it", "c/k"]),
    (dict(velocity_damping_stiffness=0.0), ["gains energy on an undamped contact spring"]),
    (dict(integrator="symplectic", velocity_damping_stiffness=0.0, collision_stiffness=1e5),
     ["dt < 0.00632 s", "contact spring limits"]),
    (dict(integrator="symplectic"), ["dt < 0.00198 s", "normal damping limits it"]),
    (dict(integrator="rk4"), ["dt < 0.00281 s", "normal damping limits it"]),
    (dict(dt=1e-3), ["try a smaller --dt (now 0.001): it is within the 0.00202 s"]),
    (dict(collision_stiffness=0.0, velocity_damping_stiffness=0.0), ["try a smaller --dt (now 0.015)"]),
    (dict(count=2), ["a contact between two bodies' particles stable", "for dt < 0.00101 s",
                     "m = particle_mass/2 = 0.5"]),  # many bodies: the pair's reduced mass
])
def test_hint_per_regime(changes, words):
    from rigid.config import SimConfig
    from rigid.run.diagnostics import stability_hint

    hint = stability_hint(SimConfig(**{"dt": 0.015, **changes}).validate())
    for word in words:
        assert word in hint, hint
