"""Where the camera stands: a scene's ``[camera]`` table or ``--camera``, else a view that frames
the bodies; optionally following a body or the bodies' centre.

Keys (the table's and the flag's, ``--camera fov=35 follow=centre``):

  position = [X, Y, Z]   the eye, m (default: framed, see ``framed_view``)
  look_at  = [X, Y, Z]   the point looked at, m (default: the framed view's target)
  fov      = DEG         vertical field of view, degrees (default 45)
  follow   = "centre"    the look-at point moves with the bodies' centre of mass (the eye keeps
           | "none"      its offset from it); a body's name or index (0-based, scene order)
           | NAME | N    follows that body; "none" (default) stands still

Without position and look_at, the default frames what is in the scene: one body keeps the
box in view (it crosses the box); many bodies are framed by their bounding box, widened by the
largest body's size (where they topple to), reaching down to the floor they will fall on and,
with walls, holding the box's whole floor (bodies slide and topple across it: framing their
bounding box alone cut the box off in the dominoes', ramp's and bounce's videos), from a height
(the pile is seen from above its top layer). The orbit camera (orbit.py) starts from this view, and the
mouse orbits and zooms it from there; a follow mode moves its target every frame.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..engine.arrays import download
from ..errors import UserError
from .orbit import MAX_ELEVATION, MIN_ELEVATION, OrbitCamera

KEYS = ("position", "look_at", "fov", "follow")
DEFAULT_FOV = 45.0
ONE_BODY = dict(target=(0.0, -0.35, 0.0), distance=4.6, azimuth_deg=28.0, elevation_deg=20.0)
MANY_AZIMUTH, MANY_ELEVATION = 28.0, 32.0  # degrees: a little from the side, from a height
FILL = 0.9  # the framed box spans this fraction of the picture's half-width or half-height
MIN_EXTENT = 0.3  # m: a box smaller than this is framed as this size


@dataclass
class CameraSpec:
    position: tuple | None = None
    look_at: tuple | None = None
    fov: float = DEFAULT_FOV
    follow: str | int | None = None  # None, "centre", a body index or a body name


def camera_spec(table: dict | None, where: str = "camera") -> CameraSpec:
    """Check a ``[camera]`` table (or the parsed ``--camera`` items): one line per bad value."""
    table = dict(table or {})
    unknown = sorted(set(table) - set(KEYS))
    if unknown:
        raise UserError(f"{where}: unknown key {unknown[0]!r}; camera keys: {', '.join(KEYS)}")
    spec = CameraSpec()
    for key in ("position", "look_at"):
        if key in table:
            value = table[key]
            if (not isinstance(value, (list, tuple)) or len(value) != 3
                    or not all(_number(v) and math.isfinite(v) for v in value)):
                raise UserError(f"{where}: {key} = {value!r}: use three finite numbers X Y Z, e.g. [0, 1, 4]")
            setattr(spec, key, tuple(float(v) for v in value))
    if "fov" in table:
        fov = table["fov"]
        if not _number(fov) or not 1.0 <= fov <= 170.0:
            raise UserError(f"{where}: fov = {fov!r}: use a field of view from 1 to 170 degrees")
        spec.fov = float(fov)
    if "follow" in table:
        follow = table["follow"]
        if isinstance(follow, bool) or not isinstance(follow, (str, int)):
            raise UserError(f"{where}: follow = {follow!r}: use \"centre\", \"none\", a body's name or index")
        spec.follow = None if follow in ("none", "") else "centre" if follow in ("centre", "center") else follow
    if spec.position is not None and spec.look_at is not None and np.allclose(spec.position, spec.look_at):
        raise UserError(f"{where}: position and look_at are the same point; move the eye away from it")
    return spec


def parse_camera_flag(items: list[str] | None) -> dict:
    """``--camera position=3,2,4 look_at=0,-0.8,0 fov=35 follow=centre`` as a table."""
    table = {}
    for item in items or ():
        key, sep, value = item.partition("=")
        if not sep or not value:
            raise UserError(f"--camera {item}: use KEY=VALUE, e.g. --camera position=3,2,4 follow=centre "
                            f"(keys: {', '.join(KEYS)})")
        key = key.replace("-", "_")
        if key in ("position", "look_at"):
            try:
                table[key] = [float(v) for v in value.split(",")]
            except ValueError:
                raise UserError(f"--camera {item}: {key} takes three numbers X,Y,Z, e.g. {key}=0,1,4") from None
        elif key == "fov":
            try:
                table[key] = float(value)
            except ValueError:
                raise UserError(f"--camera {item}: fov takes a number of degrees, e.g. fov=40") from None
        else:
            table[key] = int(value) if value.lstrip("-").isdigit() else value
    return table


def follow_index(spec: CameraSpec, sim) -> int | None:
    """The body the camera follows (None: none or the centre); a bad name or index is one line."""
    follow = spec.follow
    if follow is None or follow == "centre":
        return None
    names = [b.name for b in sim.bodies]
    if isinstance(follow, int):
        if not 0 <= follow < len(names):
            raise UserError(f"camera follow = {follow}: the scene has bodies 0 to {len(names) - 1}")
        return follow
    if follow not in names:
        shown = ", ".join(names[:6]) + (", ..." if len(names) > 6 else "")
        raise UserError(f"camera follow = {follow!r}: no body of that name; use \"centre\", an index, or one of {shown}")
    return names.index(follow)


def framed_view(sim, aspect: float, fov: float = DEFAULT_FOV) -> dict:
    """The orbit camera's (target, distance, azimuth, elevation) that frames the scene."""
    if not sim.many:
        return dict(ONE_BODY)
    points = sim.particle_positions()
    lo, hi = points.min(axis=0), points.max(axis=0)
    # Bodies fall and topple: sideways by up to their size (a domino by its height), down to the floor.
    reach = 2.0 * _largest_radius(sim)
    lo[[0, 2]] -= reach
    hi[[0, 2]] += reach
    if sim.params.walls:  # the whole floor of the box: bodies slide and topple across it
        wall, floor = float(sim.params.wall), float(sim.params.floor)
        lo[1] = min(lo[1], floor)
        lo[[0, 2]], hi[[0, 2]] = -wall, wall
    centre = 0.5 * (lo + hi)
    half = np.maximum(0.5 * (hi - lo), 0.5 * MIN_EXTENT)
    return dict(target=tuple(centre), azimuth_deg=MANY_AZIMUTH, elevation_deg=MANY_ELEVATION,
                distance=fit_distance(centre, half, MANY_AZIMUTH, MANY_ELEVATION, aspect, fov))


def fit_distance(centre, half, azimuth_deg, elevation_deg, aspect, fov) -> float:
    """The nearest distance from which a box (centre ± half) fits the picture: for each corner at
    offset r, seen along the unit view direction d (eye = centre + D d), its depth is D − r·d and
    it fits if |r·right| <= tan(fov/2) aspect (D − r·d) FILL, and likewise upwards."""
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    d = np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])
    right = np.cross(-d, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, -d)
    ty = math.tan(math.radians(fov) / 2.0) * FILL
    tx = ty * aspect
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half
    need = np.abs(corners @ right) / tx + corners @ d
    need = np.maximum(need, np.abs(corners @ up) / ty + corners @ d)
    return float(max(need.max(), 0.5))


class SceneCamera:
    """The orbit camera a renderer draws with, placed by a spec (or framed) and moved by follow."""

    def __init__(self, sim, spec: CameraSpec | None = None, aspect: float = 16 / 9):
        self.sim, self.spec = sim, spec or CameraSpec()
        self.follow = follow_index(self.spec, sim)
        view = framed_view(sim, aspect, self.spec.fov)
        self.orbit = OrbitCamera(fov_deg=self.spec.fov, **view)
        if self.spec.look_at is not None or self.spec.position is not None:
            target = np.asarray(self.spec.look_at if self.spec.look_at is not None else view["target"], float)
            eye = np.asarray(self.spec.position if self.spec.position is not None else self.orbit.position(), float)
            offset = eye - target
            if np.linalg.norm(offset) < 1e-9:
                raise UserError("camera: position and look_at are the same point; move the eye away from it")
            self.orbit.target = tuple(target)
            self.orbit.distance = float(np.linalg.norm(offset))
            # Straight down (90°) has no "up" to turn the picture by: kept within the orbit's range.
            elevation = math.asin(max(-1.0, min(1.0, offset[1] / self.orbit.distance)))
            self.orbit.elevation = min(MAX_ELEVATION, max(MIN_ELEVATION, elevation))
            self.orbit.azimuth = math.atan2(offset[0], offset[2])

    def update(self) -> None:
        """Move the target with the followed body or the bodies' centre of mass (once per frame)."""
        if self.spec.follow is None:
            return
        x = download(self.sim.state.x).astype(np.float64)  # the bodies' centres (no energy sums)
        if self.follow is not None:
            self.orbit.target = tuple(x[self.follow])
            return
        mass = self.sim.model.body_mass_np
        self.orbit.target = tuple((mass @ x) / mass.sum())


def _largest_radius(sim) -> float:
    """The largest distance of a particle from its body's centre of mass (the model's r0)."""
    r0 = sim.model.r0_np
    return float(np.sqrt((r0 * r0).sum(axis=1)).max()) if len(r0) else 0.0


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)
