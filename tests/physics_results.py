"""The float64 physics numbers, computed once per test session in a subprocess.

``start()`` launches tests/physics_fp64_worker.py in the background (test
modules call it when imported, so it runs beside the float32 tests on the
second core; under pytest-xdist the first test that needs it starts it, see
background.py); ``results()`` waits for it and returns its JSON as a dict.
"""
from pathlib import Path

from background import Worker

_worker = Worker(Path(__file__).resolve().parent / "physics_fp64_worker.py", timeout_s=300)


def start() -> None:
    _worker.start_early()


def results() -> dict:
    return _worker.result()
