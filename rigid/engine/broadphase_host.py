"""The host's side of the broadphase's arrays (broadphase.py): made for a scene, set at a reset
and between chunks (the skin, the rebuild flag), read by the Simulator, the benchmarks and the
tests, every value by its slot's name."""
from __future__ import annotations

import numpy as np
import taichi as ti

from . import broadphase as bp
from . import neighbours, refresh
from .arrays import IntCell, device_array, download, float_dtype, upload

NAMES = ("broadphase_ints", "broadphase_floats", "broadphase_body_ints", "broadphase_body_floats")
# What a chunk changes and a run keeps (list_growth.py's copy): all but the float scalars (the
# skin, set between chunks, and the motion test's reductions, made again each substep).
KEPT = ("broadphase_ints", "broadphase_body_ints", "broadphase_body_floats")


def make_arrays(model, shape, diameter: float, skin_fraction: float) -> dict:
    """The four arrays for ``model`` and a grid of GridShape ``shape``, its cells of the largest
    particle ``diameter`` plus ``skin_fraction`` of it (the skin, skin.py); the rebuild flag is
    raised at the Simulator's reset (``reset``)."""
    ints = np.zeros(bp.INTS, np.int32)
    ints[[bp.GRID_DIM, bp.GRID_CELLS, bp.GRID_CHUNKS]] = shape.dim, shape.num_cells, shape.num_chunks
    table = ti.ndarray(float_dtype(), (model.num_bodies, bp.BODY_FLOATS))
    upload(table, body_floats(model))
    return dict(broadphase_ints=device_array(ints, dtype=ti.i32),
                broadphase_floats=device_array(float_values(diameter, skin_fraction)),
                broadphase_body_ints=ti.ndarray(ti.i32, (bp.BODY_INTS, model.num_bodies + 1)),
                broadphase_body_floats=table)


def float_values(diameter: float, skin_fraction: float) -> np.ndarray:
    """broadphase_floats for a skin of ``skin_fraction`` diameters (the reductions zero)."""
    skin = skin_fraction * diameter
    values = np.zeros(bp.FLOATS)
    values[bp.INV_CELL] = 1.0 / (diameter + skin)
    values[bp.SKIN] = skin
    values[bp.ALLOWED] = neighbours.ALLOWED_MOTION * skin
    values[bp.R_MAX] = 0.5 * diameter
    values[bp.MAX_REFRESHED] = refresh.REFRESH_FRACTION
    values[bp.FULL_BUILD_COST] = refresh.BUILD_COST
    return values


def body_floats(model) -> np.ndarray:
    """broadphase_body_floats at the start: ρ_b, each body's largest particle offset |r0| (rounded
    up), the rest zero (the pose is set at the first build)."""
    norms = np.linalg.norm(model.r0_np, axis=1)
    table = np.zeros((model.num_bodies, bp.BODY_FLOATS))
    table[:, bp.RHO] = [norms[s:s + c].max() * (1 + 1e-6) + 1e-9
                        for s, c in zip(model.body_start_np, model.body_count_np)]
    return table


def reset(arrays: dict, model) -> None:
    """A Simulator's reset: the lists built at the next placement, every body's floats as at the
    start, no touches counted (part_cut.py)."""
    request_rebuild(arrays)
    upload(arrays["broadphase_body_floats"], body_floats(model))
    table = download(arrays["broadphase_body_ints"])
    table[bp.TOUCHES] = 0
    upload(arrays["broadphase_body_ints"], table)


def request_rebuild(arrays: dict) -> None:
    """A full build of the lists at the next placement."""
    arrays["broadphase_ints"][bp.REBUILD] = 1


def set_skin(arrays: dict, diameter: float, fraction: float) -> None:
    """The lists' skin ``fraction`` diameters from the next placement on (a full build there)."""
    upload(arrays["broadphase_floats"], float_values(diameter, fraction))
    request_rebuild(arrays)


def cell(arrays: dict, what: int) -> IntCell:
    """The int scalar ``what`` (broadphase.REBUILD, BUILDS, OVERFLOW ...), read and written often."""
    return IntCell(arrays["broadphase_ints"], what)


def int_value(arrays: dict, what: int) -> int:
    return int(download(arrays["broadphase_ints"])[what])


def float_value(arrays: dict, what: int) -> float:
    """The float scalar ``what`` (broadphase.INV_CELL, SKIN, ALLOWED ...)."""
    return float(download(arrays["broadphase_floats"])[what])


def builds(arrays: dict) -> int:
    """Full builds of the lists so far."""
    return int_value(arrays, bp.BUILDS)


def refreshes_so_far(sim) -> int:
    """How many substeps refreshed some lists in part (benchmarks: refreshes per substep)."""
    return int_value(sim._scratch_arrays, bp.REFRESHES) if sim.many else 0


def active_list(arrays: dict) -> np.ndarray:
    """The slots the pair stage visits (those with a candidate at the last build or refresh)."""
    return download(arrays["active"])[:int_value(arrays, bp.ACTIVE)]


def body_ints(arrays: dict, what: int) -> np.ndarray:
    """(B,) the per-body list ``what`` (broadphase.PART, REFRESH_STATE, TOUCHES ...)."""
    return download(arrays["broadphase_body_ints"])[what, :-1]


def body_float_values(arrays: dict, what: int) -> np.ndarray:
    """(B,) each body's float ``what`` (broadphase.RHO, MOTION, REACH ...)."""
    return download(arrays["broadphase_body_floats"])[:, what]
