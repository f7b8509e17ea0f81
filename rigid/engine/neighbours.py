"""Verlet neighbour lists: the pair candidates of every particle, reused across substeps.

Rebuilding the grid and walking 27 cells every substep cost most of a many-body substep (the
125-sphere pile: 14 candidates a particle, 74 % of them its own body's, 1.5 % in contact). So
each particle keeps a list of the other bodies' particles within r_a + r_b + skin of it, made
from the grid (grid.py, cells of the largest diameter + the skin) and reused until some
particle has moved more than half the skin from where it was at the build: until then no pair
can have closed from beyond reach + skin to within reach, so every pair in contact is in the
list (Verlet 1967; the classic rebuild test). Own-body candidates never enter the list.

The list of particle i is nbr_list[i·K .. i·K + nbr_count[i]) (K = its length / N), in the
grid walk's order, so each sum over it has a fixed order and runs are bit-reproducible; it is
symmetric (j in i's list iff i in j's: the test is the same bits both ways). A particle with
more than K candidates keeps only its count, and its sum walks the build's grid again around
the cell of its build position, testing the candidates' current positions: the same
candidates in the same order, so the same bits as an unlimited list (no contact is dropped).

Scratch arrays (ScratchArgs): ``nbr_count`` [N] i32, ``nbr_list`` [N·K] i32 (particle slots),
``build_x`` [N] vec3 (world positions at the last build), ``nbr_flags`` [1] i32 (1: rebuild at
the next placement), ``nbr_params`` = (skin, (skin/2)²) float.
"""
import taichi as ti

from . import grid

NEIGHBOURS_PER_PARTICLE = 16  # list slots per particle; beyond, the particle walks the grid (exact)
SKIN_FRACTION = 0.4  # skin = this × the largest particle diameter (measured: 0.3-0.5 is flat)


@ti.func
def note_motion(scratch: ti.template(), state: ti.template(), i):
    """Ask for a rebuild if slot i has moved more than half the skin since the last build (a
    NaN counts as moved). Writers only ever store 1, so running in parallel is safe."""
    d = state.particle_x[i] - scratch.build_x[i]
    if not (d.dot(d) <= scratch.nbr_params[1]):
        scratch.nbr_flags[0] = 1


@ti.func
def rebuild_gate(scratch: ti.template()):
    """1 when the lists must be rebuilt this substep, else 0: the build's loops run over
    ``n * gate`` items, so that in a parallel kernel they stay top-level loops."""
    return scratch.nbr_flags[0]


@ti.func
def build_list(model: ti.template(), state: ti.template(), scratch: ti.template(), i):
    """Slot i's candidates from the freshly built grid: other bodies' particles within reach + skin."""
    a = model.particle_body[i]
    p, r_a = state.particle_x[i], model.particle_radius[a]
    skin = scratch.nbr_params[0]
    stride = scratch.nbr_list.shape[0] // state.particle_x.shape[0]
    n = 0
    g = grid.cell_coords(scratch, p)
    for dz in range(-1, 2):
        for dy in range(-1, 2):
            for part in range(3):
                lo, hi = grid.row_range(scratch, g[0], g[1] + dy, g[2] + dz, part)
                for slot in range(lo, hi):
                    b = scratch.sorted_body[slot]
                    if b != a:
                        d = scratch.sorted_x[slot] - p
                        reach = r_a + model.particle_radius[b] + skin
                        if d.dot(d) < reach * reach:
                            if n < stride:
                                scratch.nbr_list[i * stride + n] = scratch.sorted_particle[slot]
                            n += 1
    scratch.nbr_count[i] = n
    scratch.build_x[i] = p


@ti.func
def clear_flag(scratch: ti.template()):
    scratch.nbr_flags[0] = 0


@ti.func
def list_stride(scratch: ti.template(), state: ti.template()):
    return scratch.nbr_list.shape[0] // state.particle_x.shape[0]
