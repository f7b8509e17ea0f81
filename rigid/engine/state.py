"""Per-step data: what the substeps write. Also the runtime parameters.

``State`` holds, per body (shape [B]):
- ``x``  vec3  centre of mass, world frame
- ``q``  vec4  orientation, unit quaternion, scalar first [s, vx, vy, vz]
- ``P``  vec3  linear momentum, world frame
- ``L``  vec3  angular momentum about the centre of mass, world frame
and the auxiliaries derived from them after every substep:
- ``v`` = P / M, ``R`` = R(q), ``inertia_inv`` = R I0⁻¹ Rᵀ, ``omega`` = I⁻¹ L (world)
Per particle (shape [N]): ``particle_x``, ``particle_v`` (world), and per drawn
vertex ``surface_x`` [V]; these are written once per rendered frame, not per substep.

One State lives as long as its Simulator: Taichi kernels capture fields, so a
reset rewrites these fields rather than making new ones.

``Params`` are the scalars a GUI slider may change between frames without a
recompile (0-d fields, read by the kernels at run time).
"""
import taichi as ti


class State:
    def __init__(self, num_bodies: int, num_particles: int, num_surface: int):
        self.x = ti.Vector.field(3, float, shape=num_bodies)
        self.q = ti.Vector.field(4, float, shape=num_bodies)
        self.P = ti.Vector.field(3, float, shape=num_bodies)
        self.L = ti.Vector.field(3, float, shape=num_bodies)
        self.v = ti.Vector.field(3, float, shape=num_bodies)
        self.omega = ti.Vector.field(3, float, shape=num_bodies)
        self.R = ti.Matrix.field(3, 3, float, shape=num_bodies)
        self.inertia_inv = ti.Matrix.field(3, 3, float, shape=num_bodies)
        self.particle_x = ti.Vector.field(3, float, shape=num_particles)
        self.particle_v = ti.Vector.field(3, float, shape=num_particles)
        self.surface_x = ti.Vector.field(3, float, shape=max(num_surface, 1))


class Params:
    NAMES = ("dt", "collision_stiffness", "velocity_damping_stiffness", "friction_stiffness",
             "floor", "wall")

    def __init__(self, config):
        self.gravity = ti.Vector.field(3, float, shape=())
        self.walls = ti.field(ti.i32, shape=())
        for name in self.NAMES:
            setattr(self, name, ti.field(float, shape=()))
        self.load(config)

    def load(self, config):
        """Copy the config's runtime-adjustable values into the fields."""
        self.gravity[None] = config.gravity
        self.walls[None] = int(config.walls)
        for name in self.NAMES:
            getattr(self, name)[None] = getattr(config, name)
