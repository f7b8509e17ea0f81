"""Static friction between bodies: each contact pair's tangential spring, kept beside the lists.

With materials, a pair of particles in contact carries a sticking spring (contact.py:
``pair_contact_sticking``, Cundall-Strack as on the planes): its stretch must live as long as
the contact, across substeps and across the neighbour lists' rebuilds. It is kept per list
entry: ``scratch.pair_slip[i·K + t]`` is the stretch of the pair (i, nbr_list[i·K + t]). Each
particle keeps its own copy of each of its pairs, so the pair stage writes only its own slot's
entries (no atomics on other particles' lists: a GPU and Vulkan run it as the CPU does). Both
copies evolve bit for bit alike: the pair is evaluated from its lower slot's side whichever
side asks (material_stages._material_pair), on the same numbers, and both start at zero.

A rebuild makes new lists, so before it ``keep`` copies each particle's list and springs aside
and after it (the lists sorted by slot) ``carry`` gives each entry the spring its pair had: a
merge of two sorted lists; a pair new to the list starts at zero. A pair that left the list was
apart (beyond reach + skin), where its spring is zero anyway, so the springs do not depend on
when the lists were rebuilt.

Where a particle's list overflowed (it walks the grid, candidates.py), its pairs have no entry:
they fall back to the viscous law (friction c_t |v_t| capped at μ f_n), from both sides (the
other side sees the overflow in the count), until the lists grow (list_growth.py) and the
chunk is run again; past ``MAX_NEIGHBOURS`` they stay viscous.

Arrays (ScratchArgs, one element each without materials): ``pair_slip`` [2·N·K] vec3, the
springs of the current lists, then [N·K ..) those of the last lists during a rebuild;
``kept_list`` [N·K + N] i32, the last lists, then [N·K + i] their counts.
"""

import numpy as np
import taichi as ti

from . import neighbours
from .arrays import download, upload, zeros


@ti.func
def keep(state: ti.template(), scratch: ti.template(), i):
    """Before a rebuild: slot i's list, its count and its springs copied aside."""
    stride = neighbours.list_stride(scratch, state)
    size = scratch.nbr_list.shape[0]
    n = scratch.nbr_count[i]
    scratch.kept_list[size + i] = n
    base = i * stride
    t = 0
    while t < n and t < stride:  # an overflowed list (n > stride) kept its first entries only
        scratch.kept_list[base + t] = scratch.nbr_list[base + t]
        scratch.pair_slip[size + base + t] = scratch.pair_slip[base + t]
        t += 1


@ti.func
def carry(state: ti.template(), scratch: ti.template(), i):
    """After a rebuild (slot i's list sorted): each entry's spring from the kept list, else zero."""
    stride = neighbours.list_stride(scratch, state)
    size = scratch.nbr_list.shape[0]
    base = i * stride
    n = scratch.nbr_count[i]
    m = scratch.kept_list[size + i]
    if m > stride:  # it walked the grid: no springs were kept
        m = 0
    if n > stride:  # it walks the grid: its entries are not in use
        n = 0
    u = 0
    t = 0
    while t < n:
        j = scratch.nbr_list[base + t]
        while u < m and scratch.kept_list[base + u] < j:
            u += 1
        s = ti.Vector.zero(float, 3)
        if u < m and scratch.kept_list[base + u] == j:
            s = scratch.pair_slip[size + base + u]
        scratch.pair_slip[base + t] = s
        t += 1


def grown(arrays, num_particles, stride):
    """The host's part of list_growth: ``arrays`` (the scratch arrays by name, their lists of
    ``stride`` entries a particle, as at the chunk's start) laid out again for lists twice as long,
    each entry's spring kept; a list that overflowed keeps nothing (its pairs had no springs)."""
    N, K = num_particles, stride
    count = download(arrays["nbr_count"]).reshape(N)
    lists = download(arrays["nbr_list"]).reshape(N, K)
    slips = download(arrays["pair_slip"])[:N * K].reshape(N, K, 3)
    used = np.arange(K)[None, :] < np.where(count > K, 0, count)[:, None]
    new_lists = np.zeros((N, 2 * K), lists.dtype)
    new_slips = np.zeros((2, N, 2 * K, 3), slips.dtype)
    new_lists[:, :K] = np.where(used, lists, 0)
    new_slips[0, :, :K] = np.where(used[..., None], slips, 0)
    arrays["nbr_list"] = zeros(2 * K * N, "i")
    upload(arrays["nbr_list"], new_lists)
    arrays["pair_slip"] = zeros(2 * 2 * K * N, "v3")
    upload(arrays["pair_slip"], new_slips)
    arrays["kept_list"] = zeros(2 * K * N + N, "i")
    upload(arrays["nbr_count"], np.where(count > K, 0, count))
