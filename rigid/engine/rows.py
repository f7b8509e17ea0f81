"""Rows written by the device: every body's state and the contact energy after each frame.

A run of many frames is launched in chunks; after each frame the kernel writes the next
row, and the host reads a chunk's rows back in one copy. So the frame loop does no
per-frame host work: a blow-up is found in the rows (rigid.run.runner), and the export
keeps them. A body's row is x (3), q (4), v (3), ω (3), P (3), L (3), in that order
(``LAYOUT``); RowArgs: ``body`` [capacity, B, 19] float, ``contact_energy`` [capacity, W] float
(each world's springs' ½ k δ², summed over its particle slots in order; one world: W = 1). Energies from these numbers
are computed on the host (rigid.engine.simulator).
"""
import functools

import numpy as np
import taichi as ti

from .arrays import RowArgs, host_float

LAYOUT = (("x", 3), ("q", 4), ("v", 3), ("omega", 3), ("P", 3), ("L", 3))
ROW_WIDTH = sum(width for _name, width in LAYOUT)  # 19
MAX_FRAMES = 1024  # per chunk
MAX_FLOATS = 1 << 20  # the buffer's size cap (4 MiB in float32): many bodies get fewer frames per chunk


def capacity_for(num_bodies: int) -> int:
    """Frames one chunk may write: a power of two up to MAX_FRAMES, the buffer under MAX_FLOATS numbers."""
    frames = max(1, min(MAX_FRAMES, MAX_FLOATS // (num_bodies * ROW_WIDTH)))
    return 1 << (frames.bit_length() - 1)


class FrameRows:
    def __init__(self, num_bodies: int, worlds: int = 1):
        self.num_bodies, self.num_worlds = num_bodies, worlds
        self.capacity = capacity_for(num_bodies)
        fp = ti.lang.impl.current_cfg().default_fp
        self.body = ti.ndarray(fp, (self.capacity, num_bodies, ROW_WIDTH))
        self.contact_energy = ti.ndarray(fp, (self.capacity, worlds))
        self.args = RowArgs()(body=self.body, contact_energy=self.contact_energy)

    def read(self, frames: int) -> tuple[np.ndarray, np.ndarray]:
        """Rows 0..frames-1 as float64: (frames, B, ROW_WIDTH) and the contact energy (frames, W).
        Only those rows are copied (``copy_rows``; ``to_numpy`` would copy the capacity)."""
        host = host_float()
        body = np.empty((frames, self.num_bodies, ROW_WIDTH), host)
        energy = np.empty((frames, self.num_worlds), host)
        _copy_rows()(self.args, body, energy)
        return body.astype(np.float64), energy.astype(np.float64)


@functools.cache
def _copy_rows():
    """The kernel that copies the first rows out (made after ti.init, once per process)."""
    Rw = RowArgs()

    @ti.kernel
    def copy_rows(rows: Rw, out: ti.types.ndarray(), energy_out: ti.types.ndarray()):
        for f, b, c in ti.ndrange(out.shape[0], out.shape[1], out.shape[2]):
            out[f, b, c] = rows.body[f, b, c]
        for f, w in ti.ndrange(energy_out.shape[0], energy_out.shape[1]):
            energy_out[f, w] = rows.contact_energy[f, w]

    return copy_rows


@ti.func
def write_row(state: ti.template(), rows: ti.template(), slot):
    """Every body's state into row ``slot`` (the contact energies are written beside, per world)."""
    for b in range(state.x.shape[0]):
        x, q, v, w, P, L = state.x[b], state.q[b], state.v[b], state.omega[b], state.P[b], state.L[b]
        for c in ti.static(range(3)):
            rows.body[slot, b, c] = x[c]
            rows.body[slot, b, 7 + c] = v[c]
            rows.body[slot, b, 10 + c] = w[c]
            rows.body[slot, b, 13 + c] = P[c]
            rows.body[slot, b, 16 + c] = L[c]
        for c in ti.static(range(4)):
            rows.body[slot, b, 3 + c] = q[c]


def split_rows(body: np.ndarray) -> dict:
    """(k, B, ROW_WIDTH) rows as named arrays (k, B, width): x, q, v, omega, P, L."""
    out, start = {}, 0
    for name, width in LAYOUT:
        out[name] = body[:, :, start:start + width]
        start += width
    return out


def with_energies(rows: dict, contact: np.ndarray, times, gravity, moving_mass) -> dict:
    """A block of rows (split_rows) with ``t`` and the energies, float64, computed the same way for
    every block: kinetic ½ P·v + ½ L·ω, potential −M g·x of the moving bodies (``moving_mass`` (B,),
    0 for a static one) + the contact springs' (``contact`` (k,)). Rows of many worlds (k, W, B_w,
    width) give each world's energies, (k, W)."""
    P, v, L, omega, x = rows["P"], rows["v"], rows["L"], rows["omega"], rows["x"]
    lead = x.shape[:-2]  # (k,) or (k, W)
    kinetic = 0.5 * (P * v).reshape(*lead, -1).sum(axis=-1) + 0.5 * (L * omega).reshape(*lead, -1).sum(axis=-1)
    # Elementwise products and sums along each row's last axis only: a row's sum is then the same
    # operations in the same order wherever it sits in the block (BLAS's matrix-vector products
    # treat a block's last rows differently, so a row's last bits depended on its position).
    g = np.asarray(gravity, np.float64)
    height = x[..., 0] * g[0] + x[..., 1] * g[1] + x[..., 2] * g[2]  # (k, B) or (k, W, B_w): g·x of each body
    potential = -(height * np.asarray(moving_mass, np.float64).reshape(height.shape[1:])).sum(axis=-1) + contact
    return dict(t=np.asarray(times, np.float64), **rows, kinetic_energy=kinetic, potential_energy=potential)
