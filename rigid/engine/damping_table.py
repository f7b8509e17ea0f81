"""The damping table ζ'(e, h, β): the damper ratio to ask of an integration scheme, on the host.

Each contact is a clamped damped oscillator (materials.py). In its own units (time 1/ω, length
v0/ω, v0 the approach speed at first touch, ω = √(k / m_eff)) the overlap d obeys

    d'' = γ − max(0, d + 2ζ d'),   d(0) = 0, d'(0) = 1,   inside while d > 0,

with γ = g_n / (ω v0) the constant load along the normal (gravity's part into a plane) in those
units. It leaves at d = 0 with speed e(ζ, γ); with γ = 0 that is ``clamped_restitution``.
Gravity pushes the body in during the contact, so e falls with γ at a given ζ, and a dropped
ball needs a smaller ζ than a thrown one to bounce at e (ζ 1.24 at γ = 0, 0.64 at γ = 0.02 for
e = 0.1). The table's third axis is β = γ / e, the load against the exit speed asked for: ζ is
smooth in β where it is steep in γ (at small e a little load already matters).

A contact that moves back in after it began to move out (d' > 0 again, before leaving) has not
bounced: it counts as e = 0 here, and the engine then damps it as a resting contact (β = 0).
One whose energy ½ d'² + ½ d² − γ d falls below 0 cannot come out (the damper and the clamp
only take energy) and counts as e = 0 too.

ζ'(e, h, β) is found for each node by bisection on ln ζ', running the scheme's own clamped
oscillator with step h (explicit Euler gains energy on a spring, symplectic Euler loses a
little, both end a contact on a step); h = 0 (and RK4 at every h) is the continuous oscillator,
from symplectic Euler at h = 0.02 and 0.01 extrapolated to h → 0 (Richardson; 1e-4 from the
closed form at γ = 0). ζ' never exceeds the step's limit 1 / (2h) (c ≤ m_eff / Δt); an e the
scheme cannot reach gets that limit.

Its cost is the time loop: a node at h = 0.005 takes 600 to 8,000 steps a probe, one after the
other. So each bisection step is one run of every node's oscillators together (discrete and both
continuous ones, ``loaded_restitution``), endings checked every _CHUNK steps; the continuous
probes run once per distinct (ζ', γ) (RK4's columns share them); the load-free ζ once per e.
The values are the same bit for bit as one oscillator at a time (each element's arithmetic is
its own run's). The package ships the three schemes' tables (damping_tables.npz, with this
source's fingerprint; ``python -m rigid.engine.damping_table`` makes them again), so a run with
materials reads them instead of computing them at start-up.
"""
from __future__ import annotations

import functools
import hashlib
import math
from pathlib import Path

import numpy as np

ZETA_DEAD = 1e6  # e = 0: more damping than any step takes, i.e. the step's limit
NUM_E = 41  # e = 0, 0.025, ..., 1
H_GRID = (0.0, 0.005, 0.01, 0.02, 0.03, 0.05, 0.07, 0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 1.0)
NUM_H = len(H_GRID)
# β = γ / e nodes, interpolated linearly in √β (ζ falls fastest at small β). Beyond BETA_MAX
# a contact is damped as without load: its bounce would rise less than half the static sag
# g / ω² (rise = e² v0² / 2g < δ_s / (2 β²)), and there e(ζ) is too steep to aim at.
BETA_GRID = (0.0, 0.025, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.85, 1.0)
BETA_MAX = BETA_GRID[-1]
ROOT_BETA = tuple(math.sqrt(b) for b in BETA_GRID)
NUM_B = len(BETA_GRID)
_CONTINUOUS = (0.02, 0.01)  # symplectic Euler steps extrapolated to h → 0 (2e-4 of e)
_HORIZON = 40.0  # time (1/ω) after which a contact still inside counts as captured
_CHUNK = 16  # steps between the checks for endings (each check costs a few steps' work)
_BISECTIONS = 14  # on ln ζ' over [1e-6, 2 ζ(e, 0) + 1]: 1e-3 relative


def clamped_restitution(zeta: float) -> float:
    """e of a contact x'' = −ω² x − 2ζω x' whose force may not pull (ω = 1, entering at speed 1):
    the speed when ω² x + 2 ζ ω x' first reaches 0."""
    if zeta <= 0.0:
        return 1.0
    if zeta < 1.0:
        wd = math.sqrt(1.0 - zeta * zeta)
        # force ∝ e^{−ζt} [(1 − 2ζ²)/ωd sin φ + 2ζ cos φ], φ = ωd t: first zero in (0, π]
        phi = math.pi - math.atan2(2.0 * zeta * wd, 1.0 - 2.0 * zeta * zeta)
        t = phi / wd
        return -math.exp(-zeta * t) * (math.cos(phi) - zeta * math.sin(phi) / wd)
    zeta = max(zeta, 1.0 + 1e-9)
    s = math.sqrt(zeta * zeta - 1.0)
    r1, r2 = -zeta + s, -zeta - s  # x = (e^{r1 t} − e^{r2 t}) / 2s
    a, b = 1.0 + 2.0 * zeta * r1, 1.0 + 2.0 * zeta * r2  # force ∝ a e^{r1 t} − b e^{r2 t}
    t = math.log(b / a) / (r1 - r2)
    return -(r1 * math.exp(r1 * t) - r2 * math.exp(r2 * t)) / (2.0 * s)


def damping_ratio(e: float) -> float:
    """ζ whose clamped contact (no load) gives restitution e (ZETA_DEAD for e = 0)."""
    e = float(e)
    if e >= 1.0:
        return 0.0
    if e <= 0.0:
        return ZETA_DEAD
    lo, hi = 0.0, 1.0
    while clamped_restitution(hi) > e:  # e(ζ) falls monotonically; e(1) = 0.135, e(5) = 0.009
        hi *= 2.0
        if hi > ZETA_DEAD:
            return ZETA_DEAD
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if clamped_restitution(mid) > e else (lo, mid)
    return 0.5 * (lo + hi)


def loaded_restitution(zeta, load, h, symplectic) -> np.ndarray:
    """e of the clamped oscillator with load γ (``load``) and step ``h``, stepped by symplectic
    Euler (velocity first) where ``symplectic`` is true, explicit Euler elsewhere; arrays of one
    shape. All elements step together, _CHUNK steps at a time with the state of each step kept;
    then each element's first ending in the chunk is found at once (separation: e = its outward
    speed; moving back in, its energy gone, or past the horizon: e = 0), and the ended ones are
    dropped. The arithmetic of every step is a lone element's, so its e is too, bit for bit."""
    zeta, load, h = (np.array(a, np.float64).ravel() for a in np.broadcast_arrays(zeta, load, h))
    symplectic = np.broadcast_to(np.asarray(symplectic, bool), zeta.shape).ravel()
    out = np.zeros(zeta.size)
    index = np.arange(zeta.size)
    damper = 2.0 * zeta
    d, u = np.zeros(zeta.size), np.ones(zeta.size)  # overlap, inward speed
    moving_out = np.zeros(zeta.size, bool)  # has moved out at some step before
    steps = np.ceil(_HORIZON / h)  # per element
    n0 = 0
    while index.size:
        D, U = np.empty((_CHUNK, index.size)), np.empty((_CHUNK, index.size))
        mixed, explicit = not symplectic.all() and symplectic.any(), not symplectic.any()
        for j in range(_CHUNK):
            c = damper
            if n0 + j == 1:  # the first step inside: damped for the part of the step since the touch, as the engine
                c = damper * np.minimum(d / (u * h), 1.0)
            force = np.maximum(d + c * u, 0.0)
            force *= d > 0  # none outside
            np.add(u, h * (load - force), out=U[j])
            if mixed:
                np.add(d, h * np.where(symplectic, U[j], u), out=D[j])
            else:
                np.add(d, h * (u if explicit else U[j]), out=D[j])
            d, u = D[j], U[j]
        going_out = U < 0
        left = (D <= 0) & going_out
        before = np.logical_or.accumulate(np.concatenate([moving_out[None], going_out[:-1]]), axis=0)
        ended = (left | (before & (U > 0)) | (0.5 * U * U + 0.5 * D * D < load * D)
                 | ((n0 + np.arange(_CHUNK))[:, None] >= steps))
        first = ended.argmax(axis=0)
        done = ended[first, np.arange(index.size)]
        leaving = done & left[first, np.arange(index.size)]
        out[index[leaving]] = -U[first[leaving], np.flatnonzero(leaving)]
        keep = ~done
        moving_out = (moving_out | going_out.any(axis=0))[keep]
        damper, load, h, steps, index, symplectic = (a[keep] for a in (damper, load, h, steps, index, symplectic))
        d, u = D[-1][keep], U[-1][keep]
        n0 += _CHUNK
    return out


def _restitution(zeta, load, h, scheme: str) -> np.ndarray:
    """e at step h for ``scheme`` (h = 0, and RK4 at every h: the continuous oscillator, by
    Richardson extrapolation), all elements in one ``loaded_restitution`` run; the continuous
    ones once per distinct (ζ, γ) (RK4's h columns share most of theirs)."""
    zeta, load, h = (a.ravel() for a in np.broadcast_arrays(*(np.asarray(a, np.float64) for a in (zeta, load, h))))
    cont = (h == 0) | (scheme == "rk4")
    disc = np.flatnonzero(~cont)
    pairs, inverse = np.unique(np.stack([zeta[cont], load[cont]], axis=1), axis=0, return_inverse=True)
    m = len(pairs)
    e = loaded_restitution(np.concatenate([zeta[disc], pairs[:, 0], pairs[:, 0]]),
                           np.concatenate([load[disc], pairs[:, 1], pairs[:, 1]]),
                           np.concatenate([h[disc], np.full(m, _CONTINUOUS[0]), np.full(m, _CONTINUOUS[1])]),
                           np.concatenate([np.full(disc.size, scheme != "euler"), np.ones(2 * m, bool)]))
    out = np.empty(zeta.size)
    out[disc] = e[:disc.size]
    coarse, fine = e[disc.size:disc.size + m], e[disc.size + m:]
    out[cont] = (2.0 * fine - coarse)[inverse.ravel()]
    return out


def _load_free(scheme: str, zeta_free: np.ndarray) -> np.ndarray:
    """The β = 0 layer (NUM_E, NUM_H), as this engine made it before the load: ζ'(e) sampled on
    400 ζ' per h and interpolated (bit for bit the same damping for pairs and resting contacts);
    ``zeta_free``: the continuous ζ(e) at the NUM_E values of e."""
    es = np.linspace(0.0, 1.0, NUM_E)
    table = np.repeat(np.minimum(zeta_free, ZETA_DEAD)[:, None], NUM_H, axis=1)
    if scheme == "rk4":
        return np.minimum(table, np.array([ZETA_DEAD] + [0.5 / h for h in H_GRID[1:]]))
    for j, h in enumerate(H_GRID[1:], start=1):
        limit = 0.5 / h  # c <= m_eff / Δt
        zetas = np.concatenate([[0.0], np.geomspace(1e-4, limit, 400)])
        e_of = _unloaded(zetas, h, scheme)
        order = np.argsort(-e_of, kind="stable")  # the smallest ζ' giving e, the limit if none does
        table[:, j] = np.where(es <= e_of.min(), limit, np.interp(-es, -e_of[order], zetas[order]))
    return table


def _unloaded(zetas: np.ndarray, h: float, scheme: str) -> np.ndarray:
    """e of the clamped oscillator without load, leaving where its force first clamps to 0."""
    x, v = np.zeros_like(zetas), -np.ones_like(zetas)
    out, live = np.zeros_like(zetas), np.ones(zetas.shape, bool)
    for _ in range(int(40.0 / h) + 2):
        f = np.where(x < 0, np.maximum(-x - 2.0 * zetas * v, 0.0), 0.0)
        if scheme == "euler":
            x, v = x + h * v, v + h * f
        else:
            v = v + h * f
            x = x + h * v
        left = live & (v > 0) & ((x >= 0) | (f == 0))
        out[left] = v[left]
        live &= ~left
        if not live.any():
            break
    return out


SCHEMES = ("euler", "symplectic", "rk4")
SHIPPED = Path(__file__).with_name("damping_tables.npz")  # the three tables, made by ``python -m rigid.engine.damping_table``


def _fingerprint() -> str:
    """What the tables depend on: this module's source (its constants and its arithmetic), its
    line endings normalised (a Windows checkout's CRLF is the same source)."""
    return hashlib.sha256(Path(__file__).read_bytes().replace(b"\r\n", b"\n")).hexdigest()


@functools.lru_cache(maxsize=4)
def damping_table(scheme: str) -> np.ndarray:
    """(NUM_E, NUM_H, NUM_B) ζ' per (e, h = ω Δt, β = γ / e) for ``scheme``: the package's copy
    (SHIPPED) when it was made by this source, else computed (``compute_damping_table``, about
    half a second a scheme: a start-up cost of every run with materials, which the copy saves;
    tests/test_damping_table.py checks the copy against the computation)."""
    try:
        with np.load(SHIPPED) as tables:
            if str(tables["fingerprint"]) == _fingerprint():
                return np.array(tables[scheme])
    except (OSError, KeyError, ValueError):
        pass
    return compute_damping_table(scheme)


def compute_damping_table(scheme: str) -> np.ndarray:
    """The table ``damping_table`` gives for ``scheme``, computed; RK4: the continuous ζ at every
    h (within the step's limit)."""
    e, h, beta = np.meshgrid(np.linspace(0.0, 1.0, NUM_E), np.array(H_GRID), np.array(BETA_GRID), indexing="ij")
    load = beta * e
    limit = np.where(h > 0, 0.5 / np.maximum(h, 1e-300), ZETA_DEAD)
    table = np.where(e <= 0, limit, 0.0)
    # The bracket's top: the load only lowers ζ, and the scheme's correction is O(h) (a wider
    # one would probe contacts creeping out over hundreds of time units).
    zeta_free = np.array([damping_ratio(x) for x in np.linspace(0.0, 1.0, NUM_E)])  # once per e, not per node
    top = np.minimum(limit, 2.0 * zeta_free[:, None, None] + 1.0)
    loaded = (e > 0) & (beta > 0)
    ends = _restitution(np.concatenate([np.zeros(loaded.sum()), top[loaded]]), np.tile(load[loaded], 2),
                        np.tile(h[loaded], 2), scheme).reshape(2, -1)  # at ζ' = 0 and at the top, one run
    todo, reachable = np.zeros(e.shape, bool), np.zeros(e.shape, bool)
    todo[loaded] = ends[0] > e[loaded]  # ζ' = 0 overshoots e
    reachable[loaded] = todo[loaded] & (ends[1] <= e[loaded])
    table[todo & ~reachable] = limit[todo & ~reachable]  # the deadest contact the step allows
    lo, hi = np.full(e.shape, math.log(1e-6)), np.log(top)
    for _ in range(_BISECTIONS):  # the smallest ζ' whose e is at most the target
        mid = 0.5 * (lo + hi)
        over = _restitution(np.exp(mid[reachable]), load[reachable], h[reachable], scheme) > e[reachable]
        lo[reachable] = np.where(over, mid[reachable], lo[reachable])
        hi[reachable] = np.where(over, hi[reachable], mid[reachable])
    table[reachable] = np.exp(hi[reachable])
    table[:, :, 0] = _load_free(scheme, zeta_free)
    return table


def write_shipped(path: Path = SHIPPED) -> None:
    """Compute the three schemes' tables and write them, with this source's fingerprint, to ``path``."""
    tables = {scheme: compute_damping_table(scheme) for scheme in SCHEMES}
    temporary = path.with_suffix(".tmp.npz")
    np.savez_compressed(temporary, fingerprint=np.array(_fingerprint()), **tables)
    temporary.replace(path)


if __name__ == "__main__":
    write_shipped()
    print(f"wrote {SHIPPED}")
