"""Many bodies colliding through their particles: the substep as a pipeline of stages.

One substep (explicit or symplectic Euler; the forces are those of the state at
the start of the substep, as on the slides):
  1. particles  for each particle i of body b: rᵢ = R_b r0ᵢ, pᵢ = x_b + rᵢ,
                vᵢ = v_b + ω_b × rᵢ; put it in its grid cell (grid.py)
  2. grid       prefix sum of the cell counts, scatter, each cell in index order
  3. forces     fᵢ = TODO 2 (m g) + walls (on the particle's sphere, pair_contact.py)
                + Σ over particles j of other bodies in the 27 cells around:
                pair_contact.py's force, and its couple moving it to the contact point
  4. bodies     F = Σ TODO 3 (fᵢ), τ = Σ TODO 4 (pᵢ, x, R, r0ᵢ, fᵢ) + Σ coupleᵢ,
                summed over the body's particles in index order, then the
                scheme's update from (F, τ) (updates.py: TODO 5, 6, 7)
Every sum has a fixed order, so a run is bit-reproducible on any thread count.

Two ways to run a frame of n substeps, the same stages either way:
- "serial": one kernel launch per frame, one thread, every stage a plain loop;
  no thread wake-ups (15-70 µs per parallel loop on the project's 2 vCPUs), the
  better choice for small scenes on a CPU;
- "parallel": each stage a top-level (parallel) loop of one substep kernel,
  dispatched n times by a compute graph (one call from Python per frame), for
  large scenes and GPUs. ``SERIAL_MAX_PARTICLES`` chooses (measured: bench).
``advance_recorded`` runs frames with a row after each (frame_rows.py): serial,
a chunk of frames is one graph launch; parallel, a graph and a row kernel per frame.
"""
import os

import taichi as ti

from .frame_rows import ChunkGraphs, FrameRows, make_record_kernel
from .graphs import RepeatedGraphs
from .grid import NeighbourGrid
from .matvec import matvec
from .pair_contact import pair_force, sphere_wall_force
from .updates import make_updates

# Below this many particles a CPU runs a frame on one thread (scripts/bench.py, "world crossover").
SERIAL_MAX_PARTICLES = 16384


def world_uses_serial(num_particles: int) -> bool:
    override = os.environ.get("RIGID_WORLD_SERIAL_MAX_PARTICLES")
    limit = int(override) if override else SERIAL_MAX_PARTICLES
    cfg = ti.lang.impl.current_cfg()
    return cfg.arch in (ti.x64, ti.arm64) and (num_particles < limit or cfg.cpu_max_num_threads < 2)


class WorldIntegrator:
    def __init__(self, model, state, params, units, scheme: str = "euler", serial=None, rows=None):
        """``rows``: the FrameRows that ``advance_recorded`` writes (frame_rows.py; made here if None)."""
        self.model, self.state, self.params, self.scheme = model, state, params, scheme
        self.rows = FrameRows(model.num_bodies) if rows is None else rows
        n = model.num_particles
        self.grid = NeighbourGrid(n, 2.0 * max(float(model.radius_np.max()), 1e-6))
        self.particle_f = ti.Vector.field(3, float, shape=n)
        self.particle_couple = ti.Vector.field(3, float, shape=n)
        self.serial = world_uses_serial(n) if serial is None else bool(serial)
        self._build(units)

    def _build(self, u):
        model, s, prm, grid = self.model, self.state, self.params, self.grid
        f_out, couple_out = self.particle_f, self.particle_couple
        N, B, C, V = model.num_particles, model.num_bodies, grid.num_cells, model.num_surface
        store, euler_update, symplectic_update, init_body, impulse = make_updates(model, s, u)
        update = symplectic_update if self.scheme == "symplectic" else euler_update

        @ti.func
        def place_particle(i):
            b = model.particle_body[i]
            r = matvec(s.R[b], model.r0[i])
            p = s.x[b] + r
            s.particle_x[i] = p
            s.particle_v[i] = s.v[b] + s.omega[b].cross(r)
            grid.insert(i, p)

        @ti.func
        def walls_force(p, v, r):
            """The box's five planes on a particle's sphere of radius r (pair_contact.py)."""
            k, kd, mu = prm.collision_stiffness[None], prm.velocity_damping_stiffness[None], prm.friction_stiffness[None]
            floor, wall = prm.floor[None], prm.wall[None]
            f0, e0 = sphere_wall_force(p, v, r, ti.Vector([0.0, 1.0, 0.0]), floor, k, kd, mu)
            f1, e1 = sphere_wall_force(p, v, r, ti.Vector([1.0, 0.0, 0.0]), -wall, k, kd, mu)
            f2, e2 = sphere_wall_force(p, v, r, ti.Vector([-1.0, 0.0, 0.0]), -wall, k, kd, mu)
            f3, e3 = sphere_wall_force(p, v, r, ti.Vector([0.0, 0.0, 1.0]), -wall, k, kd, mu)
            f4, e4 = sphere_wall_force(p, v, r, ti.Vector([0.0, 0.0, -1.0]), -wall, k, kd, mu)
            return f0 + f1 + f2 + f3 + f4, e0 + e1 + e2 + e3 + e4

        @ti.func
        def particle_force(i):
            """fᵢ (gravity, walls, other bodies), the pairs' couple about pᵢ, the contact energy."""
            a = model.particle_body[i]
            p, v, r_a = s.particle_x[i], s.particle_v[i], model.particle_radius[a]
            f = u.gravity_force(model.particle_mass[a], prm.gravity[None])
            couple = ti.Vector.zero(float, 3)
            energy = 0.0
            if prm.walls[None]:
                fw, energy = walls_force(p, v, r_a)
                f += fw
            k, kd, mu = prm.collision_stiffness[None], prm.velocity_damping_stiffness[None], prm.friction_stiffness[None]
            x_a, v_a, w_a = s.x[a], s.v[a], s.omega[a]
            g = grid.cell_coords(p)
            for dz in range(-1, 2):
                for dy in range(-1, 2):
                    for part in range(3):
                        lo, hi = grid.row_range(g[0], g[1] + dy, g[2] + dz, part)
                        for slot in range(lo, hi):
                            j = grid.sorted_particle[slot]
                            b = model.particle_body[j]
                            if b != a:
                                fp, cp, ep = pair_force(p, s.particle_x[j], r_a, model.particle_radius[b],
                                                        x_a, v_a, w_a, s.x[b], s.v[b], s.omega[b], k, kd, mu)
                                f += fp
                                couple += cp
                                energy += ep
            return f, couple, energy

        @ti.func
        def store_force(i):
            f, couple, _energy = particle_force(i)
            f_out[i], couple_out[i] = f, couple

        @ti.func
        def body_step(b, dt):
            F = ti.Vector.zero(float, 3)
            tau = ti.Vector.zero(float, 3)
            x, R = s.x[b], s.R[b]
            start = model.body_start[b]
            for i in range(start, start + model.body_count[b]):
                f = f_out[i]
                F += u.total_force_term(f)
                tau += u.torque_term(s.particle_x[i], x, R, model.r0[i], f) + couple_out[i]
            update(b, dt, F, tau)

        @ti.func
        def place_surface(k):
            b = model.surface_body[k]
            s.surface_x[k] = s.x[b] + matvec(s.R[b], model.surface_r0[k])

        def make_place_all(scan):
            """Stages 1 and 2 as one ti.func: at a kernel's top level its loops run in parallel
            (then the scatter order varies and the cells need sort_cell), in a serial loop in
            index order (every cell comes out sorted)."""

            @ti.func
            def place_all():
                for c in range(C):
                    grid.clear_cell(c)
                for i in range(N):
                    place_particle(i)
                scan()
                for c in range(C):
                    grid.open_cell(c)
                for i in range(N):
                    grid.scatter(i)

            return place_all

        place_all_serial, place_all_parallel = make_place_all(grid.scan_serial), make_place_all(grid.scan_parallel)

        @ti.kernel
        def frame_serial(n: ti.i32):
            ti.loop_config(serialize=True)
            for _ in range(1):
                dt = prm.dt[None]
                for _step in range(n):
                    place_all_serial()
                    for i in range(N):
                        store_force(i)
                    for b in range(B):
                        body_step(b, dt)
                place_all_serial()
                for k in range(V):
                    place_surface(k)

        @ti.kernel
        def place_parallel():
            place_all_parallel()
            for c in range(C):
                grid.sort_cell(c)

        @ti.kernel
        def forces_and_bodies():
            for slot in range(N):  # in cell order: neighbours are close in memory
                store_force(grid.sorted_particle[slot])
            for b in range(B):
                body_step(b, prm.dt[None])

        @ti.kernel
        def finish_parallel():
            for k in range(V):
                place_surface(k)

        @ti.func
        def particle_energy(i):
            # Contact energy of particle i (the particles were placed at the frame's end).
            _f, _c, e = particle_force(i)
            return e

        @ti.kernel
        def init_bodies(x0: ti.types.ndarray(), q0: ti.types.ndarray(), v0: ti.types.ndarray(),
                        w0: ti.types.ndarray()):
            for b in range(B):
                init_body(b, ti.Vector([x0[b, 0], x0[b, 1], x0[b, 2]], float),
                          ti.Vector([q0[b, 0], q0[b, 1], q0[b, 2], q0[b, 3]], float),
                          ti.Vector([v0[b, 0], v0[b, 1], v0[b, 2]], float),
                          ti.Vector([w0[b, 0], w0[b, 1], w0[b, 2]], float))

        @ti.kernel
        def kick(i: ti.i32, J: ti.types.vector(3, float)):
            ti.loop_config(serialize=True)
            for _ in range(1):
                impulse(i, J)  # updates.py

        self.frame_serial, self.place_parallel = frame_serial, place_parallel
        self.forces_and_bodies, self.finish_parallel = forces_and_bodies, finish_parallel
        self._init_bodies, self._kick = init_bodies, kick
        gpu = ti.lang.impl.current_cfg().arch not in (ti.x64, ti.arm64)
        self.record = make_record_kernel(self.rows, s, N, particle_energy, parallel_energy=gpu)
        self.particle_energy = particle_energy  # ti.func of a particle index (tests build the GPU variant)
        self._chunks = ChunkGraphs(frame_serial, self.record)
        self._parallel_frames = RepeatedGraphs(repeated=[(place_parallel, False), (forces_and_bodies, False)],
                                               then=[(place_parallel, False), (finish_parallel, False)])

    def init_state(self, x0, q0, v0, w0):
        """Initial state of every body from (B, 3/4) float64 arrays, then the particles and meshes."""
        self._init_bodies(x0, q0, v0, w0)
        self.advance(0)

    def apply_impulse(self, particle: int, impulse):
        self._kick(particle, impulse)
        self.advance(0)

    def advance_recorded(self, substeps: int, frames: int):
        """``frames`` frames (at most ``self.rows.capacity``), each followed by its row, from row 0."""
        self.rows.rewind()
        if self.serial:
            self._chunks.run(substeps, frames)
            return
        for _ in range(frames):  # a frame on this path takes milliseconds
            self.advance(substeps)
            self.record()

    def advance(self, substeps: int):
        """n substeps of every body, then the particles and drawn vertices: one launch or one graph."""
        if self.serial:
            self.frame_serial(substeps)
            return
        self._parallel_frames.run(substeps)
