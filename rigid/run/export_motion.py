"""What the animation exporters (glTF, USD) write: each body's mesh and one key per frame.

A body's mesh is in its body frame about its centre of mass, so the body's pose at a
frame is exactly the trajectory's x (translation) and q (rotation): no per-vertex data
moves. Arrays, all from ``Trajectory.arrays()`` and ``Model.body_surfaces()``:

- ``t``  (F,) float64      key times, s of simulated time (the NPZ's ``t``), strictly increasing
- ``x``  (F, B, 3) float64 centre of mass, world frame, m
- ``q``  (F, B, 4) float64 orientation, unit quaternion, scalar first (w, x, y, z)
- ``vertices[b]`` (V, 3) float64, body frame; ``faces[b]`` (T, 3) int32, empty for a point cloud
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Motion:
    names: list[str]
    vertices: list[np.ndarray]
    faces: list[np.ndarray]
    t: np.ndarray
    x: np.ndarray
    q: np.ndarray
    frame_time: float  # substeps × Δt: one rendered frame of simulated time, s
    box: tuple[float, float] | None  # (floor, wall) of the static box, None without walls
    static: list | None = None  # per body: a [[static]] mesh (written as a node that never moves)

    def is_static(self, i: int) -> bool:
        return bool(self.static and self.static[i])

    @property
    def num_bodies(self) -> int:
        return len(self.names)

    @property
    def num_keys(self) -> int:
        return len(self.t)


def motion_from(arrays: dict, surfaces: list, config) -> Motion:
    """Build the exporters' input from the NPZ dict, ``Model.body_surfaces()`` and the run's config.

    One body's (F, 3)/(F, 4) and many bodies' (F, B, 3)/(F, B, 4) both become (F, B, ·)."""
    frames = len(arrays["t"])
    x = np.asarray(arrays["x"], np.float64).reshape(frames, -1, 3)
    q = np.asarray(arrays["q"], np.float64).reshape(frames, -1, 4)
    if x.shape[1] != len(surfaces):
        raise ValueError(f"trajectory has {x.shape[1]} bodies, the model {len(surfaces)}")
    # The run's Δt as given (float64), not the NPZ's copy in the run's precision: 16 × 1e-3 s
    # gives 62.5 frames/s, where the float32 copy would give 62.499997.
    frame_time = int(arrays["substeps"]) * float(config.dt)
    return Motion(names=[s[0] for s in surfaces],
                  vertices=[np.asarray(s[1], np.float64).reshape(-1, 3) for s in surfaces],
                  faces=[np.asarray(s[2], np.int32).reshape(-1, 3) for s in surfaces],
                  t=key_times(arrays["t"], frame_time), x=x, q=q, frame_time=frame_time,
                  box=(float(config.floor), float(config.wall)) if config.walls else None,
                  # [[static]] meshes are the model's last bodies (rigid.bodies.statics)
                  static=[False] * (len(surfaces) - len(config.statics)) + [True] * len(config.statics))


def key_times(t, frame_time: float) -> np.ndarray:
    """The NPZ's ``t`` as key times. Headless runs and recordings always give a strictly
    increasing ``t`` and it is returned as is; a reset in the window restarts the clock at 0,
    and there the keys continue from the previous one (the reset shows as a jump)."""
    t = np.asarray(t, np.float64)
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size == 0:
        return t.copy()
    out = t.copy()
    for i in range(back[0] + 1, len(t)):
        step = t[i] - t[i - 1]
        if step <= 0:  # a reset: t[i] is the time since it
            step = t[i] if t[i] > 0 else frame_time
        out[i] = out[i - 1] + step
    return out


def box_meshes(floor: float, wall: float) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The static box as two meshes, facing inwards: ("floor", the y = floor square),
    ("walls", the four walls x, z = ±wall up to y = floor + 2 wall, as the viewer draws them)."""
    top = floor + 2.0 * wall
    w = wall
    floor_vertices = np.array([[-w, floor, -w], [-w, floor, w], [w, floor, w], [w, floor, -w]])
    floor_faces = np.array([[0, 1, 2], [0, 2, 3]], np.int32)
    corners = [(-w, -w), (w, -w), (w, w), (-w, w)]  # counter-clockwise seen from above
    vertices, faces = [], []
    for k, (x0, z0) in enumerate(corners):
        x1, z1 = corners[(k + 1) % 4]
        base = len(vertices)
        vertices += [[x0, floor, z0], [x1, floor, z1], [x1, top, z1], [x0, top, z0]]
        faces += [[base, base + 1, base + 2], [base, base + 2, base + 3]]  # normals point inwards
    return [("floor", floor_vertices.astype(np.float64), floor_faces),
            ("walls", np.array(vertices, np.float64), np.array(faces, np.int32))]
