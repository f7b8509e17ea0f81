"""The facade a script, a window or a test drives: build, reset, step, read.

    sim = Simulator(config, units)      # after ti.init (see rigid.runtime.init_taichi)
    sim.step_frame()                    # 1/60 s: config.substeps substeps, one launch
    block = sim.advance_frames(100)     # 100 frames in one launch, a row per frame (frame_rows.py)
    snap = sim.snapshot()               # host copy of the body state (float64 numpy)

One body (no ``[[body]]`` tables, or one without copies) runs the classic path
(integrate.py: the assignment's single body, serial, block-culled walls); a scene
with several bodies runs the many-body pipeline (world.py: grid, pair contact).
"""
from __future__ import annotations

import numpy as np

from ..bodies.mesh import BodyGeometry, body_geometry
from ..bodies.placement import BodySpec, check_inside_box, scene_bodies
from .frame_rows import FrameRows, split_rows
from .integrate import Integrator
from .model import BodyParts, Model
from .state import Params, State
from .units import check_units


class Simulator:
    def __init__(self, config, units, geometry: BodyGeometry | None = None,
                 bodies: list[BodySpec] | None = None):
        """Build from config (meshes, scales, particles), or from a ready BodyGeometry (one body)
        or list of BodySpec (many bodies, see rigid.bodies.placement)."""
        check_units(units)
        self.config = config
        self.many = config.many_bodies or (bodies is not None and len(bodies) > 1)
        if self.many:
            self.bodies = scene_bodies(config) if bodies is None else bodies
            self._bodies_from_config = bodies is None
            if config.walls:
                check_inside_box(self.bodies, config.floor, config.wall, use_radius=True)
            parts = [BodyParts(b.geometry.particles, b.geometry.vertices, b.geometry.faces, b.particle_mass,
                               b.radius, b.name) for b in self.bodies]
        else:
            self.bodies = None
            body = config.body_config(0)
            g = body_geometry(body) if geometry is None else geometry
            parts = [BodyParts(g.particles, g.vertices, g.faces, body.particle_mass)]
        self.model = Model(parts, units)
        self.state = State(self.model.num_bodies, self.model.num_particles, self.model.num_surface)
        self.params = Params(config)
        self.rows = FrameRows(self.model.num_bodies)
        if self.many:
            from .world import WorldIntegrator

            self.integrator = WorldIntegrator(self.model, self.state, self.params, units, config.integrator,
                                              rows=self.rows)
        else:
            self.integrator = Integrator(self.model, self.state, self.params, units, config.integrator,
                                         rows=self.rows)
        self.reset()
        self.snapshot()  # compile the read-back kernels now, not in the middle of a run

    @property
    def substeps(self) -> int:
        """Substeps per frame for the current Δt (the GUI may change Δt)."""
        return self._frame_steps()[1]

    def _frame_steps(self) -> tuple[float, int]:
        """(Δt, substeps per 1/60 s frame); Δt read once (each read costs ~5 µs)."""
        dt = float(self.params.dt[None])
        return dt, max(1, int((1.0 / 60.0) // dt))

    def reset(self):
        """Back to the initial state of the config; the model is kept (no mesh reload)."""
        self.time = 0.0
        self.frame = 0
        if self.many:
            b = self.bodies
            self.integrator.init_state(*(np.array([getattr(body, key) for body in b], np.float64)
                                         for key in ("position", "orientation", "velocity", "angular_velocity")))
        else:
            c = self.config.body_config(0)
            self.integrator.init_state(c.position, c.orientation, c.initial_velocity, c.initial_angular_velocity)

    # Changing these needs no new model and no recompile: they live in 0-d fields.
    RUNTIME_KEYS = frozenset(Params.NAMES) | {"gravity", "walls", "position", "initial_velocity",
                                               "initial_angular_velocity", "frames", "seed"}

    def reconfigure(self, **changes):
        """Change runtime parameters and initial conditions, then reset (no recompile)."""
        fixed = sorted(set(changes) - self.RUNTIME_KEYS)
        if fixed:
            raise ValueError(f"{fixed} need a new Simulator (they change the model or the kernels)")
        self.config = self.config.replace(**changes).validate()
        self.params.load(self.config)
        if self.many and set(changes) & self.PLACEMENT_KEYS:
            self._place_again()
        self.reset()
        return self

    PLACEMENT_KEYS = frozenset({"position", "initial_velocity", "initial_angular_velocity", "seed"})

    def _place_again(self):
        """Many bodies start from their BodySpecs: place them again from the changed config
        (the same meshes, so the model and kernels stay)."""
        if not self._bodies_from_config:
            raise ValueError("this Simulator was built from a list of bodies: build a new one to move them")
        bodies = scene_bodies(self.config)
        if [len(b.geometry.particles) for b in bodies] != [len(b.geometry.particles) for b in self.bodies]:
            raise ValueError("the changed config places other bodies: build a new Simulator")
        if self.config.walls:
            check_inside_box(bodies, self.config.floor, self.config.wall, use_radius=True)
        self.bodies = bodies

    def step_frame(self, substeps: int | None = None):
        """One frame (1/60 s, or ``substeps`` substeps); nothing is read back."""
        dt, n = self._frame_steps()
        n = n if substeps is None else substeps
        self.integrator.advance(n)
        self.time += n * dt
        self.frame += 1

    def advance_frames(self, frames: int) -> dict:
        """``frames`` frames in one launch (at most ``self.rows.capacity``), and the row of each:
        a block, the snapshot's keys with a leading frame axis (``t`` (frames,), ``x`` (frames, 3)
        for one body or (frames, B, 3) for many, ...)."""
        if not 1 <= frames <= self.rows.capacity:
            raise ValueError(f"frames = {frames}: one launch runs 1 to {self.rows.capacity} frames")
        dt, n = self._frame_steps()
        self.integrator.advance_recorded(n, frames)
        times = []
        for _ in range(frames):  # the same sums as frame by frame: t is bit-identical
            self.time += n * dt
            times.append(self.time)
        self.frame += frames
        return self._block(times)

    def apply_impulse(self, particle: int, impulse):
        """Hit particle ``particle`` with impulse J (N s, world frame): ΔP = J, ΔL = r × J."""
        if not 0 <= particle < self.model.num_particles:
            raise IndexError(f"particle {particle} out of range 0..{self.model.num_particles - 1}")
        self.integrator.apply_impulse(int(particle), [float(c) for c in impulse])

    def snapshot(self) -> dict:
        """The state and energies as float64 numpy: one row of the NPZ export. One body: its
        vectors (3,) and (4,); many: (B, 3) and (B, 4). Energies are totals."""
        row = {key: value[0] for key, value in self.current_block().items()}
        row["t"] = float(row["t"])
        return row

    def current_block(self) -> dict:
        """The current state as a block of one frame (see ``advance_frames``)."""
        self.rows.rewind()
        self.integrator.record()
        return self._block([self.time])

    def _block(self, times: list) -> dict:
        """The rows of the last launch, with the energies (float64, computed here, the same way for
        every block: kinetic ½ P·v + ½ L·ω, potential −M g·x + the contact springs')."""
        body, contact = self.rows.read(len(times))
        rows = split_rows(body)
        if not self.many:  # one body: (k, 3) vectors, not (k, 1, 3)
            rows = {key: value[:, 0] for key, value in rows.items()}
        g = np.asarray(self.params.gravity[None].to_numpy(), dtype=np.float64)
        P, v, L, omega, x = rows["P"], rows["v"], rows["L"], rows["omega"], rows["x"]
        if self.many:
            k = len(times)
            kinetic = 0.5 * (P * v).reshape(k, -1).sum(axis=1) + 0.5 * (L * omega).reshape(k, -1).sum(axis=1)
            potential = -((x @ g) @ self.model.body_mass_np) + contact
        else:
            kinetic = 0.5 * _dot3(P, v) + 0.5 * _dot3(L, omega)
            potential = -self.model.mass * _dot3(x, g) + contact
        return dict(t=np.asarray(times, np.float64), **rows, kinetic_energy=kinetic, potential_energy=potential)


def _dot3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise a·b of (k, 3) arrays, summed left to right."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]
