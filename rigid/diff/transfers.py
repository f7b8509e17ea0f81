"""Copies between the host and a tape's fields (rigid.diff.tape), one serial launch each.

A field's ``from_numpy``, ``to_numpy`` or ``fill`` is a Taichi kernel of its own, compiled for
that field and launched on the thread pool: loading a new tape that way (its ~25 fixed-data and
parameter fields, each its own compile) took about a second, and a checkpoint's six fields two
launches apiece. Here a tape's fields are laid end to end in one flat float64 array (``layout``)
and copied by one kernel (``copier``), compiled once per tape; integer fields travel as floats
(exact: counts and indices far below 2^53).
"""

import numpy as np
import taichi as ti

ROW_COLUMNS = dict(x=(0, 3), q=(3, 7), v=(7, 10), omega=(10, 13), P=(13, 16), L=(16, 19))  # a row's 19 numbers


def layout(fields) -> tuple[list, int]:
    """``fields`` end to end: [(field, start, shape, n)] (n: a vector's width, 0 for a scalar), and
    the numbers they hold."""
    entries, start = [], 0
    for f in fields:
        n = getattr(f, "n", 0)
        entries.append((f, start, tuple(f.shape), n))
        start += int(np.prod(f.shape)) * max(n, 1)
    return entries, start


def copier(entries, into_fields: bool):
    """A kernel copying a flat array to (``into_fields``) or from the fields of ``entries``
    (``layout``'s: 0-D, 1-D or 2-D, scalars or vectors), each field's numbers in C order."""

    @ti.kernel
    def copy(a: ti.types.ndarray()):
        for f, c0, shape, n in ti.static(entries):
            if ti.static(len(shape) == 0):
                for c in ti.static(range(max(n, 1))):
                    if ti.static(n == 0 and into_fields):
                        f[None] = ti.cast(a[c0], f.dtype)
                    elif ti.static(n == 0):
                        a[c0] = f[None]
                    elif ti.static(into_fields):
                        f[None][c] = ti.cast(a[c0 + c], f.dtype)
                    else:
                        a[c0 + c] = f[None][c]
            else:
                ti.loop_config(serialize=True)
                for I in ti.grouped(ti.ndrange(*shape)):
                    k = 0
                    for d in ti.static(range(len(shape))):
                        k = k * shape[d] + I[d]
                    for c in ti.static(range(max(n, 1))):
                        if ti.static(n == 0 and into_fields):
                            f[I] = ti.cast(a[c0 + k], f.dtype)
                        elif ti.static(n == 0):
                            a[c0 + k] = f[I]
                        elif ti.static(into_fields):
                            f[I][c] = ti.cast(a[c0 + k * n + c], f.dtype)
                        else:
                            a[c0 + k * n + c] = f[I][c]

    return copy


def row_kernels(row_fields: dict, zeroed: list) -> dict:
    """zero: the ``zeroed`` adjoints to zero; seed: an array (frames, B, 19) into the rows'
    adjoints; rows: the rows into such an array (columns as ROW_COLUMNS)."""
    rows = [(f, ROW_COLUMNS[key][0], f.n) for key, f in row_fields.items()]

    @ti.kernel
    def zero():
        for f in ti.static(zeroed):
            if ti.static(f.shape == ()):
                f[None] = ti.zero(f[None])
            else:
                ti.loop_config(serialize=True)
                for I in ti.grouped(ti.ndrange(*f.shape)):
                    f[I] = ti.zero(f[I])

    @ti.kernel
    def seed(a: ti.types.ndarray()):
        ti.loop_config(serialize=True)
        for f, b in ti.ndrange(a.shape[0], a.shape[1]):
            for field, c0, n in ti.static(rows):
                field.grad[f, b] = ti.Vector([ti.cast(a[f, b, c0 + c], field.dtype) for c in ti.static(range(n))])

    @ti.kernel
    def read_rows(a: ti.types.ndarray()):
        ti.loop_config(serialize=True)
        for f, b in ti.ndrange(a.shape[0], a.shape[1]):
            for field, c0, n in ti.static(rows):
                for c in ti.static(range(n)):
                    a[f, b, c0 + c] = field[f, b][c]

    return dict(zero=zero, seed=seed, rows=read_rows)


def padded(field, array, fill=0.0) -> np.ndarray:
    """``array`` (leading axis: bodies, particles or planes) as the leading part of the 1-D
    ``field``'s values; the rest is ``fill`` (a quaternion's: the identity)."""
    array = np.asarray(array, np.float64)
    full = np.full((field.shape[0],) + array.shape[1:], fill)
    if array.ndim == 2 and array.shape[1] == 4:
        full[:] = (1.0, 0.0, 0.0, 0.0)
    full[:len(array)] = array
    return full
