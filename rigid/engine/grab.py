"""A body held by the mouse: a damped spring from one particle to a target point.

The window (rigid/view/grab.py) picks a particle under the cursor and moves the target with it;
the spring's force on that particle is a force at a point (forces.point_wrench), whose TODO 3
and TODO 4 terms are added to its body's sums in every scene, so it moves and spins the body
exactly as a contact at that particle would, and the momentum bookkeeping (ΔP = Σ f Δt, ΔL = Σ r × f Δt)
holds for it as for every other force. It is an external force: it changes P, L and the energy.

    f = k (target − p) − c v_p        (p, v_p: the grabbed particle's position and velocity)

Which particle, the target and k, c are runtime values in ``WorldArgs.values`` (slots GRAB_*:
kernel arguments, never constants baked into a kernel, so grabbing does not recompile); the
slot holds −1 when nothing is held. ``Params`` (state.py) keeps the host copy and uploads it.
"""
import math

import numpy as np


# Slots of WorldArgs.values (after the world's own, with room left for more of those).
GRAB_FIRST = 24
GRAB_SLOT, GRAB_TX, GRAB_TY, GRAB_TZ, GRAB_K, GRAB_C = range(GRAB_FIRST, GRAB_FIRST + 6)
GRAB_VALUES = 6

# Default spring for a body of mass M: 2 Hz on the whole mass (k = M ω², sagging g/ω² ≈ 6 cm
# under gravity), critically damped on it (c = 2 M ω). Explicit Euler needs Δt < 2 m_eff / c
# with m_eff >= ~M/4 at a body's surface: ~20 ms, far above any Δt a frame allows.
GRAB_HZ = 2.0


def released() -> np.ndarray:
    """The host values of no grab: slot −1."""
    values = np.zeros(GRAB_VALUES)
    values[0] = -1.0
    return values


def holding(slot: int, target, stiffness: float, damping: float) -> np.ndarray:
    """The host values that hold particle slot ``slot`` at ``target`` with spring k, damper c."""
    return np.array([float(slot), *np.asarray(target, float).reshape(3), float(stiffness), float(damping)])


def default_spring(body_mass: float) -> tuple[float, float]:
    """(k, c) for a body of mass ``body_mass``: see GRAB_HZ."""
    omega = 2.0 * math.pi * GRAB_HZ
    return body_mass * omega * omega, 2.0 * body_mass * omega
