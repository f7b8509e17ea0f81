"""A helper script run beside the tests in its own process (one ti.init there, float64),
started once per test process and read once: ``Worker(script).start()`` ... ``.result()``.

Without pytest-xdist, test modules start their workers when imported, so that each runs
on the second core beside the float32 tests. Under xdist every worker process imports
every module, so there a worker starts only when a test first needs its result (the
tests that share one are in one xdist group, see conftest.py): the other xdist worker
keeps the second core busy meanwhile.
"""
import atexit
import json
import os
import subprocess
import sys


class Worker:
    def __init__(self, script, timeout_s: float = 300):
        self.script, self.timeout_s = script, timeout_s
        self.proc, self.value = None, None

    def start(self) -> "Worker":
        if self.proc is None and self.value is None:
            env = dict(os.environ, TI_SKIP_VERSION_CHECK="ON")
            self.proc = subprocess.Popen([sys.executable, str(self.script)], stdout=subprocess.PIPE,
                                         stderr=subprocess.PIPE, text=True, env=env)
            atexit.register(self._stop)
        return self

    def start_early(self) -> "Worker":
        """Start now unless this is an xdist worker process (then result() starts it)."""
        if "PYTEST_XDIST_WORKER" not in os.environ:
            self.start()
        return self

    def result(self) -> dict:
        """The worker's JSON output (waits for it; starts it if not started)."""
        if self.value is None:
            self.start()
            out, err = self.proc.communicate(timeout=self.timeout_s)
            if self.proc.returncode != 0:
                raise RuntimeError(f"{self.script.name} failed ({self.proc.returncode}):\n{err[-4000:]}")
            self.value = json.loads(out)
        return self.value

    def _stop(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()
