"""A body that left the box: its centre of mass past a wall or below the floor.

The walls are penalty springs: a particle of mass m arriving at speed v goes v·√(m/k) deep
before the spring (collision_stiffness k) stops it, damping aside. At the defaults (m = 1 kg,
k = 1e4 N/m) that is 1 cm per m/s, so a body thrown at 1000 m/s (``--v0 1000 0 0``) crosses
the wall within a frame and flies on outside. Nothing in the energy shows it (the body just
keeps its kinetic energy), so the blow-up check misses it; this one reads the centres of mass
in the rows the Simulator returns. The box has no ceiling: up is free.
"""
from __future__ import annotations

import math

import numpy as np

MARGIN = 0.25  # × wall: how far past a wall a centre of mass may go (a deep, fast contact) before it counts


def first_escape(block: dict, config, previous: dict | None = None) -> tuple[int, str, str] | None:
    """(row, what happened, the fix) for the first row of the block in which a body's centre of
    mass lies more than MARGIN·wall past a wall or below the floor; None if all stay in.
    ``previous``: the row before the block (its speed is the speed the body arrived with)."""
    if not config.walls:
        return None
    x = np.asarray(block["x"], dtype=np.float64)
    frames = x.shape[0]
    x = x.reshape(frames, -1, 3)  # (F, B, 3)
    wall, floor = float(config.wall), float(config.floor)
    past = np.stack([np.abs(x[..., 0]) - wall, floor - x[..., 1], np.abs(x[..., 2]) - wall], axis=-1)  # (F, B, 3)
    out = (past > MARGIN * wall).any(axis=(1, 2))
    if not out.any():
        return None
    row = int(np.argmax(out))
    body, axis = np.unravel_index(int(np.argmax(past[row])), past[row].shape)
    depth = float(past[row, body, axis])
    if axis == 1:
        plane = f"the floor y = {floor:g}"
    else:
        side = "+" if x[row, body, axis] > 0 else "-"
        plane = f"the wall {'xyz'[axis]} = {side}{wall:g}"
    who = "the body" if x.shape[1] == 1 else f"body {body + 1}"
    before = block["v"][row - 1] if row else (previous["v"] if previous is not None else block["v"][0])
    speed = float(np.linalg.norm(np.asarray(before, dtype=np.float64).reshape(-1, 3)[body]))
    masses = [b.get("particle_mass", config.particle_mass) for b in config.bodies] or [config.particle_mass]
    m, k = max(masses), float(config.collision_stiffness)
    depth_to_stop = speed * math.sqrt(m / k) if k > 0 else math.inf
    what = (f"{who} left the box: its centre of mass is {depth:.3g} m past {plane}, moving at {speed:.3g} m/s "
            f"(the walls' spring stops a particle within v·√(m/k) = {depth_to_stop:.3g} m)")
    fix = "throw it slower, or raise collision_stiffness (with a smaller --dt), or use --no-walls for free flight"
    return row, what, fix
