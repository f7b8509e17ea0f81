"""Shared fixtures: one Taichi runtime per test process (CPU, float32).

``ti.init`` resets every field and kernel, so the suite initialises once per
process; tests that need float64 or another arch run a subprocess.
Simulators take ~2 s to compile, so tests share them through ``sim_cache``
and change initial conditions with ``Simulator.reconfigure`` (no recompile).
"""
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
ASSETS = ROOT / "assets"
SOLUTION = ROOT / "rigid_body_dynamic.py"


@pytest.fixture(scope="session")
def ti_cpu():
    from rigid.runtime import init_taichi

    init_taichi("cpu", fp64=False)


@pytest.fixture(scope="session")
def units(ti_cpu):
    from rigid.engine.units import load_units

    return load_units(SOLUTION)


@pytest.fixture(scope="session")
def sim_cache(units):
    """sim_cache(**config) -> a Simulator for that config, built once per process, reset to
    the config's initial state (runtime keys not given take SimConfig's defaults)."""
    from rigid.science.experiments import SimulatorCache

    return SimulatorCache(units, fp64=False)


def run_cli(*args, timeout=120, cwd=ROOT):
    """Run ``python rigid_body_dynamic.py ARGS`` and return the CompletedProcess."""
    return subprocess.run([sys.executable, str(SOLUTION), *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=timeout)
