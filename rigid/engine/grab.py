"""A body held by the mouse: a damped spring from one particle to a target point.

The window (rigid/view/grab.py) picks a particle under the cursor and moves the target with it;
the spring's force on that particle is one more particle force, whose TODO 3 and TODO 4 terms
are added to its block's sums (stages.py), so it moves and spins the body exactly as a contact
at that particle would, and the momentum bookkeeping (ΔP = Σ f Δt, ΔL = Σ r × f Δt)
holds for it as for every other force. It is an external force: it changes P, L and the energy.

    f = k (target − p) − c v_p        (p, v_p: the grabbed particle's position and velocity)

Which particle, the target and k, c are runtime values in ``WorldArgs.values`` (slots GRAB_*:
kernel arguments, never constants baked into a kernel, so grabbing does not recompile); the
slot holds −1 when nothing is held. ``Params`` (state.py) keeps the host copy and uploads it.
"""
import math

import numpy as np
import taichi as ti

from .matvec import matvec

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


@ti.func
def grab_share(u: ti.template(), model: ti.template(), world: ti.template(), start, end, x, R, v, omega):
    """The spring's terms in TODO 3 and TODO 4 for a block of slots start..end−1 of a body at
    (x, R, v, ω): those of the held particle if it is in the block, else zero. Summed once per
    block beside its particles' loop (a test per particle would slow the loop every frame)."""
    F = ti.Vector.zero(float, 3)
    tau = ti.Vector.zero(float, 3)
    i = ti.cast(world.values[GRAB_SLOT], ti.i32)
    if start <= i and i < end:
        r0 = ti.Vector([model.r0_x[i], model.r0_y[i], model.r0_z[i]])
        r = matvec(R, r0)
        p = x + r
        target = ti.Vector([world.values[GRAB_TX], world.values[GRAB_TY], world.values[GRAB_TZ]])
        f = world.values[GRAB_K] * (target - p) - world.values[GRAB_C] * (v + omega.cross(r))
        F = u.total_force_term(f)
        tau = u.torque_term(p, x, R, r0, f)
    return F, tau
