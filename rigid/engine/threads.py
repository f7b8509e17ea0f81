"""Taichi's CPU worker threads pinned one to a core, for the parallel schedule.

Measured on this project's 2-vCPU machine (KVM, Linux): the pair stage of 1,000 spheres in
contact as one parallel loop took 7.7 ms on one thread, and on two either 4.2 ms or 7.1 ms,
launch by launch (Taichi's kernel profiler), ~5.8 ms on average: in about half the launches
both of Taichi's workers ran on the same vCPU, one after the other (woken together by the
launching thread, they were queued where it ran, and the idle vCPU did not pull one over
within the launch). A throughput-bound loop of FMAs and a loop of random reads scaled 1.9x
and 2.0x on the same two vCPUs, so the cores were there. With each worker pinned to a CPU of
its own: 4.2 ms at every launch, 1.83x one thread.

Which threads are the workers: the first parallel Simulator of a process runs a short
parallel probe; the threads (other than the caller) that ran during it, and not during an
equal pause just before (a BLAS pool still spinning, say), are the workers. Each is then
pinned to one of the CPUs the process may use, in turn. Nothing happens off Linux, off the
CPU backend, with fewer than two CPUs, when the probe does not find exactly Taichi's number
of workers, or with ``RIGID_PIN_THREADS=0``. Pinning moves no result: which thread runs a
part of a loop never changes a bit (schedule.py).
"""

import os
import threading
import time

PIN_ENV = "RIGID_PIN_THREADS"  # "0": leave Taichi's workers where the scheduler puts them
_state: dict = {"done": False}


def _threads() -> set[int]:
    try:
        return {int(t) for t in os.listdir("/proc/self/task")}
    except OSError:
        return set()


def _cpu_ns(tid: int) -> int:
    """Nanoseconds thread ``tid`` has run (schedstat; else user + system ticks), 0 if gone."""
    try:
        with open(f"/proc/self/task/{tid}/schedstat") as f:
            return int(f.read().split()[0])
    except (OSError, ValueError, IndexError):
        try:
            with open(f"/proc/self/task/{tid}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
            return (int(fields[11]) + int(fields[12])) * 1_000_000_000 // os.sysconf("SC_CLK_TCK")
        except (OSError, ValueError, IndexError):
            return 0


def pin_workers() -> list[int]:
    """Pin Taichi's CPU workers one to a CPU (once per process; see the module docstring).
    Returns the CPUs of the pinned workers, in pinning order ([] when nothing was pinned)."""
    import taichi as ti

    if _state["done"]:
        return _state.get("cpus", [])
    _state["done"] = True
    cfg = ti.lang.impl.current_cfg()
    cpus = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else []
    workers_wanted = cfg.cpu_max_num_threads
    if (os.environ.get(PIN_ENV) == "0" or cfg.arch != ti.x64 or len(cpus) < 2 or workers_wanted < 2
            or workers_wanted > len(cpus)):
        return []
    _probe(workers_wanted)  # compiled (or loaded) before anything is timed
    candidates = _threads() - {threading.get_native_id()}
    found: set[int] = set()
    for attempt in range(12):  # a worker may sit out a launch (the very problem): probe until all are seen,
        start = {t: _cpu_ns(t) for t in candidates}  # longer each time (a loaded machine)
        time.sleep(0.002)
        busy = {t for t in candidates if _cpu_ns(t) - start[t] > 50_000}  # running without Taichi
        start = {t: _cpu_ns(t) for t in candidates}
        _probe(workers_wanted, 1 << min(attempt, 6))
        found |= {t for t in candidates if _cpu_ns(t) - start[t] > 100_000} - busy
        if len(found) >= workers_wanted:
            break
    if len(found) != workers_wanted:
        return []  # not the pool we know: leave the threads alone
    pinned = []
    for k, tid in enumerate(sorted(found)):
        cpu = cpus[k % len(cpus)]
        try:
            os.sched_setaffinity(tid, {cpu})
        except OSError:
            return pinned
        pinned.append(cpu)
    _state["cpus"] = pinned
    return pinned


_PROBE: dict = {}


def _probe(workers: int, length: int = 1) -> None:
    """A parallel loop of ``2 × workers`` blocks of ~0.3 ms × ``length`` each (Taichi's CPU blocks
    are 512 iterations at least, schedule.py), so that every worker that wakes takes some."""
    import taichi as ti

    if "kernel" not in _PROBE:
        @ti.kernel
        def probe(out: ti.types.ndarray(), n: ti.i32, steps: ti.i32):
            for i in range(n):
                s = 1.0 + i
                for _ in range(steps):
                    s = ti.sqrt(s + 1.0)
                out[i % out.shape[0]] = s

        _PROBE["kernel"], _PROBE["out"] = probe, ti.ndarray(ti.f32, 64)
    _PROBE["kernel"](_PROBE["out"], 1024 * workers, 100 * length)
    ti.sync()
