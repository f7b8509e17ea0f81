"""``--ray ADDRESS|local``: the sweep's tasks on a Ray cluster (the ``cluster`` extra).

The same ``run_task`` as the local pool, as a Ray task of one CPU: Ray keeps its worker
processes for the next task, so each starts Taichi once and reuses its kernels, as a pool
worker does. Results (the NPZ's bytes) come back to the driver, which writes them; so the
nodes need this package and the scene's meshes at the same paths (a shared file system, or
the package installed there), never the output folder. ``local`` starts a cluster on this
machine for the sweep (``--workers`` CPUs, no more than the sweep has tasks: Ray starts a
worker process per CPU) and stops it afterwards; an address joins a running one
(``ray start --head`` prints it) and leaves it running.
"""
from __future__ import annotations

import contextlib
import socket

from ..errors import UserError
from .task import run_task

INSTALL_HINT = "pip install 'rigid-body-taichi[cluster]' (or pip install ray)"
CONNECT_TIMEOUT = 5.0  # s: Ray itself waits minutes for an address where nothing answers


def check_ray(address: str) -> None:
    """Ray installed, and for HOST:PORT something listening there: one line otherwise, before
    anything is written."""
    try:
        import ray  # noqa: F401
    except ImportError:
        raise UserError(f"--ray needs Ray, which is not installed; {INSTALL_HINT}, or leave out --ray "
                        f"to use the local process pool") from None
    if address in ("local", "auto") or "://" in address:
        return
    host, _, port = address.rpartition(":")
    if not port.isdigit():
        raise UserError(f"--ray {address}: use HOST:PORT (ray start --head prints it), or --ray local")
    try:
        socket.create_connection((host or "127.0.0.1", int(port)), timeout=CONNECT_TIMEOUT).close()
    except OSError as err:
        raise UserError(f"--ray {address}: nothing answers there ({err.strerror or type(err).__name__}); "
                        f"start the cluster (ray start --head) or use --ray local") from None


@contextlib.contextmanager
def ray_session(address: str, workers: int):
    """Ray, started here (``local``) or joined, for the block; shut down after it if started here."""
    import ray

    started = not ray.is_initialized()
    if started:
        try:
            if address == "local":
                ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False, configure_logging=False)
            else:
                ray.init(address=address, log_to_driver=False, configure_logging=False)
        except Exception as err:
            message = " ".join(str(err).split())[:300]
            raise UserError(f"--ray {address}: Ray could not start or connect ({message}); "
                            f"check the address (ray status), or use --ray local") from None
    try:
        yield ray
    finally:
        if started:
            ray.shutdown()


def run_ray(ray, tasks: list[dict], on_result) -> None:
    """Run ``tasks`` as Ray tasks; ``on_result(task, outcome)`` as each finishes."""
    refs: dict = {}
    try:
        remote = ray.remote(num_cpus=1, max_retries=0)(run_task)
        refs.update({remote.remote(task): task for task in tasks})
        while refs:
            done, _ = ray.wait(list(refs), num_returns=1)
            for ref in done:
                task = refs.pop(ref)
                try:
                    outcome = ray.get(ref)
                except ray.exceptions.RayError as err:  # the worker or its node died
                    line = " ".join(str(err).split())[:300]
                    outcome = dict(name=task["name"], status=f"Ray: {line}", energy=None, npz=None, mp4=None,
                                   seconds=None)
                on_result(task, outcome)
    except BaseException:  # Ctrl-C: the tasks still queued or running are cancelled, their workers ended
        for ref in refs:
            try:
                ray.cancel(ref, force=True)
            except Exception:  # already finished, or the cluster is going away: nothing to cancel
                pass
        raise
