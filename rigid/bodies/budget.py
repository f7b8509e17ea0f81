"""Will the scene fit in memory? An estimate from the particle count, made before anything big
is allocated, against the memory this machine (or its container) has free.

The costs below (bytes a particle, one body or many, and the process itself) were measured as
the peak RSS of whole ``--headless --frames 1`` runs of up to millions of particles. Filling a
mesh (rigid.bodies.sampling) needs memory a grid cell and a particle on top, for a moment.
"""
from __future__ import annotations

import os
from pathlib import Path

from ..errors import UserError

BASE_BYTES = 200e6
BYTES_PER_PARTICLE = {False: 150, True: 320}  # many bodies?
SAMPLING_BYTES_PER_CELL = 3
SAMPLING_BYTES_PER_PARTICLE = 100


def available_bytes() -> float | None:
    """Memory free for this process: /proc/meminfo's MemAvailable, or less where a cgroup caps
    it (containers); None where neither can be read."""
    free = []
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                free.append(float(line.split()[1]) * 1024)
    except OSError:
        pass
    try:  # cgroup v2: the cap minus what the group already uses
        cap = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        if cap != "max":
            used = float(Path("/sys/fs/cgroup/memory.current").read_text())
            free.append(max(0.0, float(cap) - used))
    except (OSError, ValueError):
        pass
    if not free and hasattr(os, "sysconf"):
        try:
            free.append(float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")))
        except (OSError, ValueError):
            pass
    return min(free) if free else None


def simulation_bytes(num_particles: float, many: bool) -> float:
    return BASE_BYTES + num_particles * BYTES_PER_PARTICLE[many]


def check_fits(need: float, what: str, fix: str) -> None:
    """Raise UserError('<what>: about <need> of memory, more than the <free> free here; <fix>')."""
    free = available_bytes()
    if free is not None and need > free:
        raise UserError(f"{what}: about {_size(need)} of memory, more than the {_size(free)} free here; {fix}")


def _size(n: float) -> str:
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n / 1e6:.2g} MB"
