"""Rows written by the device: every body's state and the contact energy after each frame.

A run of many frames is launched in chunks (one graph launch per chunk, not one
call per frame); after each frame a row kernel writes the next row, and the host
reads the chunk's rows back in one copy. So the frame loop does no per-frame host
work: a blow-up is found in the rows (rigid.run.runner), and the export keeps them.

    rows = FrameRows(num_bodies)       # capacity: the frames one chunk may write
    record = make_record_kernel(rows, state, num_particles, particle_energy)
    chunks = ChunkGraphs(frame_kernel, record)   # frame_kernel(n): one frame of n substeps
    rows.rewind(); chunks.run(n, k); rows.read(k) -> (body (k, B, 19), contact energy (k,))

A body's row is x (3), q (4), v (3), ω (3), P (3), L (3), in that order (``LAYOUT``).
The contact energy (the springs' ½ k depth²) is summed over the particles serially,
in index order, by the same loop as before rows existed, and the frame kernels are
the same as a frame-by-frame run's, so a chunked run's numbers are bit-identical to
frame-by-frame calls (LLVM vectorises a kernel as a whole: a frame loop inside the
substep kernel changed the torus's torque sums in the last bit). Energies from these
numbers are computed on the host (rigid.engine.simulator).
"""
import numpy as np
import taichi as ti

from .graphs import RepeatedGraphs

LAYOUT = (("x", 3), ("q", 4), ("v", 3), ("omega", 3), ("P", 3), ("L", 3))
ROW_WIDTH = sum(width for _name, width in LAYOUT)  # 19
MAX_FRAMES = 1024  # per chunk
MAX_FLOATS = 1 << 20  # the buffer's size cap (4 MiB in float32): many bodies get fewer frames per chunk


def capacity_for(num_bodies: int) -> int:
    """Frames one chunk may write: a power of two up to MAX_FRAMES, the buffer under MAX_FLOATS numbers."""
    frames = max(1, min(MAX_FRAMES, MAX_FLOATS // (num_bodies * ROW_WIDTH)))
    return 1 << (frames.bit_length() - 1)


class FrameRows:
    def __init__(self, num_bodies: int):
        self.num_bodies = num_bodies
        self.capacity = capacity_for(num_bodies)
        self.body = ti.field(float, shape=(self.capacity, num_bodies, ROW_WIDTH))
        self.contact_energy = ti.field(float, shape=self.capacity)
        self.next_slot = ti.field(ti.i32, shape=())
        body, energy = self.body, self.contact_energy

        @ti.kernel
        def copy_out(out: ti.types.ndarray(), energy_out: ti.types.ndarray()):
            # Only the rows written (a field's to_numpy would copy the whole capacity).
            for f, b, c in ti.ndrange(out.shape[0], out.shape[1], out.shape[2]):
                out[f, b, c] = body[f, b, c]
            for f in range(energy_out.shape[0]):
                energy_out[f] = energy[f]

        self._copy_out = copy_out
        self._dtype = np.float64 if ti.lang.impl.current_cfg().default_fp == ti.f64 else np.float32

    def rewind(self) -> None:
        """The next row written is row 0."""
        self.next_slot[None] = 0

    def read(self, frames: int) -> tuple[np.ndarray, np.ndarray]:
        """Rows 0..frames-1 as float64: (frames, B, ROW_WIDTH) and the contact energy (frames,)."""
        out = np.empty((frames, self.num_bodies, ROW_WIDTH), self._dtype)
        energy = np.empty(frames, self._dtype)
        self._copy_out(out, energy)
        return out.astype(np.float64), energy.astype(np.float64)


def make_record_kernel(rows: FrameRows, state, num_particles: int, particle_energy, parallel_energy=False):
    """A kernel writing the next row: every body's state and Σᵢ ``particle_energy(i)`` (a ti.func),
    summed serially in particle order. ``parallel_energy``: compute the terms in parallel first
    (for GPUs, where one thread would search every particle's neighbours; the sum of stored
    terms may be vectorised by LLVM, so on a CPU it is off and the numbers stay the serial loop's)."""
    s, body, energy, next_slot = state, rows.body, rows.contact_energy, rows.next_slot
    num_bodies = rows.num_bodies
    terms = ti.field(float, shape=max(num_particles, 1)) if parallel_energy else None

    @ti.kernel
    def record():
        if ti.static(parallel_energy):
            for i in range(num_particles):
                terms[i] = particle_energy(i)
        total = 0.0
        ti.loop_config(serialize=True)
        for i in range(num_particles):
            if ti.static(parallel_energy):
                total += terms[i]
            else:
                total += particle_energy(i)
        slot = next_slot[None]
        energy[slot] = total
        for b in range(num_bodies):
            x, q, v, w, P, L = s.x[b], s.q[b], s.v[b], s.omega[b], s.P[b], s.L[b]
            for c in ti.static(range(3)):
                body[slot, b, c] = x[c]
                body[slot, b, 7 + c] = v[c]
                body[slot, b, 10 + c] = w[c]
                body[slot, b, 13 + c] = P[c]
                body[slot, b, 16 + c] = L[c]
            for c in ti.static(range(4)):
                body[slot, b, 3 + c] = q[c]
        next_slot[None] = slot + 1

    return record


class ChunkGraphs:
    """Frames in chunks: a graph per power of two p dispatches p × (``frame_kernel(n)``,
    ``record()``), so a chunk of k frames is one launch per binary digit of k (graphs.py)."""

    def __init__(self, frame_kernel, record):
        self._graphs = RepeatedGraphs(repeated=[(frame_kernel, True), (record, False)])

    def run(self, substeps: int, frames: int) -> None:
        bit = 1
        while bit <= frames:
            if frames & bit:
                self._graphs.run(bit, n=substeps)
            bit <<= 1


def split_rows(body: np.ndarray) -> dict:
    """(k, B, ROW_WIDTH) rows as named arrays (k, B, width): x, q, v, omega, P, L."""
    out, start = {}, 0
    for name, width in LAYOUT:
        out[name] = body[:, :, start:start + width]
        start += width
    return out
