"""Sleeping bodies: a body at rest for a while stops being integrated, and costs next to nothing.

A body falls asleep when the speed bound of its particles, |v| + |ω| ρ_b (ρ_b its largest
particle offset), has stayed below ``sleep_speed`` for ``sleep_time`` seconds in a row; it is
then set exactly at rest (P = L = 0, so v = ω = 0: its kinetic energy is zero), its particles
placed at that pose (stages.set_at_rest), and left out:
no placement, no pair forces with other sleepers, no block forces, no update. It wakes when
- a *moving* awake body touches it (moving: its own speed bound at or above sleep_speed; a
  quiet awake body meets a sleeper as a static obstacle, so two quiet bodies in contact do
  not wake each other over and over): the toucher's pair stage marks it, and in the same
  substep the woken body's particles take their pair forces too (stage 3a's second pass), so
  the two sides are equal and opposite and momentum is conserved through the wake (with
  materials: material_stages.pair_wave, whose second pass also writes the resting sides' copies
  of the pairs' sticking springs, pair_slip.copy_to, so both copies stay the same);
- the host wakes it: an impulse (``Simulator.apply_impulse``, the window's kick), a grab
  (``Simulator.wake``), a change of a runtime parameter (gravity, walls, stiffnesses...) or a
  reset (which wakes every body).
Only scenes whose bodies collide with one another sleep (B > 1: a lone body never does, so its
trajectories and pinned exports are unchanged), with or without materials (a static body never
sleeps: it is never updated), and only under the Euler and symplectic schemes (RK4's stages
move every body). ``sleep = false`` (``--no-sleep``) turns it off
(sleep_speed 0: no body is ever quiet). Until a first body falls asleep the substeps are the
same bits with sleeping on or off; every decision is made from the state alone (no timing, no
thread order), so runs stay bit-reproducible either way.

State (StateArgs.sleep, [B] vec3 i32, per body): (asleep 0/1, substeps quiet in a row, woken
in this substep 0/1). World values (state.py): SLEEP_SPEED (m/s; 0: off), SLEEP_STEPS (the
quiet substeps before sleeping, sleep_time / Δt).
"""
import taichi as ti

from . import broadphase
from .matvec import norm
from .state import SLEEP_SPEED, SLEEP_STEPS  # defaults: state.SLEEP_SPEED_DEFAULT, SLEEP_TIME_DEFAULT


@ti.func
def resting(state: ti.template(), b):
    """Body b is asleep and was not woken in this substep: it is left out."""
    s = state.sleep[b]
    return s[0] != 0 and s[2] == 0


@ti.func
def asleep(state: ti.template(), b):
    return state.sleep[b][0] != 0


@ti.func
def speed_bound(state: ti.template(), scratch: ti.template(), b):
    """|v| + |ω| ρ_b: no particle of body b moves faster."""
    return norm(state.v[b]) + norm(state.omega[b]) * broadphase.body_radius(scratch, b)


@ti.func
def moving(state: ti.template(), world: ti.template(), scratch: ti.template(), b):
    """Whether awake body b wakes the sleepers it touches."""
    return speed_bound(state, scratch, b) >= world.values[SLEEP_SPEED]


@ti.func
def mark_woken(state: ti.template(), b):
    """A moving body touched sleeping body b (stores only 1: safe in parallel)."""
    state.sleep[b][2] = 1


@ti.func
def begin_update(state: ti.template(), b):
    """Before body b's update: a woken body is awake again, its quiet count restarts."""
    s = state.sleep[b]
    if s[2] != 0:
        state.sleep[b] = ti.Vector([0, 0, 0], ti.i32)


@ti.func
def end_update(state: ti.template(), world: ti.template(), scratch: ti.template(), b):
    """After body b's update: count its quiet substeps; return 1 when it falls asleep now (the
    caller then sets it at rest)."""
    s = state.sleep[b]
    fall = 0
    if speed_bound(state, scratch, b) < world.values[SLEEP_SPEED]:
        s[1] += 1
        if s[1] >= ti.cast(world.values[SLEEP_STEPS], ti.i32):
            s[0] = 1
            fall = 1
    else:
        s[1] = 0
    state.sleep[b] = s
    return fall


@ti.func
def wake(state: ti.template(), b):
    state.sleep[b] = ti.Vector([0, 0, 0], ti.i32)
