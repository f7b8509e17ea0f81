"""Per-step data (``State``) and the runtime parameters (``Params``).

``State`` holds, per body (shape [B], world frame):
- ``x``  vec3  centre of mass, m
- ``q``  vec4  orientation, unit quaternion, scalar first [s, vx, vy, vz]
- ``P``  vec3  linear momentum, kg m/s
- ``L``  vec3  angular momentum about the centre of mass, kg m²/s
and the auxiliaries derived from them after every substep:
- ``v`` = P / M, ``R`` = R(q) (mat3), ``inertia_inv`` = R I0⁻¹ Rᵀ (mat3), ``omega`` = I⁻¹ L (rad/s)
Per particle slot (shape [N], world frame): ``particle_x`` = x + R r0, ``particle_v`` = v + ω × R r0,
placed from the body state at the start of every substep and at the end of every frame.
A reset writes the initial state into the same arrays (no new arrays, no recompile).

``Params`` are the scalars a window's slider may change between frames: Δt, the contact's
stiffness, damping and friction, gravity, the box (floor y, walls ±x, ±z, on or off). They
live on the host and, for the kernels, in ``WorldArgs`` (``values`` and ``planes``: the
static colliders, the box as five planes n·p = offset with n pointing into the box, then the
[[plane]] tables, then the faces of the convex static meshes, rigid.engine.static_faces).
"""
from __future__ import annotations

import numpy as np

from ..bodies import colliders
from .arrays import StateArgs, WorldArgs, clear, upload, zeros
from .forces import NUM_SPRINGS
from .grab import GRAB_FIRST, GRAB_VALUES, released
from .materials import damping_table, friction_value

# Slots of WorldArgs.values (then the mouse's grab, grab.py, from GRAB_FIRST on).
DT, STIFFNESS, DAMPING, FRICTION, GX, GY, GZ, NUM_PLANES, SLEEP_SPEED, SLEEP_STEPS = range(10)
NUM_VALUES = GRAB_FIRST + GRAB_VALUES
SLEEP_SPEED_DEFAULT = 0.05  # m/s: sleeping (sleep.py) below this speed bound of a body's particles ...
SLEEP_TIME_DEFAULT = 0.5  # ... for this long, s
MAX_PLANES = colliders.MAX_PLANES
# With materials, WorldArgs.values goes on: from MATERIALS each plane's (μ, e, 0, 0) (−1: unset),
# from MATERIALS + MATERIAL_TABLE the scheme's materials.damping_table (one array, not three:
# Taichi's x64 backend takes at most 64 argument elements a kernel).
MATERIALS = NUM_VALUES
MATERIAL_TABLE = 4 * MAX_PLANES


class State:
    def __init__(self, num_bodies: int, num_particles: int, materials: bool = False, lists: int = 0):
        B, N = num_bodies, num_particles
        kinds = dict(x="v3", q="v4", P="v3", L="v3", v="v3", omega="v3", R="m3", inertia_inv="m3")
        for name, kind in kinds.items():
            setattr(self, name, zeros(B, kind))
        self.particle_x = zeros(N, "v3")
        self.particle_v = zeros(N, "v3")
        self.sleep = zeros(B, "v3i")  # (asleep, quiet substeps, woken): sleep.py
        # Materials only (material_stages.py): each particle's tangential spring on each plane
        # [N·MAX_PLANES] vec3 (world, m), then those of the pairs in the ``lists`` entries of the
        # neighbour lists and their copies during a rebuild [2 · lists] (pair_slip.py).
        self.plane_slip = zeros(N * MAX_PLANES + 2 * lists if materials else 1, "v3")
        self.args = StateArgs()(**{name: getattr(self, name) for name in StateArgs.NAMES})


    def clear_contacts(self) -> None:
        """Forget the contacts' memory (a reset): no spring stretched."""
        clear(self.plane_slip)


class Params:
    NAMES = ("dt", "collision_stiffness", "velocity_damping_stiffness", "friction_stiffness",
             "floor", "wall")

    def __init__(self, config):
        # The damping table only with materials (about 1 s to make: damping_table.py).
        self.table = damping_table(config.integrator).reshape(-1) if colliders.uses_materials(config) else np.zeros(0)
        self.values = zeros(MATERIALS + MATERIAL_TABLE + len(self.table))
        self.planes = zeros(MAX_PLANES, "v4")
        # [[spring]] rows (rigid.bodies.springs.Spring.row), set by the Simulator once the bodies are placed.
        self.spring_rows = np.zeros((0, 16))
        self.springs_per_world = 0
        self.springs = zeros(max(len(getattr(config, "springs", ())), 1), "v16")
        self.args = WorldArgs()(values=self.values, planes=self.planes, springs=self.springs)
        self._loading = True
        self.face_groups = []  # convex [[static]] meshes' faces (set_faces), kept across loads
        self.grab_values = released()  # the mouse's spring (grab.py): kept across loads and uploads
        self.load(config)

    def load(self, config) -> None:
        """Take the config's runtime values (one upload)."""
        self._loading = True
        for name in self.NAMES:
            setattr(self, name, float(getattr(config, name)))
        self.gravity = np.asarray(config.gravity, np.float64)
        self.walls = bool(config.walls)
        self.sleep = bool(getattr(config, "sleep", True))
        self.sleep_speed, self.sleep_time = SLEEP_SPEED_DEFAULT, SLEEP_TIME_DEFAULT
        # [[plane]] tables (n, offset n·point), and every plane's material (μ, ζ): the box's
        # from the top level, a table's own or the top level's.
        self.extra_planes = [list(p["normal"]) + [float(np.dot(p["normal"], p["point"]))] for p in config.planes]
        top = dict(restitution=config.restitution, friction=config.friction)
        material = lambda t: (friction_value(t.get("friction")), friction_value(t.get("restitution")), 0.0, 0.0)
        self.box_material = material(top)
        self.extra_materials = [material({**top, **{k: v for k, v in p.items() if v is not None}})
                                for p in config.planes]
        self._loading = False
        self.upload()

    def __setattr__(self, name, value):
        object.__setattr__(self, name, value)
        if name in self.NAMES or name in ("gravity", "walls", "sleep", "sleep_speed", "sleep_time"):
            if name == "gravity":
                object.__setattr__(self, name, np.asarray(value, np.float64).reshape(3))
            if not getattr(self, "_loading", True):
                self.upload()

    def set_springs(self, rows, worlds: int = 1) -> None:
        """The scene's springs (rigid.bodies.springs.Spring.row each), for the kernels; with many
        worlds, each world's in turn (rigid.engine.worlds)."""
        self.spring_rows = np.asarray(rows, np.float64).reshape(-1, 16)
        self.springs_per_world = len(self.spring_rows) // worlds
        if len(self.spring_rows) > self.springs.shape[0]:  # more than the scene's (many worlds' copies)
            self.springs = zeros(len(self.spring_rows), "v16")
            self.args = WorldArgs()(values=self.values, planes=self.planes, springs=self.springs)
        if len(self.spring_rows):
            upload(self.springs, self.spring_rows)
        self.upload()

    def set_faces(self, groups) -> None:
        """The convex static meshes touched at their faces (rigid.engine.static_faces): per mesh,
        (its face planes (F, 4): outward normal, offset; its (μ, e), None: unset), after the other planes."""
        self.face_groups = [(np.asarray(planes, np.float64).reshape(-1, 4), tuple(map(friction_value, material)))
                            for planes, material in groups]
        self.upload()

    def plane_list(self) -> np.ndarray:
        """The static planes (n, 4): normal (into the free side) and offset n·p, in force order:
        the box's (if walls), the [[plane]] tables', the static meshes' faces."""
        extra = np.array(getattr(self, "extra_planes", []), np.float64).reshape(-1, 4)
        faces = [planes for planes, _m in getattr(self, "face_groups", [])]
        if self.walls:
            f, w = self.floor, self.wall
            extra = np.concatenate([[[0, 1, 0, f], [1, 0, 0, -w], [-1, 0, 0, -w], [0, 0, 1, -w], [0, 0, -1, -w]],
                                    extra])
        return np.concatenate([extra, *faces]) if faces else extra

    def _material_rows(self, planes) -> list:
        """Each plane's row (μ, e, first, count): a static mesh's faces name their mesh's planes."""
        rows = [self.box_material] * (5 if self.walls else 0) + list(self.extra_materials)
        for faces, (mu, e) in self.face_groups:
            rows += [(mu, e, len(rows), len(faces))] * len(faces)
        return rows

    def upload(self, wakes: bool = True) -> None:
        """Copy the values to the device; ``wakes``: a change every body must feel (the Simulator
        wakes them all), not the mouse's spring, which wakes only the body it holds."""
        planes = self.plane_list()
        values = np.zeros(NUM_VALUES)
        values[[DT, STIFFNESS, DAMPING, FRICTION]] = (self.dt, self.collision_stiffness,
                                                      self.velocity_damping_stiffness, self.friction_stiffness)
        values[GX:GZ + 1] = self.gravity
        values[NUM_PLANES] = len(planes)
        values[NUM_SPRINGS] = self.springs_per_world
        values[GRAB_FIRST:GRAB_FIRST + GRAB_VALUES] = self.grab_values
        values[SLEEP_SPEED] = self.sleep_speed if self.sleep else 0.0
        values[SLEEP_STEPS] = max(1, round(self.sleep_time / self.dt))
        if wakes or not hasattr(self, "version"):
            self.version = getattr(self, "version", 0) + 1  # the Simulator wakes every body on a change
        material = np.zeros((MAX_PLANES, 4))
        if len(planes):
            material[:len(planes)] = np.array(self._material_rows(planes))
        upload(self.values, np.concatenate([values, material.reshape(-1), self.table]))
        padded = np.zeros((MAX_PLANES, 4))
        padded[:len(planes)] = planes
        upload(self.planes, padded)
