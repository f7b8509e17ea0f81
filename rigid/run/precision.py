"""Is float32 fine enough for this Δt? A substep adds Δt·v to the positions and Δt·g to the
velocities; where those increments come near float32's spacing of the numbers they are added
to, each addition rounds away a large part of them (below half the spacing: all of it).

Measured on the handout's drop (42 particles, 30 frames against the same run in float64): the
centre of mass is off by 0.6 mm at Δt = 1e-6, 4.7 mm at 3e-7, 13 mm and 8 J at 1e-7; at 1e-8
the energy is wrong by 0.1 J after a few frames and at 1e-9 the body stops falling after 4 mm
(P += Δt·F no longer changes P). Below Δt ≈ 1e-6 float32's round-off outgrows explicit Euler's
own O(Δt) error, so a convergence study there measures the rounding, not the scheme.

``float32_problem(config)`` refuses a run whose increment is under MARGIN times float32's
spacing for the scene's scales: positions of the box's size (or the body's start, if farther),
speeds up to v0 + ω0·scale or what a fall through twice that size reaches, the quaternion's
unit components turned at ω0.
"""
from __future__ import annotations

import math

EPS32 = 2.0 ** -23  # float32's spacing at 1 (numpy.finfo(numpy.float32).eps)
MARGIN = 8  # an increment under 8 spacings loses up to 1/16 of itself to rounding every substep


def float32_problem(config) -> str | None:
    """One line (without ``error:``) if the run's Δt is too small for float32, else None."""
    if config.fp64:
        return None
    bodies = [config.body_config(i) for i in range(config.num_body_entries)]
    size = max([1.0] + [max(abs(c) for c in b.position) for b in bodies]
               + ([config.wall, abs(config.floor)] if config.walls else []))
    g = math.sqrt(sum(c * c for c in config.gravity))
    spin = max(_norm(b.initial_angular_velocity) for b in bodies)
    speed = max([math.sqrt(2.0 * g * 2.0 * size)]
                + [_norm(b.initial_velocity) + _norm(b.initial_angular_velocity) * b.scale for b in bodies])
    dt = config.dt
    checks = []  # (smallest dt that passes, what a substep adds, to what)
    if speed > 0:
        checks.append((MARGIN * EPS32 * size / speed,
                       f"a substep moves the body Δt·v = {dt * speed:.2g} m, against float32's spacing "
                       f"{EPS32 * size:.2g} m of positions near {size:g} m"))
    if g > 0:
        checks.append((MARGIN * EPS32 * speed / g,
                       f"gravity adds Δt·|g| = {dt * g:.2g} m/s a substep, against float32's spacing "
                       f"{EPS32 * speed:.2g} m/s of speeds near {speed:.2g} m/s"))
    if spin > 0:
        checks.append((2.0 * MARGIN * EPS32 / spin,
                       f"a substep turns the quaternion by Δt·|ω|/2 = {dt * spin / 2:.2g}, against float32's "
                       f"spacing {EPS32:.2g} of its components near 1"))
    if not checks:
        return None
    smallest = max(c[0] for c in checks)
    if dt >= smallest:
        return None
    worst = max(checks, key=lambda c: c[0])[1]
    return (f"dt = {dt:g} is too small for float32: {worst} (under {MARGIN} spacings, rounding eats "
            f"the motion); "
            f"use --fp64 (float64), or --dt {_round_up(smallest):g} or larger")


def _norm(v) -> float:
    return math.sqrt(sum(float(c) ** 2 for c in v))


def _round_up(x: float) -> float:
    """x rounded up to two significant digits (the --dt to suggest)."""
    exponent = math.floor(math.log10(x)) - 1
    return math.ceil(x / 10 ** exponent) * 10 ** exponent
