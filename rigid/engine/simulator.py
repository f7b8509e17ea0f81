"""The facade a script, a window or a test drives: build, reset, step, read.

    sim = Simulator(config, units)      # after ti.init (see rigid.runtime.init_taichi)
    sim.step_frame()                    # 1/60 s: config.substeps substeps, one launch
    snap = sim.snapshot()               # host copy of the body state (float64 numpy)

One body (no ``[[body]]`` tables, or one without copies) runs the classic path
(integrate.py: the assignment's single body, serial, block-culled walls); a scene
with several bodies runs the many-body pipeline (world.py: grid, pair contact).
"""
from __future__ import annotations

import numpy as np

from ..bodies.mesh import BodyGeometry, body_geometry
from ..bodies.placement import BodySpec, check_inside_box, scene_bodies
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
        if self.many:
            from .world import WorldIntegrator

            self.integrator = WorldIntegrator(self.model, self.state, self.params, units, config.integrator)
        else:
            self.integrator = Integrator(self.model, self.state, self.params, units, config.integrator)
        self.reset()
        self.snapshot()  # compile the read-back kernels now, not in the middle of a run

    @property
    def substeps(self) -> int:
        """Substeps per frame for the current Δt (the GUI may change Δt)."""
        return max(1, int((1.0 / 60.0) // float(self.params.dt[None])))

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
        self.reset()
        return self

    def step_frame(self, substeps: int | None = None):
        dt = float(self.params.dt[None])  # one read per frame: each costs ~5 µs
        n = max(1, int((1.0 / 60.0) // dt)) if substeps is None else substeps
        self.integrator.advance(n)
        self.time += n * dt
        self.frame += 1

    def apply_impulse(self, particle: int, impulse):
        """Hit particle ``particle`` with impulse J (N s, world frame): ΔP = J, ΔL = r × J."""
        if not 0 <= particle < self.model.num_particles:
            raise IndexError(f"particle {particle} out of range 0..{self.model.num_particles - 1}")
        self.integrator.apply_impulse(int(particle), [float(c) for c in impulse])

    def snapshot(self) -> dict:
        """The state and energies as float64 numpy: one row of the NPZ export. One body: its
        vectors (3,) and (4,); many: (B, 3) and (B, 4). Energies are totals."""
        s, m = self.state, self.model
        x, v, P, L, omega, q = (f.to_numpy().astype(np.float64) for f in (s.x, s.v, s.P, s.L, s.omega, s.q))
        g = np.asarray(self.params.gravity[None].to_numpy(), dtype=np.float64)
        if not self.many:
            x, v, P, L, omega, q = x[0], v[0], P[0], L[0], omega[0], q[0]
            kinetic = 0.5 * P.dot(v) + 0.5 * L.dot(omega)
            potential = -m.mass * g.dot(x) + float(self.integrator.contact_energy())
        else:
            kinetic = 0.5 * float((P * v).sum()) + 0.5 * float((L * omega).sum())
            potential = -float(m.body_mass_np.dot(x @ g)) + float(self.integrator.contact_energy())
        return dict(t=self.time, x=x, q=q, v=v, omega=omega, P=P, L=L,
                    kinetic_energy=kinetic, potential_energy=potential)
