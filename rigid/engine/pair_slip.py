"""Static friction between bodies: each contact pair's tangential spring, kept beside the lists.

With materials, a pair of particles in contact carries a sticking spring (contact.py:
``pair_contact_sticking``, Cundall-Strack as on the planes): its stretch must live as long as
the contact, across substeps and across the neighbour lists' rebuilds. It is kept per list
entry: ``spring(state, scratch, e)`` is the stretch of the pair (i, nbr_list[e]), e = i·K + t.
Each particle keeps its own copy of each of its pairs, so the pair stage writes only its own
slot's entries (no atomics on other particles' lists: a GPU and Vulkan run it as the CPU does).
Both copies evolve bit for bit alike: the pair is evaluated from its lower slot's side whichever
side asks (material_stages._material_pair), on the same numbers, and both start at zero.

A rebuild makes new lists, so before it ``keep`` copies each particle's list and springs aside
and after it (the lists sorted by slot) ``carry`` gives each entry the spring its pair had: a
merge of two sorted lists; a pair new to the list starts at zero. A pair that left the list was
apart (beyond reach + skin), where its spring is zero anyway, so the springs do not depend on
when the lists were rebuilt.

Where a particle's list overflowed (it walks the grid, candidates.py), its pairs have no entry:
they fall back to the viscous law (friction c_t |v_t| capped at μ f_n), from both sides (the
other side sees the overflow in the count), until the lists grow (list_growth.py, ``grown``)
and the chunk is run again; past ``MAX_NEIGHBOURS`` they stay viscous.

With sleeping bodies (sleep.py) a resting sleeper's particles skip the pair stage, so the copy
on its side would go stale while the awake side's evolves: the awake side writes it too
(``copy_to``, in material_stages.pair_wave's wave 1, after wave 0 has decided who wakes; the
entry of i in j's sorted list found by bisection). Each such entry (j's pair with i) is written
by i's thread only, without atomics (Vulkan skips stores with atomics on other particles' data).
Wave 0 notes which awake particles have sleepers among their candidates (``note_sleepers``),
in the kept lists' counts, which only a rebuild uses, so that wave 1 walks only those.

Where they live (a kernel taking every argument pack is at the x64 backend's 64 elements, so
no array of their own), with L = N·K the lists' length: the springs at the end of
``state.plane_slip`` (after the planes' springs), [L] those of the current lists then [L] the
copies during a rebuild; the kept lists at the end of ``scratch.contacts``, [L] entries then
[N] counts.
"""
import numpy as np
import taichi as ti

from . import neighbours
from .arrays import download, upload, zeros
from .matvec import ZERO3


def kept_size(num_particles: int, lists: int, pairs: bool) -> int:
    """The i32 elements the kept lists add to scratch.contacts (with materials)."""
    return lists + num_particles if pairs else 0


@ti.func
def _springs(state: ti.template(), scratch: ti.template()):
    """Where the current lists' springs start in state.plane_slip."""
    return state.plane_slip.shape[0] - 2 * scratch.nbr_list.shape[0]


@ti.func
def _kept(state: ti.template(), scratch: ti.template()):
    """Where the kept lists start in scratch.contacts."""
    return scratch.contacts.shape[0] - scratch.nbr_list.shape[0] - state.particle_x.shape[0]


@ti.func
def spring(state: ti.template(), scratch: ti.template(), e):
    """The spring of list entry e."""
    return state.plane_slip[_springs(state, scratch) + e]


@ti.func
def set_spring(state: ti.template(), scratch: ti.template(), e, s):
    state.plane_slip[_springs(state, scratch) + e] = s


@ti.func
def keep(state: ti.template(), scratch: ti.template(), i):
    """Before a rebuild: slot i's list, its count and its springs copied aside."""
    stride = neighbours.list_stride(scratch, state)
    size = scratch.nbr_list.shape[0]
    springs, kept = _springs(state, scratch), _kept(state, scratch)
    n = scratch.nbr_count[i]
    scratch.contacts[kept + size + i] = n
    base = i * stride
    t = 0
    while t < n and t < stride:  # an overflowed list (n > stride) kept its first entries only
        scratch.contacts[kept + base + t] = scratch.nbr_list[base + t]
        state.plane_slip[springs + size + base + t] = state.plane_slip[springs + base + t]
        t += 1


@ti.func
def carry(state: ti.template(), scratch: ti.template(), i):
    """After a rebuild (slot i's list sorted): each entry's spring from the kept list, else zero."""
    stride = neighbours.list_stride(scratch, state)
    size = scratch.nbr_list.shape[0]
    springs, kept = _springs(state, scratch), _kept(state, scratch)
    base = i * stride
    n = scratch.nbr_count[i]
    m = scratch.contacts[kept + size + i]
    if m > stride:  # it walked the grid: no springs were kept
        m = 0
    if n > stride:  # it walks the grid: its entries are not in use
        n = 0
    u = 0
    t = 0
    while t < n:
        j = scratch.nbr_list[base + t]
        while u < m and scratch.contacts[kept + base + u] < j:
            u += 1
        s = ZERO3
        if u < m and scratch.contacts[kept + base + u] == j:
            s = state.plane_slip[springs + size + base + u]
        state.plane_slip[springs + base + t] = s
        t += 1


@ti.func
def note_sleepers(state: ti.template(), scratch: ti.template(), i, count):
    """Wave 0: slot i has ``count`` candidates of sleeping bodies (kept in the kept counts' slot
    i, free between rebuilds: ``keep`` and ``carry`` use it within one)."""
    scratch.contacts[_kept(state, scratch) + scratch.nbr_list.shape[0] + i] = count


@ti.func
def near_sleepers(state: ti.template(), scratch: ti.template(), i):
    return scratch.contacts[_kept(state, scratch) + scratch.nbr_list.shape[0] + i] > 0


@ti.func
def copy_to(state: ti.template(), scratch: ti.template(), i, j, e):
    """The spring of slot i's entry e (its pair with j; −1: none, then zero) written to j's copy,
    the entry of i in j's sorted list (none if j's list overflowed or lacks i)."""
    stride = neighbours.list_stride(scratch, state)
    n = scratch.nbr_count[j]
    if n <= stride:
        base = j * stride
        lo, hi = 0, n
        while lo < hi:  # the first entry above i ...
            mid = (lo + hi) >> 1
            if scratch.nbr_list[base + mid] > i:
                hi = mid
            else:
                lo = mid + 1
        if lo > 0 and scratch.nbr_list[base + lo - 1] == i:  # ... follows i's
            s = ZERO3
            if e >= 0:
                s = spring(state, scratch, e)
            set_spring(state, scratch, base + lo - 1, s)


def grown(sim, num_particles, stride):
    """The host's part of list_growth, with materials: the Simulator's lists of ``stride`` entries a
    particle (as at the chunk's start) laid out again twice as long, each entry's spring kept
    (state.plane_slip and scratch.contacts made longer for them); a list that overflowed keeps
    nothing (its pairs had no springs)."""
    from .arrays import ScratchArgs, StateArgs

    arrays, state = sim._scratch_arrays, sim.state
    N, K = num_particles, stride
    count = download(arrays["nbr_count"]).reshape(N)
    count = np.where(count > K, 0, count)
    lists = download(arrays["nbr_list"]).reshape(N, K)
    slips = download(state.plane_slip)
    planes = len(slips) - 2 * N * K
    used = np.arange(K)[None, :] < count[:, None]
    new_lists = np.zeros((N, 2 * K), lists.dtype)
    new_lists[:, :K] = np.where(used, lists, 0)
    new_springs = np.zeros((2, N, 2 * K, 3), slips.dtype)
    new_springs[0, :, :K] = np.where(used[..., None], slips[planes:planes + N * K].reshape(N, K, 3), 0)
    arrays["nbr_list"] = zeros(2 * K * N, "i")
    upload(arrays["nbr_list"], new_lists)
    upload(arrays["nbr_count"], count)
    state.plane_slip = zeros(planes + 4 * K * N, "v3")
    upload(state.plane_slip, np.concatenate([slips[:planes], new_springs.reshape(-1, 3)]))
    contacts = download(arrays["contacts"])
    counts = len(contacts) - K * N - N  # the contact counts before the kept lists
    arrays["contacts"] = zeros(counts + kept_size(N, 2 * K * N, True), "i")
    upload(arrays["contacts"], np.concatenate([contacts[:counts], np.zeros(2 * K * N + N, contacts.dtype)]))
    state.args = StateArgs()(**{name: getattr(state, name) for name in StateArgs.NAMES})
    sim.scratch = ScratchArgs()(**{name: arrays[name] for name in ScratchArgs.NAMES})


def springs_by_pair(sim) -> dict:
    """{(i, j): the spring slot i keeps for its pair with slot j} over the lists' entries in use
    (host, float of the run's precision; tests and diagnostics)."""
    arrays = sim._scratch_arrays
    count, lists = download(arrays["nbr_count"]).ravel(), download(arrays["nbr_list"]).ravel()
    K = len(lists) // len(count)
    slips = download(sim.state.plane_slip)
    slips = slips[len(slips) - 2 * len(lists):len(slips) - len(lists)]  # the current lists' (_springs)
    return {(i, int(lists[i * K + t])): slips[i * K + t] for i in range(len(count)) if count[i] <= K
            for t in range(count[i])}
