"""The arrays a substep rewrites (ScratchArgs: forces, partial sums, the grid, the neighbour
lists, RK4, the material contacts' counts), sized for a Model and a scene. What each holds:
arrays.py, grid.py, neighbours.py, material_stages.py, pair_slip.py."""
from __future__ import annotations

import numpy as np
import taichi as ti

from . import neighbours, pair_slip, refresh, refresh_state
from .arrays import ScratchArgs, device_array, zeros
from .grid import GridShape


def make_scratch(model, config, pairs: bool, materials: bool):
    """(ScratchArgs pack, its arrays by name, the GridShape)."""
    B, N, K = model.num_bodies, model.num_particles, model.num_blocks
    diameter = particle_diameter(model)
    cell = diameter + neighbours.SKIN_FRACTION * diameter
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
                  grid_dims=device_array(np.array([shape.dim, shape.num_cells, shape.num_chunks]), dtype=ti.i32),
                  grid_params=device_array(grid_params(diameter, neighbours.SKIN_FRACTION)),
                  nbr_count=zeros(paired, "i"), nbr_list=zeros(lists, "i"), build_x=zeros(paired, "v3"),
                  nbr_flags=zeros(refresh_state.flags_size(B) if pairs else 3, "i"), active=zeros(paired, "i"), build_pose=device_array(build_pose(model), 16),
                  rk=zeros(2 * B, "v13"),
                  contacts=zeros(N + 2 * K + 2 * B + pair_slip.kept_size(N, lists, pairs) if materials else 1, "i"))
    return ScratchArgs()(**{name: arrays[name] for name in ScratchArgs.NAMES}), arrays, shape


def grid_params(diameter: float, skin_fraction: float) -> np.ndarray:
    """grid_params for a skin of ``skin_fraction`` diameters: 1 / the cell (the diameter plus the
    skin), the skin, the relative motion allowed before a rebuild (grid.py, neighbours.py), the
    largest particle radius (pair_stages.pair_between), the share of the particles a refresh may
    cover and what a full build costs in refreshed particles, per particle (refresh.py); then nine
    slots for the motion test's reductions off a CPU (motion.REDUCED, note_motion_spread)."""
    skin = skin_fraction * diameter
    return np.array([1.0 / (diameter + skin), skin, neighbours.ALLOWED_MOTION * skin, 0.5 * diameter,
                     refresh.REFRESH_FRACTION, refresh.BUILD_COST] + [0.0] * 9)


def particle_diameter(model) -> float:
    """The largest particle diameter (the grid's cells are this plus the lists' skin)."""
    return 2.0 * max(float(model.radius_np.max()), 1e-6)


def build_pose(model) -> np.ndarray:
    """(B, 16) the neighbour lists' pose per body (set at each build), with ρ_b, the body's
    largest particle offset |r0| (rounded up), in slot 12; slots 13, 14 are note_motion's
    (motion.py), then part_cut's; slot 15 the body's touching particles at the parallel pair
    stage's last run (part_cut.py)."""
    norms = np.linalg.norm(model.r0_np, axis=1)
    pose = np.zeros((model.num_bodies, 16))
    pose[:, 12] = [norms[s:s + c].max() * (1 + 1e-6) + 1e-9 for s, c in zip(model.body_start_np, model.body_count_np)]
    return pose
