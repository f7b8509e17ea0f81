"""Trajectory rows, the NPZ export, and blow-up detection (a block of frames at a time).

Export contract (one row per rendered frame, row 0 the initial state):
``t`` (F,), ``x`` (F,3), ``q`` (F,4 scalar first), ``v`` (F,3), ``omega`` (F,3 world),
``P`` (F,3), ``L`` (F,3), ``kinetic_energy`` (F,), ``potential_energy`` (F,), and
``mass``, ``inertia_body`` (3,3, I0 about the centre of mass), ``dt``, ``substeps``.
``potential_energy`` is gravity's −M g·x plus the contact springs' ½ k depth².
"""
from __future__ import annotations

import math
import zipfile

import numpy as np

from .atomic import atomic_output

ROW_KEYS = ("t", "x", "q", "v", "omega", "P", "L", "kinetic_energy", "potential_energy")


class Trajectory:
    """Blocks of rows (``Simulator.advance_frames``), kept in memory until saved (~100 bytes per
    frame and body)."""

    def __init__(self, mass, inertia_body, dt: float, substeps: int, fp64: bool):
        """``mass`` (B,), ``inertia_body`` (B, 3, 3); blocks of (k, B, ...) rows. With one body the
        arrays drop the body axis (the NPZ contract: ``x`` (F, 3), ``mass`` a scalar)."""
        self.blocks: list[dict] = []
        self.num_rows = 0
        self.dtype = np.float64 if fp64 else np.float32
        mass, inertia_body = np.asarray(mass), np.asarray(inertia_body)
        self.one_body = mass.shape == (1,)
        if self.one_body:
            mass, inertia_body = mass[0], inertia_body[0]
        self.constants = dict(mass=np.asarray(mass, self.dtype),
                              inertia_body=np.asarray(inertia_body, self.dtype),
                              dt=np.asarray(dt, self.dtype), substeps=np.asarray(substeps, np.int64))

    def append_block(self, block: dict, rows: int | None = None) -> None:
        """Keep the block's first ``rows`` rows (all if None)."""
        rows = len(block["t"]) if rows is None else rows
        if rows:
            kept = {key: np.asarray(block[key])[:rows] for key in ROW_KEYS}
            if self.one_body:
                kept.update({key: kept[key][:, 0] for key in ROW_KEYS if kept[key].ndim == 3})
            self.blocks.append(kept)
            self.num_rows += rows

    def arrays(self) -> dict:
        out = {key: np.concatenate([block[key] for block in self.blocks]).astype(self.dtype) for key in ROW_KEYS}
        out.update(self.constants)
        return out

    def save(self, path) -> None:
        """Write the NPZ under a temporary name, then rename: never a half file."""
        with atomic_output(path) as tmp:
            write_npz(tmp, self.arrays())


def write_npz(path, arrays: dict) -> None:
    """np.savez, but byte-identical for identical arrays: np.savez stamps each member with
    the current time; we stamp a fixed date, so the same run gives the same file."""
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_STORED) as archive:
        for key, value in arrays.items():
            info = zipfile.ZipInfo(f"{key}.npy", date_time=(1980, 1, 1, 0, 0, 0))
            # ZIP64 headers only where a member needs them (> 2 GiB): CPython 3.11.2 and 3.11.7
            # write forced ZIP64 headers differently, and the same run must give the same bytes.
            big = np.asanyarray(value).nbytes > (1 << 31) - (1 << 20)
            with archive.open(info, "w", force_zip64=big) as member:
                np.lib.format.write_array(member, np.asanyarray(value), allow_pickle=False)


def first_blow_up(block: dict, initial_energy: float, energy_bound: float) -> tuple[int, str] | None:
    """The first row of a block that blew up, and what blew up in it; None if all look sane.
    Checked on the host, for a whole block at once: the kernels run with fast math, under
    which a NaN test on the device may be compiled away."""
    frames = len(block["t"])
    bad = np.zeros(frames, bool)
    for key in ("x", "q", "P", "L"):
        bad |= ~np.isfinite(np.asarray(block[key]).reshape(frames, -1)).all(axis=1)
    energy = block["kinetic_energy"] + block["potential_energy"]
    with np.errstate(invalid="ignore"):  # inf - inf in a row already marked
        bad |= ~np.isfinite(energy) | (energy - initial_energy > energy_bound)
    if not bad.any():
        return None
    first = int(np.argmax(bad))
    return first, blow_up({key: block[key][first] for key in block}, initial_energy, energy_bound)


def blow_up(row: dict, initial_energy: float, energy_bound: float) -> str | None:
    """Describe what blew up in this row, or None if it looks sane."""
    for key in ("x", "q", "P", "L"):
        if not np.all(np.isfinite(row[key])):
            return f"{key} became {'NaN' if np.any(np.isnan(row[key])) else 'infinite'}"
    energy = row["kinetic_energy"] + row["potential_energy"]
    if not math.isfinite(energy):
        return "the energy became non-finite"
    if energy - initial_energy > energy_bound:
        return (f"the energy grew from {initial_energy:.3g} J to {energy:.3g} J "
                f"(the contact springs are unstable)")
    return None


def stability_hint(config) -> str:
    """The likely fix: the integrator's stability bound for one particle's wall contact
    (spring and damper together, rigid.run.stability), naming the term that limits it.
    With several bodies the lightest particle sets the bound, for a contact between two of them."""
    from .stability import stability_message

    masses = [body.get("particle_mass", config.particle_mass) for body in getattr(config, "bodies", ())]
    return stability_message(config.dt, config.collision_stiffness, config.velocity_damping_stiffness,
                             min(masses or [config.particle_mass]), config.integrator,
                             pairs=bool(getattr(config, "many_bodies", False)))
