"""The argument packs the kernels take: which arrays each stage may read or write.

Kernels are compiled once per process and receive the data as Taichi ndarrays bundled
in argument packs (``ti.types.argpack``), one per role, so that a new Simulator (another
scene, other sizes) reuses them:

  ModelArgs    static model data (model.py)              read-only
  StateArgs    per-step state (state.py)                 written by every substep
  WorldArgs    runtime parameters and static colliders   read-only (changed between frames)
  ScratchArgs  forces, partial sums, the grid, RK4        rewritten every substep
  RowArgs      the rows a chunk of frames writes         written once per frame
  SurfaceArgs  the drawn meshes                          read when a frame is drawn

Each member is an ndarray of an element type and a number of dimensions; the element's
float is the run's precision, so the types are made after ``ti.init`` (and cached). Model,
State and World are documented in model.py and state.py, the grid's arrays in grid.py, the
neighbour lists' in neighbours.py, the broadphase's scalars and per-body tables (named slots
and columns, packed by kind and meaning) in broadphase.py; the rest of ScratchArgs, per
particle slot [N] (world frame): ``particle_f`` the pair force, ``particle_couple`` the pairs'
couple about the particle; per block [K]: ``block_energy`` its springs' energy (at a frame's
end), ``block_wrench`` its share of F (0..2) and τ (3..5, about the body's centre of mass);
[2B]: ``rk`` RK4's Y₀ (slots 0..B−1) and the weighted sum of its stages (slots B..2B−1), x, q,
P, L packed in 13 numbers; with materials,
``contacts`` [N + 2K + 2B] i32: each particle's pair contacts, each block's plane and pair
contacts, each body's of the last evaluation (material_stages.py; else one element; one
array, as the x64 backend takes at most 64 argument elements: a kernel taking every pack is at
that limit, so new per-run data goes at the end of an array of its kind, as the kept lists of
pair_slip.py at the end of ``contacts``). RowArgs: rows.py.
"""
from __future__ import annotations

import ctypes
import functools

import numpy as np
import taichi as ti


def float_dtype():
    """The run's float (ti.f32 or ti.f64), as set by ti.init."""
    return ti.lang.impl.current_cfg().default_fp


def host_float():
    """The numpy float of the run's precision (np.float32 or np.float64)."""
    return np.float64 if float_dtype() == ti.f64 else np.float32


def _element(kind: str):
    f = float_dtype()
    return {"f": f, "i": ti.i32, "v3": ti.types.vector(3, f), "v4": ti.types.vector(4, f),
            "v13": ti.types.vector(13, f), "v16": ti.types.vector(16, f), "m3": ti.types.matrix(3, 3, f),
            "v3i": ti.types.vector(3, ti.i32), "v4i": ti.types.vector(4, ti.i32), "v2i": ti.types.vector(2, ti.i32), "v6": ti.types.vector(6, f)}[kind]


def _pack_type(members: dict):
    """A factory of the argpack type (made on first use, after ti.init) with ``NAMES``."""

    @functools.cache
    def make():
        return ti.types.argpack(**{name: ti.types.ndarray(dtype=_element(kind), ndim=ndim)
                                   for name, (kind, ndim) in members.items()})

    make.NAMES = tuple(members)
    return make


ModelArgs = _pack_type(dict(
    r0_x=("f", 1), r0_y=("f", 1), r0_z=("f", 1), particle_body=("i", 1), body_start=("i", 1), body_count=("i", 1),
    particle_mass=("f", 1), particle_radius=("f", 1), body_mass=("f", 1),
    inertia_body=("m3", 1), inertia_body_inv=("m3", 1),
    block_start=("i", 1), block_count=("i", 1), block_body=("i", 1),
    block_centre=("v3", 1), block_bounds=("v4", 1), body_blocks=("v2i", 1),
    body_material=("v4", 1), body_world=("v4i", 1)))


StateArgs = _pack_type(dict(
    x=("v3", 1), q=("v4", 1), P=("v3", 1), L=("v3", 1), v=("v3", 1), omega=("v3", 1),
    R=("m3", 1), inertia_inv=("m3", 1), particle_x=("v3", 1), particle_v=("v3", 1), sleep=("v3i", 1),
    plane_slip=("v3", 1)))

WorldArgs = _pack_type(dict(values=("f", 1), planes=("v4", 1), springs=("v16", 1)))

ScratchArgs = _pack_type(dict(
    particle_f=("v3", 1), particle_couple=("v3", 1), block_energy=("f", 1), block_wrench=("v6", 1),
    cell_count=("i", 1), cell_start=("i", 1),
    sorted_particle=("i", 1), sorted_x=("v3", 1), sorted_body=("i", 1), sorted_run_end=("i", 1), chunk_total=("i", 1),
    broadphase_ints=("i", 1), broadphase_floats=("f", 1), nbr_count=("i", 1), nbr_list=("i", 1), build_x=("v3", 1),
    active=("i", 1), broadphase_body_ints=("i", 2), broadphase_body_floats=("f", 2),
    rk=("v13", 1), contacts=("i", 1)))

RowArgs = _pack_type(dict(body=("f", 3), contact_energy=("f", 2)))

SurfaceArgs = _pack_type(dict(surface_r0=("v3", 1), surface_body=("i", 1)))


_HOST = {"f32": np.float32, "f64": np.float64, "i32": np.int32, "u32": np.uint32, "i64": np.int64}


def _cpu_pointer(array):
    """The address of ``array``'s elements in this process's memory, or None (not the CPU
    backend, or a Taichi whose internals differ from 1.7's)."""
    if ti.lang.impl.current_cfg().arch != ti.x64:
        return None
    try:
        return int(ti.lang.impl.get_runtime().prog.get_ndarray_data_ptr_as_int(array.arr))
    except Exception:
        return None


def _layout(array):
    """(numpy dtype, shape) of ``array`` as to_numpy gives it: (n,) + the element's shape."""
    return _HOST[str(array.dtype)], tuple(array.shape) + tuple(array.arr.element_shape())


def byte_size(array) -> int:
    """How many bytes ``array``'s elements take."""
    dtype, shape = _layout(array)
    return int(np.prod(shape)) * np.dtype(dtype).itemsize


# Taichi's ndarray.from_numpy / to_numpy / fill (of vectors) launch a kernel that takes the
# ndarray as a template argument, so every array compiles (or loads and links) a kernel of its
# own: ~50 for a Simulator, about a second of every process's start-up. On the CPU the arrays
# live in this process's memory, so these copy bytes instead (AOS layout, as to_numpy reads it:
# tests/test_frame_chunks.py checks); other backends keep Taichi's kernels.

def upload(array, values) -> None:
    """array ← values (any shape with the array's number of elements; cast to its dtype)."""
    dtype, shape = _layout(array)
    values = np.ascontiguousarray(np.asarray(values).reshape(shape), dtype=dtype)
    pointer = _cpu_pointer(array)
    if pointer is None:
        array.from_numpy(values)
        return
    ti.sync()
    ctypes.memmove(pointer, values.ctypes.data, values.nbytes)


def download(array) -> np.ndarray:
    """A numpy copy of ``array``, shaped (n,) + the element's shape."""
    dtype, shape = _layout(array)
    pointer = _cpu_pointer(array)
    if pointer is None:
        return array.to_numpy()
    ti.sync()
    out = np.empty(shape, dtype)
    ctypes.memmove(out.ctypes.data, pointer, out.nbytes)
    return out


def clear(array) -> None:
    """array ← 0."""
    pointer = _cpu_pointer(array)
    if pointer is None:
        array.fill(0)
        return
    ti.sync()
    ctypes.memset(pointer, 0, byte_size(array))


class IntCell:
    """One element of an i32 ndarray, read and written often from the host (a flag, a counter):
    on the CPU through its address, found once (~1 µs; download() of the array ~8 µs, and more for
    a long one), elsewhere through Taichi. The array must live as long as this."""

    def __init__(self, array, index: int):
        self.array, self.index = array, index % array.shape[0]
        pointer = _cpu_pointer(array)
        self._cell = None if pointer is None else ctypes.c_int32.from_address(pointer + 4 * self.index)

    @property
    def on_cpu(self) -> bool:
        """Read through its address (cheap), not through Taichi."""
        return self._cell is not None

    @property
    def value(self) -> int:
        if self._cell is None:
            return int(self.array[self.index])
        ti.sync()
        return self._cell.value

    @value.setter
    def value(self, value: int) -> None:
        if self._cell is None:
            self.array[self.index] = value
            return
        ti.sync()
        self._cell.value = value


def device_array(values: np.ndarray, width: int = 0, dtype=None):
    """An ndarray holding ``values``: float (the run's precision) by default, vectors of
    ``width`` if width > 0, else scalars; at least one element (Taichi has no empty arrays)."""
    values = np.asarray(values)
    dtype = float_dtype() if dtype is None else dtype
    if width:
        values = values.reshape(-1, width)
        if len(values) == 0:
            values = np.zeros((1, width))
        array = ti.ndarray(ti.types.vector(width, dtype), len(values))
    else:
        values = values.reshape(-1)
        if len(values) == 0:
            values = np.zeros(1)
        array = ti.ndarray(dtype, len(values))
    upload(array, values)  # cast to the array's dtype there
    return array


def zeros(count: int, kind: str = "f"):
    """A zero ndarray of ``count`` (at least 1) elements of kind "f", "i", "v3", "v4", "v13", "v16", "m3"
    (Taichi fills a new ndarray with zeros)."""
    return ti.ndarray(_element(kind), max(int(count), 1))
