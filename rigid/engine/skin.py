"""The neighbour lists' skin: its widest from the particles' spacing, then adapted to how often
the lists are rebuilt.

A list holds the other bodies' particles within a diameter plus the skin, and how many there
are grows with that reach over their spacing. Volume particles lie a diameter apart; a
sphere's vertices moved inward by their radius (rigid.bodies.inset) lie closer (0.71
diameters on the course's icosphere), and a fine static mesh closer still (the bowl: 0.28).
So the widest skin is half a diameter, or half the smallest spacing in diameters of any body
where that is less (``widest_fraction``): a skin of half a diameter over such particles
filled the lists with 2-3 times the candidates, walked every substep. A skin of half a
particle diameter lets a pile of volume bodies reuse its lists for 7-30 substeps.

Where some bodies move by about the skin every substep (a few bodies still bouncing on top of
a 24,000-body pile: up to 3.4 m/s, spinning at 97 rad/s), the lists are rebuilt every substep
whatever the skin, and then a wide skin only costs: three times the candidates a particle
needs, in cells of the diameter plus the skin (266-275 ns a particle-substep on that pile at
0.5 diameters, 194 at 0.2; the same skin everywhere made the 1,000-sphere pile 8 % and a
dense volume pile 16 % slower: their lists were reused less).

So after each chunk of frames the host looks at the chunk's rebuilds per substep: at
``SHRINK_ABOVE`` or more (the lists were not reused) the skin halves, down to ``MIN_FRACTION``
of a diameter; below ``GROW_BELOW`` it doubles, up to the widest. (Halving at 0.5 rebuilds a
substep trapped the 8,000-body pile: shrunk while it landed, its thinner lists were rebuilt
0.28 times a substep, too often to grow back at 0.1.) The grid's cells follow (the diameter
plus the skin), and the lists are rebuilt at the next placement. The skin changes which pairs
a list holds beyond contact, never the sums: each runs over the touching pairs in slot order
(and a list that overflows grows, list_growth.py), so a run keeps its bits, whatever its
chunks, with bodies asleep too (a sleeper's particles are placed once, when it falls asleep:
pair_stages.place_for_pairs says why). Only a list past list_growth.MAX_NEIGHBOURS walks the
grid, in the order of the cells the skin sizes.
"""
from __future__ import annotations

import numpy as np

from . import broadphase, broadphase_host, neighbours

SHRINK_ABOVE = 0.95  # rebuilds a substep: the lists were (nearly) never reused
GROW_BELOW = 0.5  # reused at least once on average: a wider skin may pay again
MIN_FRACTION = 0.1  # of the largest particle diameter


def widest_fraction(model) -> float:
    """The widest skin, in largest particle diameters (scratch.particle_diameter): half a
    diameter (neighbours.SKIN_FRACTION), or less where a body's particles lie closer than a
    diameter: half the smallest ratio, over bodies, of a body's particle spacing (the median
    distance from a particle to its nearest one of the same body, at rest) to its particles'
    diameter; at least MIN_FRACTION."""
    return max(MIN_FRACTION, min(neighbours.SKIN_FRACTION, 0.5 * densest_spacing(model)))


def densest_spacing(model) -> float:
    """The smallest, over bodies of two or more particles of nonzero radius, of their particle
    spacing in their particles' diameters (inf if none); the bodies of one shape counted once."""
    from scipy.spatial import cKDTree  # only for scenes whose bodies collide

    seen, best = set(), np.inf
    for b, (start, count) in enumerate(zip(model.body_start_np, model.body_count_np)):
        diameter = 2.0 * float(model.radius_np[b])
        points = model.r0_np[start:start + count]
        key = (diameter, np.round(np.sort(points, axis=0), 9).tobytes())
        if count < 2 or diameter <= 0 or key in seen:
            continue
        seen.add(key)
        nearest = cKDTree(points).query(points, k=2)[0][:, 1]
        best = min(best, round(float(np.median(nearest)) / diameter, 6))  # (a lattice's: 1, not 1 − ε)
    return best


class AdaptiveSkin:
    def __init__(self, diameter: float, widest: float, pairs: bool, scratch_arrays: dict):
        """``widest``: the largest fraction of a ``diameter`` the skin takes (widest_fraction),
        and the one it starts at."""
        self.diameter, self.pairs = diameter, pairs
        self.fraction = self.widest = widest
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
            fraction = min(self.widest, fraction * 2)
        if fraction != self.fraction:
            self.set(sim, fraction)

    def set(self, sim, fraction: float) -> None:
        """Skin = ``fraction`` of a diameter from the next placement on (the lists rebuilt there)."""
        self.fraction = fraction
        broadphase_host.set_skin(sim._scratch_arrays, self.diameter, fraction)
