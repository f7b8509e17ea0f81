"""The neighbour lists' skin, adapted to how often the lists are rebuilt.

A skin of half a particle diameter lets a pile reuse its lists for 7-30 substeps (0.03-0.15
rebuilds a substep in the benchmark piles). But where some bodies move by about the skin every
substep (a few bodies still bouncing on top of a 24,000-body pile at 1 s: up to 3.4 m/s,
spinning at 97 rad/s), the lists are rebuilt every substep whatever the skin, and then a wide
skin only costs: three times the candidates a particle needs, in cells of the diameter plus the
skin. Measured on that pile: 266-275 ns a particle-substep with the skin at 0.5 diameters,
194 at 0.2 (the same skin everywhere made the 1,000-sphere pile 8 % and a dense volume pile
16 % slower: their lists were reused less).

So after each chunk of frames the host looks at the chunk's rebuilds per substep: at
``SHRINK_ABOVE`` or more (the lists were not reused) the skin halves, down to ``MIN_FRACTION``
of a diameter; below ``GROW_BELOW`` it doubles, up to neighbours.SKIN_FRACTION. (Halving at
0.5 rebuilds a substep trapped the 8,000-body pile: shrunk while it landed, its thinner lists
were rebuilt 0.28 times a substep, too often to grow back at 0.1, and it ran 80 ns a
particle-substep instead of 63.) The grid's cells follow (the
diameter plus the skin), and the lists are rebuilt at the next placement. The skin changes
which pairs a list holds beyond contact, never the sums: each runs over the touching pairs
in slot order (and a list that overflows grows, list_growth.py), so a run keeps its bits,
whatever its chunks, with bodies asleep too (a sleeper's particles are placed once, when it
falls asleep: pair_stages.place_for_pairs says why).
"""
from __future__ import annotations

from . import broadphase, broadphase_host, neighbours

SHRINK_ABOVE = 0.95  # rebuilds a substep: the lists were (nearly) never reused
GROW_BELOW = 0.5  # reused at least once on average: a wider skin may pay again
MIN_FRACTION = 0.1  # of the largest particle diameter


class AdaptiveSkin:
    def __init__(self, diameter: float, pairs: bool, scratch_arrays: dict):
        self.diameter, self.pairs = diameter, pairs
        self.fraction = neighbours.SKIN_FRACTION
        self._builds = 0
        self._counter = broadphase_host.cell(scratch_arrays, broadphase.BUILDS) if pairs else None  # builds so far

    def after_chunk(self, sim, substeps: int) -> None:
        """Adapt the skin to the rebuilds of the chunk just run (``substeps`` in all)."""
        if not self.pairs or substeps <= 0:
            return
        builds = self._counter.value
        rate, self._builds = (builds - self._builds) / substeps, builds
        fraction = self.fraction
        if rate >= SHRINK_ABOVE:
            fraction = max(MIN_FRACTION, fraction / 2)
        elif rate < GROW_BELOW:
            fraction = min(neighbours.SKIN_FRACTION, fraction * 2)
        if fraction != self.fraction:
            self.set(sim, fraction)

    def set(self, sim, fraction: float) -> None:
        """Skin = ``fraction`` of a diameter from the next placement on (the lists rebuilt there)."""
        self.fraction = fraction
        broadphase_host.set_skin(sim._scratch_arrays, self.diameter, fraction)
