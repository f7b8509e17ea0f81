"""The same pipeline on every Taichi backend: Vulkan (Mesa's software lavapipe here, the SPIR-V
path that Metal and most laptop GPUs take too) against the CPU, float32, within 1 mm; and the
arch a user asks for by name is the one that runs, or one line saying it cannot.

tests/backend_worker.py runs the scenes on Vulkan in a process of its own (one ti.init per
process); the CPU side runs here on the suite's Taichi. Skipped where no Vulkan device exists.
"""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest


HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import backend_worker  # noqa: E402



@pytest.fixture(scope="module")
def vulkan_rows():
    proc = subprocess.run([sys.executable, str(HERE / "backend_worker.py"), "vulkan"], capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = json.loads(proc.stdout)
    if out["backend"] is None:
        pytest.skip(f"no Vulkan device here: {out['why']}")
    assert out["backend"] == "vulkan", "asked for vulkan by name, it must run there, never on the CPU"
    return out


@pytest.mark.parametrize("name", sorted(backend_worker.scenes()))
def test_vulkan_follows_the_cpu(units, vulkan_rows, name):
    cpu = np.array(backend_worker.run(name, backend_worker.scenes()[name]))
    gpu = np.array(vulkan_rows[name])
    assert gpu.shape == cpu.shape == (backend_worker.FRAMES, cpu.shape[1], 3)
    free = backend_worker.free_flight(backend_worker.scenes()[name])  # the start, then each frame
    assert np.abs(cpu[-1] - free[0]).max() > 0.01, "the bodies should move by ten times the tolerance"
    assert np.abs(cpu - free[1:]).max() > 5e-3, "a contact must move them: not a comparison of free flight only"
    assert np.abs(gpu - cpu).max() < 1e-3, np.abs(gpu - cpu).max(axis=(1, 2))


def test_a_backend_asked_by_name_runs_there_or_says_so_in_one_line():
    # This machine has no CUDA device: asking for it is one line and exit code 2, never a silent CPU.
    proc = subprocess.run([sys.executable, str(HERE.parent / "rigid_body_dynamic.py"), "--arch", "cuda",
                           "--headless", "--frames", "1"], capture_output=True, text=True, timeout=300)
    if proc.returncode == 0:
        assert "on cuda" in proc.stdout, proc.stdout  # a machine with CUDA: it ran there
        return
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == ["error: --arch cuda: Taichi found no cuda device here; use --arch cpu, or --arch gpu to "
                     "take whatever GPU there is"], proc.stderr


def test_importing_and_running_the_engine_replaces_nothing_in_taichi():
    proc = subprocess.run([sys.executable, str(HERE / "taichi_untouched_worker.py")], capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip().splitlines()[-1] == "same", proc.stdout
