"""The arrays a substep rewrites (ScratchArgs: forces, partial sums, the grid, the neighbour
lists, the broadphase's scalars and per-body tables, RK4, the material contacts' counts), sized
for a Model and a scene. What each holds: arrays.py, grid.py, neighbours.py, broadphase.py,
material_stages.py, pair_slip.py."""
from __future__ import annotations

from . import broadphase_host, neighbours, pair_slip
from .arrays import ScratchArgs, zeros
from .grid import GridShape


def make_scratch(model, config, pairs: bool, materials: bool, skin_fraction: float):
    """(ScratchArgs pack, its arrays by name, the GridShape), the lists' skin ``skin_fraction``
    of the largest particle diameter (skin.widest_fraction)."""
    B, N, K = model.num_bodies, model.num_particles, model.num_blocks
    diameter = particle_diameter(model)
    cell = diameter + skin_fraction * diameter
    span = 2.0 * config.wall / cell + 2 if config.walls else 0.0
    shape = GridShape.for_particles(N, pairs, span)
    lists = N * neighbours.NEIGHBOURS_PER_PARTICLE if pairs else 1
    paired = N if pairs else 1  # per particle, only when bodies collide
    arrays = dict(particle_f=zeros(N, "v3"), particle_couple=zeros(N, "v3"), block_energy=zeros(K),
                  block_wrench=zeros(K, "v6"),
                  cell_count=zeros(shape.num_cells, "i"), cell_start=zeros(shape.num_cells + 1, "i"),
                  sorted_particle=zeros(N, "i"), sorted_x=zeros(paired, "v3"),
                  sorted_body=zeros(paired, "i"), sorted_run_end=zeros(paired, "i"),
                  chunk_total=zeros(shape.num_chunks + 1, "i"),
                  nbr_count=zeros(paired, "i"), nbr_list=zeros(lists, "i"), build_x=zeros(paired, "v3"),
                  active=zeros(paired, "i"), rk=zeros(2 * B, "v13"),
                  contacts=zeros(N + 2 * K + 2 * B + pair_slip.kept_size(N, lists, pairs) if materials else 1, "i"),
                  **broadphase_host.make_arrays(model, shape, diameter, skin_fraction))
    return ScratchArgs()(**{name: arrays[name] for name in ScratchArgs.NAMES}), arrays, shape


def particle_diameter(model) -> float:
    """The largest particle diameter (the grid's cells are this plus the lists' skin)."""
    return 2.0 * max(float(model.radius_np.max()), 1e-6)
