"""Every simulation parameter in one dataclass, with the handout's defaults.

A scene is a TOML file whose keys are the field names below (the handout's
names: ``particle_mass``, ``initial_velocity``, ...). Values come, in order of
precedence, from command-line flags, then the scene file, then these defaults.
``validate()`` turns every bad value into one ``UserError`` line.
"""
from __future__ import annotations

import dataclasses
import difflib
import functools
import math
import tomllib
from dataclasses import dataclass, field, fields
from pathlib import Path

from .errors import UserError

# The backends --arch takes (runtime.init_taichi): "gpu" picks one, the others are asked by name.
ARCHES = ("cpu", "gpu", "cuda", "vulkan", "metal")

REPO_ROOT = Path(__file__).resolve().parent.parent
# The checkout's assets/, or the copy `pip install .` puts in the package (pyproject.toml).
ASSETS = REPO_ROOT / "assets" if (REPO_ROOT / "assets").is_dir() else Path(__file__).resolve().parent / "assets"
FRAME_TIME = 1.0 / 60.0  # one rendered frame, as in the handout
MAX_GRID = 512  # volume sampling: 512³ cells (rigid.bodies.sampling.MAX_CELLS); 1024³ would need ~100 GB


@dataclass
class SimConfig:
    # body
    mesh: str = str(ASSETS / "sphere.obj")
    scale: float = 0.3  # the handout's read_obj_file(..., scale=0.3)
    position: tuple = (0.0, 0.0, 0.0)  # initial centre of mass, world frame
    orientation: tuple = (1.0, 0.0, 0.0, 0.0)  # initial unit quaternion, scalar first
    particles: str = "vertex"  # "vertex": mesh vertices; "volume": grid cells inside the mesh
    grid: int = 32  # volume sampling: cells along the longest side
    particle_mass: float = 1.0
    initial_velocity: tuple = (0.0, 0.0, 0.0)
    initial_angular_velocity: tuple = (0.0, 0.0, 0.0)  # world frame, rad/s
    particle_radius: float | None = None  # collision radius between bodies; None: from the spacing
    count: int = 1  # copies of the body, placed in a lattice above position (rigid.bodies.placement)
    drag: float = 0.0  # linear air drag c: f = -c v on every particle, N s/m (rigid.engine.forces)
    # [[body]] tables of a scene: per-body overrides of the keys above (BODY_KEYS); empty: one body
    bodies: tuple = ()
    # world
    gravity: tuple = (0.0, -9.8, 0.0)
    walls: bool = True  # the box: floor y = floor, walls x, z = ±wall
    floor: float = -1.0
    wall: float = 1.0
    collision_stiffness: float = 1e4  # penalty spring, N/m per particle
    velocity_damping_stiffness: float = 1e3  # damping of the normal velocity, N s/m
    friction_stiffness: float = 0.1  # Coulomb coefficient: |f_t| <= mu |f_n|
    sleep: bool = True  # many bodies: bodies at rest for a while sleep (rigid.engine.sleep)
    # materials and static colliders (rigid.bodies.colliders): None = unset (the three keys above rule)
    restitution: float | None = None  # coefficient of restitution e, 0..1: sets each contact's damping
    friction: float | None = None  # Coulomb mu with static friction (a tangential spring at each contact)
    planes: tuple = ()  # [[plane]] tables: point, normal, friction, restitution
    statics: tuple = ()  # [[static]] tables: mesh, scale, position, orientation, friction, restitution
    springs: tuple = ()  # [[spring]] tables: bodies, points, stiffness, damping, rest_length (rigid.bodies.springs)
    # time
    dt: float = 1e-3
    integrator: str = "euler"  # euler (the slides) | symplectic | rk4
    # run
    frames: int | None = None
    fp64: bool = False
    arch: str = "cpu"
    seed: int = 0
    resolution: tuple = (1280, 720)
    camera: dict | None = None  # a scene's [camera] table (position, look_at, fov, follow): rigid/view/camera.py

    @property
    def num_body_entries(self) -> int:
        """Body entries before ``count`` copies: the [[body]] tables, or the top level alone."""
        return max(1, len(self.bodies))

    @property
    def many_bodies(self) -> bool:
        """Whether the scene has several bodies (a file of several meshes, ``mesh_count``, is several)."""
        entries = self.bodies or ({},)
        return len(entries) > 1 or any(b.get("count", self.count) > 1 for b in entries) \
            or mesh_count(entries[0].get("mesh", self.mesh)) > 1

    def body_config(self, index: int) -> "SimConfig":
        """The config of body entry ``index``: the top level with the [[body]] table's keys over it."""
        if not self.bodies:
            return self
        overrides = self.bodies[index]
        body = dataclasses.replace(self, bodies=(), **overrides)
        try:
            return body.validate()
        except UserError as err:
            raise UserError(f"[[body]] {index + 1}: {err}") from None

    @property
    def substeps(self) -> int:
        """Substeps per rendered frame: int(1/60 // dt), as the handout does (16 at 1e-3)."""
        return max(1, int(FRAME_TIME // self.dt))

    def replace(self, **changes) -> "SimConfig":
        return dataclasses.replace(self, **changes)

    def validate(self) -> "SimConfig":
        for name in ("scale", "particle_mass", "dt"):
            _positive(name, getattr(self, name))
        for name in ("collision_stiffness", "velocity_damping_stiffness", "friction_stiffness", "drag"):
            _non_negative(name, getattr(self, name))
        for name in ("floor", "wall"):
            _finite(name, getattr(self, name))
        if self.wall <= 0:
            raise UserError(f"wall = {self.wall}: the walls stand at x, z = ±wall; use a positive value")
        for name in ("position", "initial_velocity", "initial_angular_velocity", "gravity"):
            object.__setattr__(self, name, _vec3(name, getattr(self, name)))
        object.__setattr__(self, "orientation", _quaternion("orientation", self.orientation))
        if self.particle_radius is not None:
            _positive("particle_radius", self.particle_radius)
        if not isinstance(self.count, int) or isinstance(self.count, bool) or not 1 <= self.count <= 1_000_000:
            raise UserError(f"count = {self.count!r}: use a whole number of copies from 1 to 1000000")
        if self.restitution is not None and not (_is_number(self.restitution) and 0 <= self.restitution <= 1):
            raise UserError(f"restitution = {self.restitution!r}: use a number from 0 (no bounce) to 1 (elastic)")
        if self.friction is not None:  # [[plane]] and [[static]] tables: rigid.bodies.colliders
            _non_negative("friction", self.friction)
        for i in range(len(self.bodies)):
            self.body_config(i)  # raises "[[body]] i: ..." for a bad value in that table
        if self.dt > FRAME_TIME:
            raise UserError(f"dt = {self.dt} is longer than a frame (1/60 s); use --dt 1e-3 or smaller")
        if self.particles not in ("vertex", "volume"):
            raise UserError(f"particles = {self.particles!r}: use 'vertex' or 'volume'")
        if self.integrator not in ("euler", "symplectic", "rk4"):
            raise UserError(f"integrator = {self.integrator!r}: use 'euler', 'symplectic' or 'rk4'")
        if self.arch not in ARCHES:
            raise UserError(f"arch = {self.arch!r}: use one of {', '.join(ARCHES)}")
        if not isinstance(self.grid, int) or isinstance(self.grid, bool) or not 2 <= self.grid <= MAX_GRID:
            raise UserError(f"grid = {self.grid!r}: use a whole number of cells from 2 to {MAX_GRID}, e.g. --grid 64")
        if self.frames is not None and (not isinstance(self.frames, int) or self.frames <= 0):
            raise UserError(f"frames = {self.frames}: use a positive number of frames, e.g. --frames 300")
        res = tuple(self.resolution)
        if len(res) != 2 or not all(isinstance(r, int) and not isinstance(r, bool) for r in res):
            raise UserError(f"resolution = {self.resolution}: use two whole numbers W H, e.g. --resolution 1280 720")
        if not all(16 <= r <= 8192 for r in res):
            raise UserError(f"resolution = {res[0]} x {res[1]} is too {'small' if min(res) < 16 else 'large'}: "
                            f"width and height go from 16 to 8192 pixels, e.g. --resolution 1280 720")
        return self


MATERIAL_KEYS = ("restitution", "friction")
SCENE_KEYS = ({f.name for f in fields(SimConfig)} - {"bodies", "planes", "statics", "springs"}
              | {"body", "plane", "static", "spring"})
# Keys a [[body]] table may set; at the top level they are every body's defaults.
BODY_KEYS = {"mesh", "scale", "position", "orientation", "initial_velocity", "initial_angular_velocity",
             "particle_mass", "particles", "grid", "particle_radius", "count", "drag", *MATERIAL_KEYS}
_VECTOR_KEYS = {"position", "initial_velocity", "initial_angular_velocity", "gravity", "resolution", "orientation"}


# Formats whose file may hold several meshes (a GLB's mesh nodes, an ASCII STL's solids); an OBJ is one.
GROUP_FORMATS = (".glb", ".stl")


def mesh_count(mesh: str) -> int:
    """How many meshes (bodies) a mesh file places; 1 for other formats and unreadable files (read_mesh says why)."""
    path = Path(mesh)
    if path.suffix.lower() not in GROUP_FORMATS or not path.is_file():
        return 1
    stat = path.stat()
    return _mesh_count(str(path.resolve()), stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=32)
def _mesh_count(path: str, _mtime: int, _size: int) -> int:
    try:
        import trimesh  # deferred: slow to import, and only for .glb and .stl

        scene = trimesh.load(path, force="scene", process=False, maintain_order=True, merge_primitives=True)
        return max(1, len(scene.graph.nodes_geometry))
    except Exception:  # a garbled file is read_mesh's to report
        return 1


def load_scene(path: str | Path) -> dict:
    """Read a scene TOML into a dict of SimConfig fields; mesh paths are relative to the file."""
    path = Path(path)
    if not path.is_file():
        raise UserError(f"scene file {path} not found; see assets/scenes/ for examples")
    try:
        data = tomllib.loads(path.read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise UserError(f"scene file {path} is not valid TOML ({err}); fix the syntax") from None
    if not data:
        raise UserError(f"scene file {path} is empty: it sets no keys, so the run would be the defaults; "
                        f"add keys (see assets/scenes/assignment.toml) or leave out --scene")
    unknown = sorted(set(data) - SCENE_KEYS)
    if unknown:
        close = difflib.get_close_matches(unknown[0], SCENE_KEYS, n=1)
        hint = f"did you mean {close[0]!r}?" if close else "known keys: " + ", ".join(sorted(SCENE_KEYS))
        raise UserError(f"scene file {path}: unknown key {unknown[0]!r}; {hint}")
    camera = data.pop("camera", None)  # checked by rigid/view/camera.py (its keys are the view's)
    if camera is not None and not isinstance(camera, dict):
        raise UserError(f"scene file {path}: 'camera' must be a [camera] table (position, look_at, fov, follow)")
    planes, statics, tables = data.pop("plane", []), data.pop("static", []), data.pop("body", [])
    springs = data.pop("spring", [])  # checked with the bodies placed: rigid.bodies.springs
    for name, given, what in (("plane", planes, ""), ("static", statics, ""), ("spring", springs, ""),
                              ("body", tables, ", one per body")):
        if not isinstance(given, list) or not all(isinstance(t, dict) for t in given):
            raise UserError(f"scene file {path}: '{name}' must be [[{name}]] tables{what}")
    data.update({key: tuple(value) for key, value in (("planes", planes), ("springs", springs)) if value})
    if statics:
        data["statics"] = tuple({**t, "mesh": resolve_mesh(path, t["mesh"])} if isinstance(t.get("mesh"), str)
                                else t for t in statics)
    _check_table(path, data, "")
    bodies = []
    for i, table in enumerate(tables):
        unknown = sorted(set(table) - BODY_KEYS)
        if unknown:
            where = "a top-level key" if unknown[0] in SCENE_KEYS else "not a body key"
            close = difflib.get_close_matches(unknown[0], BODY_KEYS, n=1)
            hint = f"did you mean {close[0]!r}?" if close else f"{where}; body keys: " + ", ".join(sorted(BODY_KEYS))
            raise UserError(f"scene file {path}: [[body]] {i + 1}: unknown key {unknown[0]!r}; {hint}")
        bodies.append(_check_table(path, table, f"[[body]] {i + 1}: "))
    if bodies:
        data["bodies"] = tuple(bodies)
    if camera is not None:
        data["camera"] = camera
    return data


def _check_table(path: Path, table: dict, where: str) -> dict:
    """Check the types of a table's keys (in place), resolve its mesh path, make vectors tuples."""
    defaults = SimConfig()
    for key, value in table.items():
        if key not in ("planes", "statics", "springs"):  # [[plane]], [[static]]: rigid.bodies.colliders checks them
            _check_type(path, key, value, getattr(defaults, key), where)
    if "mesh" in table:
        table["mesh"] = resolve_mesh(path, table["mesh"])
    for key in _VECTOR_KEYS & set(table):
        table[key] = tuple(table[key])
    return table


def resolve_mesh(scene: Path, mesh: str) -> str:
    """A scene's mesh path: relative to the TOML file, then to assets/ (absolute paths as they are)."""
    beside = (scene.parent / mesh).resolve()
    if beside.exists() or Path(mesh).is_absolute() or not (ASSETS / mesh).exists():
        return str(beside)
    return str((ASSETS / mesh).resolve())


def _check_type(path, key, value, default, where=""):
    if key in _VECTOR_KEYS:
        ok = isinstance(value, list) and all(_is_number(v) for v in value)
        want = "a list of numbers, e.g. [0.0, 1.0, 0.0]"
    elif key in ("frames", "count"):
        ok, want = isinstance(value, int) and not isinstance(value, bool), "a whole number"
    elif key in ("particle_radius", *MATERIAL_KEYS):
        ok, want = _is_number(value), "a number (metres)"
    elif isinstance(default, bool):
        ok, want = isinstance(value, bool), "true or false"
    elif isinstance(default, int):
        ok, want = isinstance(value, int) and not isinstance(value, bool), "a whole number"
    elif isinstance(default, float):
        ok, want = _is_number(value), "a number"
    else:
        ok, want = isinstance(value, str), "a string in quotes"
    if not ok:
        raise UserError(f"scene file {path}: {where}{key} = {value!r} has the wrong type; use {want}")


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _finite(name, value):
    if not _is_number(value) or not math.isfinite(value):
        raise UserError(f"{name} = {value}: use a finite number")


def _positive(name, value, zero_ok=False):
    _finite(name, value)
    if value < 0 or (value == 0 and not zero_ok):
        raise UserError(f"{name} = {value}: use {'zero or ' if zero_ok else ''}a positive number")


_non_negative = functools.partial(_positive, zero_ok=True)


def _quaternion(name, value) -> tuple:
    value = tuple(value)
    if len(value) != 4 or not all(_is_number(v) and math.isfinite(v) for v in value):
        raise UserError(f"{name} = {list(value)}: use four finite numbers W X Y Z (a quaternion, scalar first)")
    norm = math.sqrt(sum(float(v) ** 2 for v in value))
    if norm < 1e-9:
        raise UserError(f"{name} = {list(value)}: a zero quaternion is no rotation; use e.g. [1, 0, 0, 0]")
    return tuple(float(v) / norm for v in value)


def _vec3(name, value) -> tuple:
    value = tuple(value)
    if len(value) != 3 or not all(_is_number(v) and math.isfinite(v) for v in value):
        raise UserError(f"{name} = {list(value)}: use three finite numbers X Y Z")
    return tuple(float(v) for v in value)
