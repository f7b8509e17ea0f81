"""Taichi start-up: one ``ti.init`` per process, chosen arch and precision.

Taichi resets every field and kernel on ``ti.init``, so a process initialises
once; tests needing another arch or precision run in a subprocess.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

# Taichi asks the network for a newer version at start-up; offline that costs seconds.
os.environ.setdefault("TI_SKIP_VERSION_CHECK", "ON")
# Compiled kernels are cached on disk, so a second run starts faster.
os.environ.setdefault("TI_OFFLINE_CACHE_FILE_PATH",
                      str(Path.home() / ".cache" / "rigid-body-taichi"))

import taichi as ti  # noqa: E402

_initialised: dict | None = None


def init_taichi(arch: str = "cpu", fp64: bool = False, debug: bool = False) -> str:
    """Initialise Taichi once; return the backend actually used ("cpu", "cuda", "vulkan")."""
    global _initialised
    wanted = dict(arch=arch, fp64=fp64)
    if _initialised is not None:
        if _initialised["wanted"] != wanted:
            raise RuntimeError(f"Taichi already initialised with {_initialised['wanted']}; "
                               f"one precision and arch per process")
        return _initialised["backend"]
    fp = ti.f64 if fp64 else ti.f32
    common = dict(default_fp=fp, log_level=ti.WARN, offline_cache=True, debug=debug,
                  random_seed=0)
    backend = "cpu"
    if arch == "gpu":
        for candidate, name in ((ti.cuda, "cuda"), (ti.vulkan, "vulkan")):
            try:
                ti.init(arch=candidate, **common)
            except Exception:
                continue
            if ti.lang.impl.current_cfg().arch == candidate:
                backend = name
                break
        else:
            print("note: --arch gpu: no CUDA or Vulkan GPU backend found; running on the CPU",
                  file=sys.stderr)
            ti.init(arch=ti.cpu, **common)
    else:
        ti.init(arch=ti.cpu, **common)
    _initialised = dict(wanted=wanted, backend=backend)
    return backend
