# Rigid body simulation, Assignment 3 (a test fixture in the format of the course's original
# handout: one script, global fields, kernels initial() and substep(), a window loop at the bottom).
# Written for the grader's tests from the description in issue 14: solved, but it calls ti.init twice
# and draws with the legacy ti.GUI in a loop that never checks gui.running.
import numpy as np
import taichi as ti

ti.init(arch=ti.gpu, debug=True)
ti.init(arch=ti.cpu, debug=True)


def read_obj_file(file_path, scale=1.0):
    vertices = []
    with open(file_path, "r") as f:
        for line in f:
            parts = line.split()
            if len(parts) >= 4 and parts[0] == "v":
                vertices.append([float(parts[1]) * scale, float(parts[2]) * scale, float(parts[3]) * scale])
    return np.array(vertices, dtype=np.float32)


# parameters of the simulation
particle_mass = 1
initial_velocity = ti.Vector([0.0, 0.0, 0.0])
initial_angular_velocity = ti.Vector([0.0, 0.0, 0.0])
gravity = ti.Vector([0.0, -9.8, 0.0])
collision_stiffness = 1e4
velocity_damping_stiffness = 1e3
friction_stiffness = 0.1
dt = 1e-3

mesh_vertices = read_obj_file("sphere.obj", scale=0.3)
num_particles = mesh_vertices.shape[0]

# per particle
particle_vertices = ti.Vector.field(3, dtype=ti.f32, shape=num_particles)
particle_origin_vertices = ti.Vector.field(3, dtype=ti.f32, shape=num_particles)
particle_velocities = ti.Vector.field(3, dtype=ti.f32, shape=num_particles)
particle_force = ti.Vector.field(3, dtype=ti.f32, shape=num_particles)

# the body
body_cm_position = ti.Vector.field(3, dtype=ti.f32, shape=())
body_origin_cm_position = ti.Vector.field(3, dtype=ti.f32, shape=())
body_velocity = ti.Vector.field(3, dtype=ti.f32, shape=())
body_angular_velocity = ti.Vector.field(3, dtype=ti.f32, shape=())
body_rotation = ti.Matrix.field(3, 3, dtype=ti.f32, shape=())
body_rotation_quaternion = ti.Vector.field(4, dtype=ti.f32, shape=())
body_angular_momentum = ti.Vector.field(3, dtype=ti.f32, shape=())
body_origin_inverse_inertia = ti.Matrix.field(3, 3, dtype=ti.f32, shape=())
body_mass = ti.field(dtype=ti.f32, shape=())

particle_vertices.from_numpy(mesh_vertices)


@ti.func
def quaternion_multiplication(p, q):
    # p * q for quaternions stored as (w, x, y, z)
    w = p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3]
    x = p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2]
    y = p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1]
    z = p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0]
    return ti.Vector([w, x, y, z])


@ti.func
def quaternion_to_matrix(q):
    w, x, y, z = q[0], q[1], q[2], q[3]
    return ti.Matrix([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


@ti.kernel
def initial():
    # the centre of mass
    body_mass[None] = 0.0
    body_cm_position[None] = ti.Vector([0.0, 0.0, 0.0])
    for i in particle_vertices:
        body_mass[None] += particle_mass
        body_cm_position[None] += particle_mass * particle_vertices[i]
    body_cm_position[None] /= body_mass[None]
    body_origin_cm_position[None] = body_cm_position[None]
    for i in particle_vertices:
        particle_origin_vertices[i] = particle_vertices[i] - body_cm_position[None]

    inertia = ti.Matrix([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    # TODO 1: Compute the inertia tensor of the body
    # sum over the particles: m (r^T r E - r r^T), r from the centre of mass
    for i in particle_vertices:
        r = particle_origin_vertices[i]
        inertia += particle_mass * (r.dot(r) * ti.Matrix.identity(float, 3) - r.outer_product(r))

    # compute the inverse inertia and the initial angular momentum
    body_origin_inverse_inertia[None] = inertia.inverse()
    body_rotation[None] = ti.Matrix.identity(float, 3)
    body_rotation_quaternion[None] = ti.Vector([1.0, 0.0, 0.0, 0.0])
    body_velocity[None] = initial_velocity
    body_angular_velocity[None] = initial_angular_velocity
    body_angular_momentum[None] = inertia @ initial_angular_velocity


@ti.kernel
def substep():
    # computer the force on every particle
    for i in particle_vertices:
        # TODO 2: gravity
        particle_force[i] = particle_mass * gravity

        # Collision force: a spring pushes the particle back into the box
        if particle_vertices[i][1] < -1:
            particle_force[i][1] += collision_stiffness * (-1 - particle_vertices[i][1])
        if particle_vertices[i][0] < -1:
            particle_force[i][0] += collision_stiffness * (-1 - particle_vertices[i][0])
        if particle_vertices[i][0] > 1:
            particle_force[i][0] += collision_stiffness * (1 - particle_vertices[i][0])
        if particle_vertices[i][2] < -1:
            particle_force[i][2] += collision_stiffness * (-1 - particle_vertices[i][2])
        if particle_vertices[i][2] > 1:
            particle_force[i][2] += collision_stiffness * (1 - particle_vertices[i][2])

    # computer the force for rigid body
    body_force = ti.Vector([0.0, 0.0, 0.0])
    # TODO 3: compute the force for rigid body
    for i in particle_vertices:
        body_force += particle_force[i]

    # computer the torque for rigid body
    body_torque = ti.Vector([0.0, 0.0, 0.0])
    # TODO 4: compute the torque for rigid body
    for i in particle_vertices:
        arm = particle_vertices[i] - body_cm_position[None]
        body_torque += arm.cross(particle_force[i])

    # update the centre of mass position and velocity
    # TODO 5: update the center of mass position and velocity
    body_cm_position[None] += dt * body_velocity[None]
    body_velocity[None] += dt * body_force / body_mass[None]

    # update the rotation
    # TODO 6: update the rotation quaternion
    w = body_angular_velocity[None]
    omega_q = ti.Vector([0.0, w[0], w[1], w[2]])
    body_rotation_quaternion[None] += 0.5 * dt * quaternion_multiplication(omega_q, body_rotation_quaternion[None])

    # normalize the quaternion and update the rotation matrix
    body_rotation_quaternion[None] = body_rotation_quaternion[None].normalized()
    body_rotation[None] = quaternion_to_matrix(body_rotation_quaternion[None])

    # update the angular momentum, inertia tensor and angular velocity
    # TODO 7: update, the angular momentum, inertia tensor and angular velocity
    body_angular_momentum[None] += dt * body_torque
    world_inverse_inertia = body_rotation[None] @ body_origin_inverse_inertia[None] @ body_rotation[None].transpose()
    body_angular_velocity[None] = world_inverse_inertia @ body_angular_momentum[None]

    # update the particles
    for i in particle_vertices:
        offset = body_rotation[None] @ particle_origin_vertices[i]
        particle_vertices[i] = body_cm_position[None] + offset
        particle_velocities[i] = body_velocity[None] + body_angular_velocity[None].cross(offset)


initial()

gui = ti.GUI("Rigid body", res=(800, 600), background_color=0xFFFFFF)
while True:
    for _ in range(int(1 / 60 // dt)):
        substep()
    positions = particle_vertices.to_numpy()
    gui.circles(positions[:, [0, 1]] * 0.4 + 0.5, radius=3, color=0x3366CC)
    if gui.get_event(ti.GUI.ESCAPE):
        break
    gui.show()
