"""The float64 physics numbers, computed once per test session in a subprocess.

``start()`` launches tests/physics_fp64_worker.py in the background (test
modules call it when imported, so it runs beside the float32 tests on the
second core); ``results()`` waits for it and returns its JSON as a dict.
"""
import atexit
import json
import os
import subprocess
import sys
from pathlib import Path

WORKER = Path(__file__).resolve().parent / "physics_fp64_worker.py"
TIMEOUT_S = 300
_proc = None
_results = None


def start() -> None:
    global _proc
    if _proc is None and _results is None:
        env = dict(os.environ, TI_SKIP_VERSION_CHECK="ON")
        _proc = subprocess.Popen([sys.executable, str(WORKER)], stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True, env=env)
        atexit.register(_stop)


def results() -> dict:
    global _results
    if _results is None:
        start()
        out, err = _proc.communicate(timeout=TIMEOUT_S)
        if _proc.returncode != 0:
            raise RuntimeError(f"physics_fp64_worker.py failed ({_proc.returncode}):\n{err[-4000:]}")
        _results = json.loads(out)
    return _results


def _stop() -> None:
    if _proc is not None and _proc.poll() is None:
        _proc.kill()
