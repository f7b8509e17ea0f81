"""The facade a script, a window or a test drives: build, reset, step, read.

    sim = Simulator(config, units)      # after ti.init (see rigid.runtime.init_taichi)
    sim.step_frame()                    # 1/60 s: config.substeps substeps, one launch
    snap = sim.snapshot()               # host copy of the body state (float64 numpy)
"""
from __future__ import annotations

import numpy as np

from .integrate import Integrator
from ..bodies.mesh import BodyGeometry, body_geometry
from .model import Model
from .state import Params, State
from .units import check_units


class Simulator:
    def __init__(self, config, units, geometry: BodyGeometry | None = None):
        """Build from config (mesh path, scale, particles) or from a ready BodyGeometry."""
        check_units(units)
        self.config = config
        g = body_geometry(config) if geometry is None else geometry
        self.model = Model(g.particles, g.vertices, g.faces, config.particle_mass, units)
        self.state = State(self.model.num_bodies, self.model.num_particles, self.model.num_surface)
        self.params = Params(config)
        self.integrator = Integrator(self.model, self.state, self.params, units, config.integrator)
        self.reset()
        self.snapshot()  # compile the read-back kernels now, not in the middle of a run

    @property
    def substeps(self) -> int:
        """Substeps per frame for the current Δt (the GUI may change Δt)."""
        return max(1, int((1.0 / 60.0) // float(self.params.dt[None])))

    def reset(self):
        """Back to the initial state of the config; the model is kept (no mesh reload)."""
        c = self.config
        self.time = 0.0
        self.frame = 0
        self.integrator.init_state(c.position, c.initial_velocity, c.initial_angular_velocity)

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
        """Body 0's state and energies as float64 numpy: one row of the NPZ export."""
        s, m = self.state, self.model
        x, v, P, L, omega = (f.to_numpy()[0].astype(np.float64)
                             for f in (s.x, s.v, s.P, s.L, s.omega))
        q = s.q.to_numpy()[0].astype(np.float64)
        g = np.asarray(self.params.gravity[None].to_numpy(), dtype=np.float64)
        kinetic = 0.5 * P.dot(v) + 0.5 * L.dot(omega)
        potential = -m.mass * g.dot(x) + float(self.integrator.contact_energy())
        return dict(t=self.time, x=x, q=q, v=v, omega=omega, P=P, L=L,
                    kinetic_energy=kinetic, potential_energy=potential)
