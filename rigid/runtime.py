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

from .config import ARCHES
from .errors import UserError

_initialised: dict | None = None

# The serial schedule's frame kernel (rigid.engine.kernels: run_frames, the whole frame on one
# thread) compiles without Taichi's whole-kernel common-subexpression pass (opt_level 0): that
# pass took over half of a cold compile of bodies in contact (its cost grows with the kernel's
# size times its duplicate statements), and LLVM eliminates the same subexpressions again in the
# machine code. Without it, Taichi 1.7.4's loop-invariant caching (cache_loop_invariant_global_vars)
# is wrong: it keeps an array element in a local through a one-thread loop but redirects only the
# accesses through the same pointer statement, which the CSE pass had merged; another access to
# the element, through a duplicate pointer, goes to memory beside the cached copy, and the copy
# written back at the loop's end undoes its stores (the broadphase's counters lost their updates
# and the pair sweep read past its list; tests/test_compile_settings.py). So both go off
# together: opt_level is part of Taichi's disk-cache key, the caching flag is not, and this
# pairing keeps the two from mixing. The parallel schedule's forces and update on a CPU
# (split_substep.py) compile so too; the other kernels keep Taichi's defaults: the parallel
# schedule's other parts ran a 1,000-pile ~7 % slower without the caching. report/bench_versions.md.
CSE_OFF = dict(opt_level=0, cache_loop_invariant_global_vars=False)


@contextlib.contextmanager
def compile_settings(**options):
    """Kernels compiled inside compile with these Taichi CompileConfig ``options`` (CSE_OFF, or
    rigid.diff.passes's); the process's own are restored after. A kernel must be
    compiled with the same options at every launch (the launch looks it up by its settings)."""
    config = ti.lang.impl.current_cfg()
    before = {name: getattr(config, name) for name in options}
    for name, value in options.items():
        setattr(config, name, value)
    try:
        yield
    finally:
        for name, value in before.items():
            setattr(config, name, value)


QUICK_COMPILE_ENV = "RIGID_QUICK_COMPILE"  # "1": quick_compile by default (the test suite sets it)


def init_taichi(arch: str = "cpu", fp64: bool = False, debug: bool = False, quick_compile: bool | None = None) -> str:
    """Initialise Taichi once; return the backend actually used ("cpu", "cuda", "vulkan", "metal").

    ``arch``: "cpu"; "gpu" (a hardware GPU if any, else the CPU with a note); or a backend by
    name ("cuda", "vulkan", "metal"), which runs there or raises BackendUnavailable: an explicit
    "vulkan" takes any Vulkan device, software ones (Mesa lavapipe) included.

    ``quick_compile``: skip Taichi's advanced IR optimisations (``advanced_optimization=False``;
    LLVM still optimises the machine code). Kernels compile faster and run a little slower
    (report/bench_build.json measures building; the serial frame kernel, which users compile
    without the costliest pass anyway, gains least), so it
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
    # cfg_optimization: Taichi's control-flow-graph passes (store-to-load forwarding, dead
    # stores) grow steeply with a kernel's size: they were most of a first compile of bodies in
    # contact and bought nothing measurable at run time (report/bench_first_run.md), so they are
    # off (rigid.diff turns them on for its adjoint kernels: passes.ADJOINT).
    common = dict(default_fp=fp, log_level=ti.WARN, offline_cache=True, debug=debug,
                  random_seed=0, advanced_optimization=not quick_compile, cfg_optimization=False)
    if arch not in ARCHES:
        raise UserError(f"arch = {arch!r}: use one of {', '.join(ARCHES)}")
    backend = "cpu"
    if arch == "gpu":
        for name in gpu_candidates():
            if name == "vulkan" and not glob.glob("/dev/dri/renderD*") and sys.platform == "linux":
                # Without a GPU render node the only Vulkan device is a software one (Mesa
                # lavapipe, installed for drawing): slower than Taichi's own CPU backend.
                continue
            if _try_init(name, common):
                backend = name
                break
        else:
            print("note: --arch gpu: no CUDA, Metal or Vulkan GPU found (a software Vulkan does not count); "
                  "running on the CPU",
                  file=sys.stderr)
            _quiet_init(arch=ti.cpu, **common)
    elif arch == "cpu":
        _quiet_init(arch=ti.cpu, **common)
    elif _try_init(arch, common):  # asked by name: that backend or an error, never a silent CPU
        backend = arch
    else:
        raise BackendUnavailable(f"--arch {arch}: Taichi found no {arch} device here; "
                                 f"use --arch cpu, or --arch gpu to take whatever GPU there is")
    _initialised = dict(wanted=wanted, backend=backend)
    return backend


class BackendUnavailable(UserError):
    """An arch asked for by name that this machine cannot give."""


def _try_init(name: str, common: dict) -> bool:
    """ti.init on backend ``name``; True if Taichi really runs there (it falls back to the CPU
    with a warning when the device is missing)."""
    if name == "cuda" and ctypes.util.find_library("cuda") is None:
        return False  # no NVIDIA driver: don't let Taichi warn and fall back to the CPU
    if name == "metal" and sys.platform != "darwin":
        return False
    candidate = getattr(ti, name)
    try:
        _quiet_init(arch=candidate, **common)
    except Exception:
        return False
    return ti.lang.impl.current_cfg().arch == candidate


def gpu_candidates() -> list:
    """The backends to try for --arch gpu, in order: CUDA, then Metal on a Mac (Taichi's GPU
    backend there; untested by this project: no Mac here), then Vulkan."""
    return ["cuda"] + (["metal"] if sys.platform == "darwin" else []) + ["vulkan"]


def _quiet_init(**kwargs):
    # ti.init prints "[Taichi] Starting on arch=..." to stdout; keep stdout for results.
    with contextlib.redirect_stdout(sys.stderr):
        ti.init(**kwargs)


class SettingsKernel:
    """A Taichi kernel that compiles with its own ``settings`` (compile_settings): called plainly,
    or launched by rigid.engine.launch, which reads ``settings`` and ``_primal``."""

    def __init__(self, kernel, settings: dict):
        self.kernel, self.settings, self._primal = kernel, settings, kernel._primal

    def __call__(self, *args):
        with compile_settings(**self.settings):
            return self.kernel(*args)
