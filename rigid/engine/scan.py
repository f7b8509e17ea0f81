"""Exclusive prefix sum of an i32 array, in Taichi on any arch (Taichi's PrefixSumExecutor
runs only on CUDA and Vulkan and raises on the CPU).

Two levels, as in Blelloch's chunked scan: (1) each chunk of CHUNK entries is summed by one
thread, in parallel over chunks; (2) one thread scans the chunk totals; (3) each chunk writes
its running sums from its total's offset, in parallel. ``scan_parallel``'s loops are meant
to sit at a kernel's top level, where Taichi runs each in parallel; ``scan_serial`` is the
plain running sum for a kernel that runs on one thread. Both give
``starts[c] = Σ_{c' < c} counts[c']`` and ``starts[size]`` = the total.
"""
import taichi as ti

CHUNK = 1024


@ti.func
def scan_parallel(counts: ti.template(), starts: ti.template(), chunk_total: ti.template(), size, num_chunks):
    for k in range(num_chunks):  # (1) per chunk, in parallel
        total = 0
        for c in range(k * CHUNK, ti.min((k + 1) * CHUNK, size)):
            total += counts[c]
        chunk_total[k + 1] = total
    sum_chunk_totals(chunk_total, num_chunks)  # (2)
    for k in range(num_chunks):  # (3) per chunk, in parallel
        running = chunk_total[k]
        for c in range(k * CHUNK, ti.min((k + 1) * CHUNK, size)):
            starts[c] = running
            running += counts[c]
        if k == num_chunks - 1:
            starts[size] = running


@ti.func
def sum_chunk_totals(chunk_total: ti.template(), num_chunks):
    """Step (2) at a kernel's top level, on one thread: chunk_total[1..num_chunks] (each chunk's
    total) become the running sums, chunk_total[0] = 0 (none for num_chunks 0)."""
    ti.loop_config(serialize=True)
    for _ in range(ti.min(num_chunks, 1)):
        chunk_total[0] = 0
        for k in range(num_chunks):
            chunk_total[k + 1] += chunk_total[k]


@ti.func
def scan_serial(counts: ti.template(), starts: ti.template(), size):
    running = 0
    for c in range(size):
        starts[c] = running
        running += counts[c]
    starts[size] = running
