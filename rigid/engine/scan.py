"""Exclusive prefix sum of an i32 field, in Taichi on any arch (Taichi's PrefixSumExecutor
runs only on CUDA and Vulkan and raises on the CPU).

Two levels, as in Blelloch's chunked scan: (1) each chunk of CHUNK entries is
summed by one thread, in parallel over chunks; (2) one thread scans the chunk
totals; (3) each chunk writes its running sums from its total's offset, in
parallel. The three loops are ``ti.func``s meant to sit at a kernel's top level
(``scan_parallel``), where Taichi runs each in parallel; ``scan_serial`` is the
plain running sum for a kernel that runs on one thread. Both give
``starts[c] = Σ_{c' < c} counts[c']`` and ``starts[size]`` = the total.
"""
import taichi as ti

CHUNK = 1024


def make_scan(counts, starts, size: int):
    """``ti.func``s (scan_parallel, scan_serial) writing the exclusive scan of counts[:size] into
    starts[:size + 1]."""
    num_chunks = max(1, (size + CHUNK - 1) // CHUNK)
    chunk_total = ti.field(ti.i32, shape=num_chunks + 1)

    @ti.func
    def scan_parallel():
        for k in range(num_chunks):  # (1) per chunk, in parallel
            total = 0
            for c in range(k * CHUNK, ti.min((k + 1) * CHUNK, size)):
                total += counts[c]
            chunk_total[k + 1] = total
        ti.loop_config(serialize=True)
        for _ in range(1):  # (2) one thread: running sum of the chunk totals
            chunk_total[0] = 0
            for k in range(num_chunks):
                chunk_total[k + 1] += chunk_total[k]
        for k in range(num_chunks):  # (3) per chunk, in parallel
            running = chunk_total[k]
            for c in range(k * CHUNK, ti.min((k + 1) * CHUNK, size)):
                starts[c] = running
                running += counts[c]
            if k == num_chunks - 1:
                starts[size] = running

    @ti.func
    def scan_serial():
        running = 0
        for c in range(size):
            starts[c] = running
            running += counts[c]
        starts[size] = running

    return scan_parallel, scan_serial
