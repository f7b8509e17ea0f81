"""Compute graphs that repeat kernels: one Python call launches many kernel dispatches.

    graphs = RepeatedGraphs(repeated=[(substep, False)], then=[(write, False)])
    graphs.run(16)            # substep ×16, then write: one launch
    chunks = RepeatedGraphs(repeated=[(frame, True), (record, False)])
    chunks.run(8, n=16)       # (frame(n=16), record) ×8

Each kernel is given with whether it takes the graph's one scalar argument ``n``
(i32). A graph is built once per repeat count and cached. Launching a graph costs
~1 µs per dispatch, a kernel called from Python ~12 µs; a loop inside one kernel
would cost nothing, but only a kernel's top-level loops run in parallel, and the
frame kernels must stay the same kernels as a frame-by-frame run's (frame_rows.py).
"""
import taichi as ti


class RepeatedGraphs:
    def __init__(self, repeated, then=()):
        """``repeated``, ``then``: sequences of (kernel, takes_n)."""
        self.repeated, self.then = tuple(repeated), tuple(then)
        self.takes_n = any(takes_n for _kernel, takes_n in self.repeated + self.then)
        self._graphs = {}

    def run(self, count: int, n: int = 0) -> None:
        """Dispatch the repeated kernels ``count`` times, then the others once, in one launch."""
        graph = self._graphs.get(count)
        if graph is None:
            builder = ti.graph.GraphBuilder()
            arg = ti.graph.Arg(ti.graph.ArgKind.SCALAR, "n", ti.i32) if self.takes_n else None
            for kernel, takes_n in self.repeated * count + self.then:
                if takes_n:
                    builder.dispatch(kernel, arg)
                else:
                    builder.dispatch(kernel)
            graph = self._graphs[count] = builder.compile()
        graph.run({"n": n} if self.takes_n else {})
