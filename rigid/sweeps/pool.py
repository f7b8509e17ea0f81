"""The local process pool: ``--workers N`` spawned processes, each running task after task.

Spawned, not forked: a forked child would inherit the driver's Taichi runtime and its threads
(the API may be called from a process that has started Taichi). Each worker has a pipe of its
own and holds at most one task, and the driver waits on every pipe and every process's exit at
once (``multiprocessing.connection.wait``). So a worker that dies (killed, out of memory) fails
only the run it held: its row says so (the next invocation retries it), and a fresh worker takes
its place. No queue is shared between workers, so a death cannot leave a lock held or a pipe
half-written for the others (``ProcessPoolExecutor`` can hang there: a worker killed while it
starts may leave its queue's feeder thread blocked, and no future ever completes). On Ctrl-C the
driver ends its workers and re-raises.
"""
from __future__ import annotations

import multiprocessing
from collections import deque
from multiprocessing.connection import wait

from .task import ignore_ctrl_c, run_task

DIED = ("its worker process died while running it (killed, or out of memory); "
        "run the same command again to retry it")


def _serve(conn) -> None:
    """A worker's life: run each task the driver sends, send its outcome back; None ends it."""
    ignore_ctrl_c()
    while (task := conn.recv()) is not None:
        conn.send(run_task(task))


class _Worker:
    """One spawned process, the driver's end of its pipe, and the task it holds (None: idle)."""

    def __init__(self, context):
        self.conn, child_end = context.Pipe()
        self.process = context.Process(target=_serve, args=(child_end,))
        self.process.start()
        child_end.close()  # the driver keeps its end only: the pipe reads EOF once the worker is gone
        self.task = None

    def give(self, task: dict) -> None:
        self.task = task
        try:
            self.conn.send(task)
        except OSError:  # it has died: the wait below sees its exit, and the task fails as its own
            pass

    def end(self, kill: bool) -> None:
        if kill:
            self.process.kill()
        else:
            try:
                self.conn.send(None)
            except OSError:  # already gone
                pass
        self.process.join()
        self.conn.close()


def run_local(tasks: list[dict], workers: int, on_result) -> None:
    """Run ``tasks`` on ``workers`` processes; ``on_result(task, outcome)`` for each, in the
    order they finish (``outcome``: run_task's dict)."""
    context = multiprocessing.get_context("spawn")
    pending = deque(tasks)
    crew: list[_Worker] = []
    finished = False
    try:
        while pending or any(w.task is not None for w in crew):
            while len(crew) < workers and len(pending) > sum(w.task is None for w in crew):
                crew.append(_Worker(context))  # no more workers than tasks to give them
            for worker in crew:
                if worker.task is None and pending:
                    worker.give(pending.popleft())
            busy = {w.conn: w for w in crew if w.task is not None}
            busy.update({w.process.sentinel: w for w in busy.values()})
            for worker in {busy[ready] for ready in wait(list(busy))}:
                _collect(worker, crew, on_result)
        finished = True
    finally:  # Ctrl-C or the driver's own error: end the workers now; at the end, let them exit
        for worker in crew:
            worker.end(kill=not finished)


def _collect(worker: _Worker, crew: list, on_result) -> None:
    """The outcome of ``worker``'s task, or, if the worker died, a failure naming why (and the
    worker leaves the crew: a fresh one is started for the tasks still pending)."""
    task, worker.task = worker.task, None
    try:
        outcome = worker.conn.recv()
    except (EOFError, OSError):
        crew.remove(worker)
        worker.end(kill=True)
        outcome = dict(name=task.get("name"), status=DIED, energy=None, npz=None, mp4=None, seconds=None)
    on_result(task, outcome)
