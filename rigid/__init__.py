"""A particle-based rigid body simulator in Taichi (HKU COMP3360 Assignment 3, solved).

The engine never imports the assignment file: it receives the 7 TODO units as
a parameter (see ``rigid.engine.units``). The Python API (rigid/api.py): ``rigid.init``,
``rigid.scene``, ``rigid.load_scene``, ``rigid.Simulator``, ``rigid.export``, ``rigid.show``,
``rigid.sweep``; and, differentiable (rigid/diff), ``rigid.gradient`` and ``rigid.fit``.

Importing ``rigid`` first sets Taichi's environment, so import it before taichi.
"""
import inspect
import os
from pathlib import Path

# Taichi asks the network for a newer version at start-up; offline that costs seconds.
os.environ.setdefault("TI_SKIP_VERSION_CHECK", "ON")
# No "[Taichi] version ..." banner on stdout at import.
os.environ.setdefault("ENABLE_TAICHI_HEADER_PRINT", "0")
# Compiled kernels are cached on disk, so a second run starts faster.
os.environ.setdefault("TI_OFFLINE_CACHE_FILE_PATH", str(Path.home() / ".cache" / "rigid-body-taichi"))
# Each @ti.func and @ti.kernel at a module's top level asks inspect for the source of the frame
# importing that module, a frozen importlib frame, to see whether it decorates a class's method.
# inspect's table of files by module has no entry for that frozen file, so it scanned every loaded
# module at each of the engine's ~350 decorators (~0.1 s of every start). Saying which module the
# frozen file is makes that a lookup; the answer (no source: not a method) is the same.
for _module in ("importlib._bootstrap", "importlib._bootstrap_external"):
    inspect.modulesbyfile.setdefault(f"<frozen {_module}>", _module)
del _module

# The Python API (rigid/api.py), loaded on first use so that ``import rigid`` stays light.
_API = ("init", "scene", "load_scene", "Simulator", "export", "show", "frames", "sweep", "load_units",
        "default_units", "SimConfig", "ASSETS")
_DIFF = ("gradient", "fit")  # rigid/diff: gradients through a run, fitting a run to data


def __getattr__(name):
    if name in _API:
        from . import api

        return getattr(api, name)
    if name in _DIFF:
        from . import diff

        return getattr(diff, name)
    raise AttributeError(f"module 'rigid' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_API) + list(_DIFF))
