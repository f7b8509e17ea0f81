"""Taichi start-up: one ``ti.init`` per process, chosen arch and precision.

Taichi resets every field and kernel on ``ti.init``, so a process initialises
once; tests needing another arch or precision run in a subprocess.
"""
from __future__ import annotations

import contextlib
import ctypes.util
import glob
import os
import sys

import taichi as ti  # rigid/__init__.py has set Taichi's environment before this import

_initialised: dict | None = None


QUICK_COMPILE_ENV = "RIGID_QUICK_COMPILE"  # "1": quick_compile by default (the test suite sets it)


def init_taichi(arch: str = "cpu", fp64: bool = False, debug: bool = False, quick_compile: bool | None = None) -> str:
    """Initialise Taichi once; return the backend actually used ("cpu", "cuda", "vulkan").

    ``quick_compile``: skip Taichi's advanced IR optimisations (``advanced_optimization=False``;
    LLVM still optimises the machine code). Kernels compile several times faster and run a little
    slower (report/bench_build.json measures building), so it
    suits processes that compile much and simulate little: the grader's children, whose runs
    are a few hundred substeps of ten particles, and the test suite (``RIGID_QUICK_COMPILE=1``,
    which every process it starts inherits). Simulations for users keep the default (None:
    off unless that variable says 1)."""
    global _initialised
    if quick_compile is None:
        quick_compile = os.environ.get(QUICK_COMPILE_ENV) == "1"
    wanted = dict(arch=arch, fp64=fp64, quick_compile=quick_compile)
    if _initialised is not None:
        if _initialised["wanted"] != wanted:
            raise RuntimeError(f"Taichi already initialised with {_initialised['wanted']}; "
                               f"one precision and arch per process")
        return _initialised["backend"]
    fp = ti.f64 if fp64 else ti.f32
    common = dict(default_fp=fp, log_level=ti.WARN, offline_cache=True, debug=debug,
                  random_seed=0, advanced_optimization=not quick_compile)
    backend = "cpu"
    if arch == "gpu":
        for candidate, name in gpu_candidates():
            if name == "cuda" and ctypes.util.find_library("cuda") is None:
                continue  # no NVIDIA driver: skip Taichi's two lines of warnings about it
            if name == "vulkan" and not glob.glob("/dev/dri/renderD*") and sys.platform == "linux":
                # Without a GPU render node the only Vulkan device is a software one (Mesa
                # lavapipe, installed for drawing): slower than Taichi's own CPU backend.
                continue
            try:
                _quiet_init(arch=candidate, **common)
            except Exception:
                continue
            if ti.lang.impl.current_cfg().arch == candidate:
                backend = name
                break
        else:
            print("note: --arch gpu: no CUDA, Metal or Vulkan GPU found (a software Vulkan does not count); "
                  "running on the CPU",
                  file=sys.stderr)
            _quiet_init(arch=ti.cpu, **common)
    else:
        _quiet_init(arch=ti.cpu, **common)
    _initialised = dict(wanted=wanted, backend=backend)
    return backend


def gpu_candidates() -> list:
    """(Taichi arch, name) to try for --arch gpu, in order: CUDA, then Metal on a Mac (Taichi's
    GPU backend there; untested by this project: no Mac here), then Vulkan."""
    found = [(ti.cuda, "cuda")]
    if sys.platform == "darwin":
        found.append((ti.metal, "metal"))
    return found + [(ti.vulkan, "vulkan")]


def _quiet_init(**kwargs):
    # ti.init prints "[Taichi] Starting on arch=..." to stdout; keep stdout for results.
    with contextlib.redirect_stdout(sys.stderr):
        ti.init(**kwargs)
