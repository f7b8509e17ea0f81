"""Where the partial rebuilds of the neighbour lists (refresh.py) keep their state: in nbr_flags
(neighbours.py), after the parts' slots. Per body b, [4 + 3B + b] its state (MARKED while it is
refreshed now, REFRESHED since the last full build); the refreshed bodies [4 + 4B + k], their
number [4 + 5B], their particles [5 + 5B], the refreshes so far [6 + 5B] (benchmarks); while a
refresh searches (refresh.PENDING): its particles' number [7 + 5B] (the particles themselves in
the active list, which the refresh makes again after), the hash's buckets [8 + 5B] and whether a
list was full [9 + 5B]; the cost of the last full build and of the refreshes since [10 + 5B] and
the motion tests since [11 + 5B] (refresh.BUILD_COST)."""
import taichi as ti

from .arrays import download

MARKED, REFRESHED = 1, 2  # a body's state bits
# The refresh's scalars (``scalar``), after the bodies' states and the refreshed bodies: the
# refreshed bodies' number and particles, the refreshes so far, the searching particles' number,
# the hash's H, a list full, the full build's and the refreshes' cost since it, the motion tests since.
COUNT, PARTICLES, REFRESHES, SEARCHING, BUCKETS, FULL, COST, SINCE = range(8)
SCALARS = 8


def _index(num_bodies: int, what: int) -> int:
    """Index in nbr_flags of the refresh's slot ``what`` on the host (``at`` in a kernel)."""
    return 4 + 3 * num_bodies + what


def flags_size(num_bodies: int) -> int:
    """Length of nbr_flags for ``num_bodies`` bodies in contact (the last two: neighbours.py)."""
    return _index(num_bodies, 2 * num_bodies + SCALARS) + 2


def refreshes_so_far(sim) -> int:
    """How many substeps refreshed some lists in part (benchmarks: refreshes per substep)."""
    B = sim.num_bodies
    return int(download(sim._scratch_arrays["nbr_flags"])[_index(B, 2 * B + REFRESHES)]) if sim.many else 0


@ti.func
def at(state: ti.template(), what):
    """Index in nbr_flags of the refresh's slot ``what``: b (a body's state), B + k (the k-th
    refreshed body). (_index on the host: a kernel calls no plain Python function.)"""
    return 4 + 3 * state.x.shape[0] + what


@ti.func
def scalar(state: ti.template(), what):
    """Index in nbr_flags of the refresh's scalar ``what`` (COUNT ... SINCE)."""
    return at(state, 2 * state.x.shape[0] + what)


@ti.func
def body_state(state: ti.template(), scratch: ti.template(), b):
    return scratch.nbr_flags[at(state, b)]


@ti.func
def marked(state: ti.template(), scratch: ti.template(), b):
    return body_state(state, scratch, b) & MARKED != 0


@ti.func
def refreshed_body(state: ti.template(), scratch: ti.template(), k):
    """The k-th body refreshed since the last full build."""
    return scratch.nbr_flags[at(state, state.x.shape[0] + k)]


@ti.func
def num_refreshed(state: ti.template(), scratch: ti.template()):
    return scratch.nbr_flags[scalar(state, COUNT)]


@ti.func
def refreshed_particles(state: ti.template(), scratch: ti.template()):
    return scratch.nbr_flags[scalar(state, PARTICLES)]


@ti.func
def searching(state: ti.template(), scratch: ti.template()):
    """How many particles the pending refresh searches for (scratch.active[0 .. n - 1])."""
    return scratch.nbr_flags[scalar(state, SEARCHING)]
