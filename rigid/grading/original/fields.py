"""One set of fields for every version of a file that the grader runs in one process.

runner.py runs each version of a submission (reference lines, the student's TODOs, other
parameters) as a new module, so each declares its fields again. A new field is a new
program for every kernel that names it: Taichi compiles, per field, the kernels that reach
it from Python (``from_numpy``, a ``[None] =`` write, the grader's snapshot), and the
file's own kernels cannot be found in its cache when only the fields differ. About a
third of a version's compile time went there.

``install(ti)`` (after the grader's ``ti.init``) makes the k-th field declaration of a
version return the k-th field of the first version that declared the same thing (kind,
element type, shape, layout, name), zeroed as a new field is (``new_version()``, called by
runner.run before each version, zeroes them all in one kernel). A declaration without a
shape (placed later with ``ti.root``), or that differs from the first version's k-th,
gets a new field. The versions run one after the other, each from zeroed fields, so a
version sees exactly what a fresh process would.
"""
_declared = []  # [(key or None, field)]: the first version's declarations, in order
_next = 0  # the current version's next declaration
_zero = None  # (number of fields it zeroes, the kernel)


def install(ti) -> None:
    from taichi.lang import impl
    from taichi.lang.matrix import Matrix

    scalar, matrix = impl._field, Matrix.field.__func__

    def scalar_field(dtype, *args, **kwargs):
        key = ("scalar", dtype, args, kwargs) if _kept(args, kwargs) else None
        return _declare(key, lambda: scalar(dtype, *args, **kwargs))

    def matrix_field(cls, n, m, dtype, *args, **kwargs):
        key = ("matrix", cls.__name__, n, m, dtype, args, kwargs) if _kept(args, kwargs) else None
        return _declare(key, lambda: matrix(cls, n, m, dtype, *args, **kwargs))

    impl._field = scalar_field  # ti.field's own call (impl.field), and ti.types' scalar fields
    Matrix.field = classmethod(matrix_field)  # ti.Vector.field, ti.Matrix.field, ti.types.vector(...).field


def _kept(args, kwargs) -> bool:
    """Whether a declaration's field may serve later versions: it has a shape (it is placed
    now), and no gradients (new_version zeroes the values only)."""
    shaped = (args[0] if args else kwargs.get("shape")) is not None
    return shaped and not kwargs.get("needs_grad") and not kwargs.get("needs_dual")


def _declare(key, make):
    global _next
    index, _next = _next, _next + 1
    try:
        key = repr(_plain(key)) if key is not None else None  # dtypes, shapes and names as text
    except Exception:
        key = None
    if index < len(_declared) and key is not None and _declared[index][0] == key:
        return _declared[index][1]
    field = make()
    if index == len(_declared):
        _declared.append((key, field))
    return field


def _plain(value):
    """``value`` with Taichi's data types by name (their repr is an address)."""
    if isinstance(value, (tuple, list)):
        return type(value)(_plain(v) for v in value)
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if hasattr(value, "to_string"):
        return f"dtype {value.to_string()}"
    return value


def new_version() -> None:
    """Before a version runs: its declarations start again from the first, on zeroed fields."""
    global _next, _zero
    _next = 0
    fields = [field for key, field in _declared if key is not None]
    if not fields:
        return
    try:
        if _zero is None or _zero[0] != len(fields):
            _zero = (len(fields), _zero_kernel(fields))
        _zero[1]()
    except Exception:  # (Taichi internals other than 1.7's) every version declares new fields, as before
        _declared.clear()
        _declared.append((None, None))  # never matched again: index 0 is taken by a field-less entry


def _zero_kernel(fields):
    import taichi as ti
    from taichi.lang.matrix import MatrixField

    # (rows, columns, 1 for a vector), or (0, 0, 0) for a scalar field
    kinds = [(f.n, getattr(f, "m", 1), int(f.ndim == 1)) if isinstance(f, MatrixField) else (0, 0, 0)
             for f in fields]

    @ti.kernel
    def zero():
        for k in ti.static(range(len(fields))):
            f = ti.static(fields[k])
            for I in ti.grouped(f):
                if ti.static(kinds[k][0] == 0):
                    f[I] = 0
                elif ti.static(kinds[k][2] == 1):
                    f[I] = ti.Vector.zero(f.dtype, kinds[k][0])
                else:
                    f[I] = ti.Matrix.zero(f.dtype, kinds[k][0], kinds[k][1])

    return zero
