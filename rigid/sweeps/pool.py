"""The local process pool: ``--workers N`` spawned processes, each running task after task.

Spawned, not forked: a forked child would inherit the driver's Taichi runtime and its threads
(the API may be called from a process that has started Taichi). At most one task per worker
is in flight, so a worker that dies (killed, out of memory) takes down only the runs the pool
held then: they come back as failures (retried by the next invocation), and a fresh pool
carries on with the rest. On Ctrl-C the driver ends its own workers, by their handles, and
re-raises.
"""
from __future__ import annotations

import multiprocessing
from collections import deque
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

from .task import ignore_ctrl_c, run_task

DIED = ("its worker process died while running it (killed, or out of memory); "
        "run the same command again to retry it")


def run_local(tasks: list[dict], workers: int, on_result) -> None:
    """Run ``tasks`` on ``workers`` processes; ``on_result(task, outcome)`` for each, in the
    order they finish (``outcome``: run_task's dict)."""
    context = multiprocessing.get_context("spawn")
    pending = deque(tasks)
    while pending:
        before = set(multiprocessing.active_children())
        pool = ProcessPoolExecutor(min(workers, len(pending)), mp_context=context, initializer=ignore_ctrl_c)
        try:
            _drain(pool, pending, workers, on_result)
        except BaseException:  # Ctrl-C, or the driver's own error: end this pool's workers now
            pool.shutdown(wait=False, cancel_futures=True)
            for process in set(multiprocessing.active_children()) - before:
                process.kill()
                process.join()
            raise
        pool.shutdown(wait=True)


def _drain(pool, pending: deque, workers: int, on_result) -> None:
    """Feed the pool until ``pending`` is empty or the pool breaks (a worker died)."""
    in_flight: dict = {}
    broken = False
    while (pending and not broken) or in_flight:
        while pending and not broken and len(in_flight) < workers:
            task = pending.popleft()
            try:
                in_flight[pool.submit(run_task, task)] = task
            except BrokenProcessPool:
                pending.appendleft(task)
                broken = True
        if not in_flight:
            break
        done, _ = wait(in_flight, return_when=FIRST_COMPLETED)
        for future in done:
            task = in_flight.pop(future)
            try:
                outcome = future.result()
            except BrokenProcessPool:
                broken = True
                outcome = dict(name=task["name"], status=DIED, energy=None, npz=None, mp4=None, seconds=None)
            on_result(task, outcome)
