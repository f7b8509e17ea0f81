"""The facade a script, a window, a notebook or a test drives: build, reset, step, read.

    sim = Simulator(config, units)      # after ti.init (rigid.init)
    sim.step_frame()                    # 1/60 s: config.substeps substeps
    block = sim.advance_frames(100)     # 100 frames and a row per frame (rows.py)
    snap = sim.snapshot()               # host copy of the bodies' state (float64 numpy)

Every scene, one body or many, runs the same pipeline (stages.py) with kernels compiled
once per process (kernels.py): a Simulator only allocates its arrays. Shapes in the API are
per body, always: ``x`` (B, 3), ``q`` (B, 4), ...; a block of frames adds a leading frame
axis. (The NPZ export keeps one body's rows as (F, 3): rigid.run.diagnostics.)
"""
from __future__ import annotations

import numpy as np

from ..bodies.mesh import BodyGeometry
from ..bodies.colliders import check_colliders, uses_materials
from ..bodies.overlap import check_start
from ..bodies.placement import BodySpec, check_inside_box, scene_bodies
from ..bodies.springs import resolve_springs, spring_ends, spring_energy
from ..bodies.statics import static_bodies, static_faces
from . import broadphase, broadphase_host
from .arrays import clear, download, host_float, upload
from .pushes import Pushes
from .kernels import engine_kernels
from .refresh import worth_refreshing
from .list_growth import ListGrowth
from .scratch import make_scratch, particle_diameter
from .skin import AdaptiveSkin, widest_fraction
from .launch import run_chunk, schedule_launches
from .model import BodyParts, Model
from .neighbours import NEIGHBOURS_PER_PARTICLE, SKIN_FRACTION
from .rows import FrameRows, split_rows, with_energies
from .schedule import check_schedule, choose_schedule
from .state import Params, State
from .units import check_units
from .worlds import all_worlds, by_world, cell_shifts, check_worlds, span_in_cells, world_table


class Simulator(Pushes):
    def __init__(self, config, units=None, geometry: BodyGeometry | None = None,
                 bodies: list[BodySpec] | None = None, schedule: str | None = None, worlds: int = 1,
                 vary: dict | None = None):
        """Build from ``config`` (meshes, scales, particles; rigid.config.SimConfig), or from a
        ready ``geometry`` (one body at the config's pose) or list of ``bodies``
        (rigid.bodies.placement.BodySpec). ``units``: the 7 TODO ``ti.func``s (default: the
        repository's solved rigid_body_dynamic.py). ``schedule``: "serial" or "parallel"
        (default: schedule.py chooses). ``worlds``: that many copies of the scene, stepped
        together, none touching another, each with its values of ``vary`` (worlds.py); rows
        then gain a world axis before the body axis, and energies are per world."""
        if units is None:
            from .units import default_units

            units = default_units()
        check_units(units)
        check_colliders(config)  # [[plane]] and [[static]] tables: one line for a bad one
        self.config, self.units = config, units
        self._bodies_from_config = bodies is None and geometry is None
        if geometry is not None:
            bodies = [BodySpec.from_geometry(config, geometry)]
        self.bodies = scene_bodies(config) if bodies is None else list(bodies)
        self.bodies += static_bodies(config, self.bodies)
        if config.walls:
            check_inside_box([b for b in self.bodies if not b.static], config.floor, config.wall, use_radius=True)
        varied = check_worlds(worlds, vary, len(self.bodies))
        # Convex statics touched at their faces (static_faces.py); their planes are every world's.
        faces = {} if {"position", "orientation"} & set(varied) else static_faces(config, self.bodies)
        self._faces = faces
        check_start(config, self.bodies, faces)  # no body behind a [[plane]] or inside another
        self.springs = resolve_springs(config.springs, np.array([b.position for b in self.bodies]),
                                       np.array([b.orientation for b in self.bodies]))
        pairs = len(self.bodies) > 1  # bodies that may touch: within a world
        per_world = len(self.bodies)
        self.num_worlds = worlds = int(worlds)
        if worlds > 1 or varied:
            self.bodies, self.springs = all_worlds(config, self.bodies, self.springs, worlds, varied)
        self.materials = materials = uses_materials(config)
        self.kernels = engine_kernels(units, config.integrator, pairs=pairs, materials=materials,
                                      refreshing=worth_refreshing(len(self.bodies)))
        parts = [BodyParts(b.geometry.particles, b.geometry.vertices, b.geometry.faces, b.particle_mass,
                           b.radius, b.name, b.restitution, b.friction, b.static, b.drag, i % per_world in faces)
                 for i, b in enumerate(self.bodies)]
        self.model = Model(parts, self.kernels, worlds)
        B, N = self.model.num_bodies, self.model.num_particles
        self.state = State(B, N, materials, N * NEIGHBOURS_PER_PARTICLE if pairs else 0)
        self.params = Params(config)
        self.params.set_faces(faces.values())
        self.params.set_springs([s.row() for s in self.springs], worlds)
        self.params.sleep = self.params.sleep and not self.springs  # a spring's far end moves a sleeper
        self.rows = FrameRows(B, worlds)
        skin = widest_fraction(self.model) if pairs else SKIN_FRACTION
        self.scratch, self._scratch_arrays, self.grid_shape = make_scratch(self.model, config, pairs, self.materials, skin)
        if worlds > 1 and pairs:  # each world in cells of its own
            shifts = cell_shifts(worlds, B // worlds, span_in_cells(self.bodies, config, 1.0 / self.scratch_cell()))
            upload(self.model.body_world, world_table(worlds, B // worlds, shifts))
        self._launches = None
        self._lists = ListGrowth(N, pairs)
        self._skin = AdaptiveSkin(particle_diameter(self.model), skin, pairs, self._scratch_arrays)
        self.schedule = choose_schedule(N, pairs, schedule)
        self._surface_out = np.empty((max(self.model.num_surface, 1), 3), host_float())
        self.reset()

    @property
    def schedule(self) -> str:
        """"serial" or "parallel" (rigid.engine.schedule); may be set between frames."""
        return self._schedule

    @schedule.setter
    def schedule(self, value: str) -> None:
        self._schedule, self._launches = check_schedule(value), None  # its launches made at the next run

    @property
    def num_bodies(self) -> int:
        return self.model.num_bodies

    @property
    def num_particles(self) -> int:
        return self.model.num_particles

    @property
    def many(self) -> bool:
        """Whether bodies collide with one another (B > 1)."""
        return self.model.num_bodies > 1

    def scratch_cell(self) -> float:
        """The grid's cell size, m (scratch.py)."""
        return 1.0 / broadphase_host.float_value(self._scratch_arrays, broadphase.INV_CELL)

    @property
    def substeps(self) -> int:
        """Substeps per frame for the current Δt (a window's slider may change Δt)."""
        return max(1, int((1.0 / 60.0) // self.params.dt))

    @property
    def neighbour_builds(self) -> int:
        """How many times the neighbour lists were built (benchmarks: rebuilds per substep)."""
        return broadphase_host.builds(self._scratch_arrays)

    def neighbour_counts(self) -> np.ndarray:
        """(N,) candidates in each particle's list at its last build (slot order; benchmarks)."""
        return download(self._scratch_arrays["nbr_count"])

    def reset(self):
        """Back to the initial state of the bodies; the model is kept (no mesh reload)."""
        self.time = 0.0
        self.frame = 0
        self.release()
        clear(self.state.sleep)  # every body awake
        broadphase_host.reset(self._scratch_arrays, self.model)  # lists built at the next placement, no touches
        self._params_version = self.params.version
        self.state.clear_contacts()
        clear(self._scratch_arrays["contacts"])
        b = self.bodies
        self.kernels.init_bodies(self.model.args, self.state.args,
                                 *(np.array([getattr(body, key) for body in b], np.float64)
                                   for key in ("position", "orientation", "velocity", "angular_velocity")))

    # Changing these needs no new model: they are runtime parameters or initial conditions.
    RUNTIME_KEYS = frozenset(Params.NAMES) | {"gravity", "walls", "sleep", "position", "initial_velocity",
                                               "initial_angular_velocity", "frames", "seed"}
    PLACEMENT_KEYS = frozenset({"position", "initial_velocity", "initial_angular_velocity", "seed"})

    def reconfigure(self, **changes):
        """Change runtime parameters and initial conditions, then reset (nothing recompiles)."""
        fixed = sorted(set(changes) - self.RUNTIME_KEYS)
        if fixed:
            raise ValueError(f"{fixed} need a new Simulator (they change the model)")
        self.config = check_colliders(self.config.replace(**changes).validate())
        self.params.load(self.config)
        if set(changes) & self.PLACEMENT_KEYS:
            self._place_again()
        self.reset()
        return self

    def _place_again(self):
        """Place the bodies again from the changed config (the same meshes, so the model stays)."""
        if self.num_worlds > 1:
            raise ValueError("a Simulator of many worlds keeps its bodies' starts: build a new one to move them")
        if not self._bodies_from_config:
            if len(self.bodies) == 1:  # one body from a geometry: move it
                c, body = self.config, self.bodies[0]
                body.position, body.velocity = np.asarray(c.position, float), np.asarray(c.initial_velocity, float)
                body.angular_velocity = np.asarray(c.initial_angular_velocity, float)
                return
            raise ValueError("this Simulator was built from a list of bodies: build a new one to move them")
        bodies = scene_bodies(self.config)
        bodies += static_bodies(self.config, bodies)
        if [len(b.geometry.particles) for b in bodies] != [len(b.geometry.particles) for b in self.bodies]:
            raise ValueError("the changed config places other bodies: build a new Simulator")
        if self.config.walls:
            check_inside_box([b for b in bodies if not b.static], self.config.floor, self.config.wall, use_radius=True)
        check_start(self.config, bodies, self._faces)
        self.bodies = bodies

    def step_frame(self, substeps: int | None = None):
        """One frame (int(1/60 // dt) substeps, 16 ms at the default dt; or ``substeps`` substeps);
        its row is kept on the device."""
        n = self.substeps if substeps is None else int(substeps)
        self._run(1, n)
        self.time += n * self.params.dt
        self.frame += 1

    def advance_frames(self, frames: int) -> dict:
        """``frames`` frames and the row of each: a block, the snapshot's keys with a leading
        frame axis (``t`` (frames,), ``x`` (frames, B, 3), ...). Runs in chunks of
        ``rows.capacity`` frames, one launch each on the serial schedule."""
        if frames < 1:
            raise ValueError(f"frames = {frames}: advance at least one frame")
        blocks = []
        done = 0
        while done < frames:
            k = min(self.rows.capacity, frames - done)
            n, dt = self.substeps, self.params.dt
            self._run(k, n)
            times = []
            for _ in range(k):  # the same sums as frame by frame: t is bit-identical
                self.time += n * dt
                times.append(self.time)
            self.frame += k
            blocks.append(self._block(times))
            done += k
        if len(blocks) == 1:
            return blocks[0]
        return {key: np.concatenate([b[key] for b in blocks]) for key in blocks[0]}

    def advance(self, frames: int) -> dict:
        """A trajectory from now: row 0 the current state, then one row per frame (frames + 1
        rows, the NPZ's keys with a body axis: ``x`` (frames + 1, B, 3), ...)."""
        start = self.current_block()
        block = self.advance_frames(frames)
        return {key: np.concatenate([start[key], block[key]]) for key in block}

    def _run(self, frames: int, substeps: int):
        """``frames`` frames of ``substeps`` substeps, rows 0 .. frames − 1 written (run again with
        longer neighbour lists if a build overflowed them: list_growth.py)."""
        if self._params_version != self.params.version:  # a runtime parameter changed: wake every body
            self.wake()
        self._lists.run(self, lambda: run_chunk(self._prepared_launches(), self.schedule, frames, substeps))
        self._skin.after_chunk(self, frames * substeps)  # skin.py

    def _prepared_launches(self) -> dict:
        """The launches of this Simulator's schedule, made on first use (a Simulator only read
        costs nothing here) and only for its schedule: a kernel is compiled when first launched,
        so a serial run never compiles the parallel kernels (a lone body's first run ~40 % less)."""
        if self._launches is None:
            self._launches = schedule_launches(self.schedule, self.kernels, self.model.args, self.state.args,
                                               self.params.args, self.scratch, self.rows.args)
        return self._launches

    def snapshot(self) -> dict:
        """The state and energies as float64 numpy: ``t``; per body ``x`` (B, 3), ``q`` (B, 4),
        ``v``, ``omega``, ``P``, ``L`` (B, 3); ``kinetic_energy``, ``potential_energy`` totals."""
        row = {key: value[0] for key, value in self.current_block().items()}
        row["t"] = float(row["t"])
        return row

    def current_block(self) -> dict:
        """The current state as a block of one frame (see ``advance_frames``)."""
        launch = self._prepared_launches()
        if self.schedule == "serial":  # a frame of no substeps: the particles placed, the row written
            launch["run_frames"](frames=1, substeps=0)
        else:
            launch["finish_frame"](slot=0)
        return self._block([self.time])

    def spring_ends(self) -> np.ndarray:
        """(2 S, 3) float64 world positions of the [[spring]]s' ends, each spring's two in turn."""
        return spring_ends(self.springs, download(self.state.x), download(self.state.q))

    def particle_positions(self) -> np.ndarray:
        """(N, 3) float64 world positions of the particles, in the mesh files' order."""
        return download(self.state.particle_x).astype(np.float64)[self.model.slot_of]

    def particle_velocities(self) -> np.ndarray:
        """(N, 3) float64 world velocities of the particles, in the mesh files' order."""
        return download(self.state.particle_v).astype(np.float64)[self.model.slot_of]

    def particle_bodies(self) -> np.ndarray:
        """(N,) the body of each particle, in the mesh files' order."""
        return np.repeat(np.arange(self.model.num_bodies), self.model.body_count_np)

    def surface_positions(self) -> np.ndarray:
        """(V, 3) world positions of the drawn meshes' vertices (float of the run's precision)."""
        self.kernels.place_surfaces(self.state.args, self.model.surface_args, self._surface_out)
        return self._surface_out

    def _block(self, times: list) -> dict:
        """The rows of the last launch, with the energies (rows.with_energies)."""
        body, contact = self.rows.read(len(times))
        rows = split_rows(body)
        W = self.num_worlds
        if self.springs:  # their energy ½ k (|d| − l0)², beside the contacts', world by world
            per = len(self.springs) // W
            contact = contact + np.column_stack([spring_energy(self.springs[w * per:(w + 1) * per], rows["x"], rows["q"])
                                                 for w in range(W)])
        moving_mass = np.where(self.model.static_np, 0.0, self.model.body_mass_np)
        if W == 1:
            return with_energies(rows, contact[:, 0], times, self.params.gravity, moving_mass)
        return with_energies(by_world(rows, W), contact, times, self.params.gravity, moving_mass)
