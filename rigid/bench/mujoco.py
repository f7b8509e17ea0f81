"""The benchmark's MuJoCo side: one free body in the same box, same Δt (optional).

The box is the engine's: a floor plane at y = floor and four walls at x, z =
±wall, normals into the box, gravity (0, −9.8, 0), Δt = 1e-3, MuJoCo's Euler
integrator. The body is the same mesh as a mesh geom (MuJoCo collides with its
convex hull: for the torus that is fewer vertices than the engine's 4096
particles, and a different contact model: MuJoCo's soft constraints, not
penalty springs) or, for the volume-sampled cube, a box geom. Timing calls
``mj_step(model, data, nstep)`` once per frame, so Python runs once per frame
as for the engine.
"""
from __future__ import annotations

import numpy as np


def available() -> str | None:
    """MuJoCo's version, or None if it is not installed (``pip install mujoco``)."""
    try:
        import mujoco
    except ImportError:
        return None
    return mujoco.__version__


def _planes(floor: float, wall: float) -> str:
    walls = [((0, floor, 0), (0, 1, 0)), ((wall, 0, 0), (-1, 0, 0)), ((-wall, 0, 0), (1, 0, 0)),
             ((0, 0, wall), (0, 0, -1)), ((0, 0, -wall), (0, 0, 1))]
    return "\n".join(f'<geom type="plane" size="0 0 1" pos="{p[0]} {p[1]} {p[2]}" '
                     f'zaxis="{n[0]} {n[1]} {n[2]}"/>' for p, n in walls)


def body_xml(vertices: np.ndarray | None, faces: np.ndarray | None, box_half: float | None,
             mass: float) -> tuple[str, str]:
    """(asset XML, geom XML) for a mesh given inline, or a cube of half-side box_half."""
    if box_half is not None:
        return "", f'<geom type="box" size="{box_half} {box_half} {box_half}" mass="{mass}"/>'
    vert = " ".join(f"{c:.9g}" for c in np.asarray(vertices).reshape(-1))
    face = " ".join(str(int(i)) for i in np.asarray(faces).reshape(-1))
    return (f'<asset><mesh name="body" vertex="{vert}" face="{face}"/></asset>',
            f'<geom type="mesh" mesh="body" mass="{mass}"/>')


class MujocoBox:
    def __init__(self, config, mass: float, vertices=None, faces=None, box_half=None):
        import mujoco

        self._mujoco = mujoco
        c = config
        asset, geom = body_xml(vertices, faces, box_half, mass)
        g = c.gravity
        xml = f"""<mujoco>
  <option timestep="{c.dt}" gravity="{g[0]} {g[1]} {g[2]}" integrator="Euler"/>
  {asset}
  <worldbody>
    {_planes(c.floor, c.wall)}
    <body name="body" pos="0 0 0"><freejoint/>{geom}</body>
  </worldbody>
</mujoco>"""
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        self.config = c
        self.reset()

    def reset(self):
        c, d = self.config, self.data
        self._mujoco.mj_resetData(self.model, d)
        d.qpos[:3] = c.position
        d.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
        d.qvel[:3] = c.initial_velocity
        d.qvel[3:6] = c.initial_angular_velocity  # body frame; equal to world frame at q = identity

    def step_frame(self, substeps: int):
        self._mujoco.mj_step(self.model, self.data, nstep=substeps)

    def position(self) -> np.ndarray:
        return np.array(self.data.qpos[:3])
