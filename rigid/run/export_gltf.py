"""Animated glTF 2.0 (.glb binary, .gltf JSON with the buffer embedded), through pygltflib.

Layout (Y-up, metres, as the simulation):

- one node per body, named after it, holding its mesh in the body frame about the centre
  of mass (named after the first body that has it: copies of a body share one mesh); its
  translation and rotation at rest are frame 0's (what a viewer shows without playing the
  animation). A body with no triangles is a POINTS primitive.
- a static node "box" (when the run has walls) with two children, "floor" and "walls",
  their meshes in world coordinates facing inwards: hide "walls" to look in from outside.
- one animation, "simulation": per body a translation and a rotation channel, LINEAR,
  sharing one input accessor (the key times, s of simulated time, with min/max).
  Rotations are glTF's (x, y, z, w), our scalar-first q reordered.

Everything goes into one buffer, one bufferView per accessor, each 4-byte aligned; the
JSON has no timestamps, so the same run writes the same bytes.
"""
from __future__ import annotations

import numpy as np
import pygltflib as gl

from .export_motion import Motion, box_meshes

GENERATOR = "rigid-body-taichi (HKU COMP3360 Assignment 3)"


class _Builder:
    """Accumulates the binary buffer and the accessors that view it."""

    def __init__(self):
        self.gltf = gl.GLTF2(asset=gl.Asset(version="2.0", generator=GENERATOR))
        self.blob = bytearray()

    def accessor(self, array: np.ndarray, kind: str, target: int | None = None, bounds: bool = False) -> int:
        data = np.ascontiguousarray(array)
        component = gl.UNSIGNED_INT if data.dtype == np.uint32 else gl.FLOAT
        view = gl.BufferView(buffer=0, byteOffset=len(self.blob), byteLength=data.nbytes, target=target)
        self.blob += data.tobytes()
        self.blob += b"\0" * (-len(self.blob) % 4)
        self.gltf.bufferViews.append(view)
        count = len(data)  # (count,) for SCALAR, (count, n) for VECn
        acc = gl.Accessor(bufferView=len(self.gltf.bufferViews) - 1, componentType=component,
                          count=count, type=kind)
        if bounds:  # required for POSITION and for animation inputs
            flat = data.reshape(count, -1)
            acc.min, acc.max = flat.min(axis=0).tolist(), flat.max(axis=0).tolist()
        self.gltf.accessors.append(acc)
        return len(self.gltf.accessors) - 1

    def mesh(self, name: str, vertices: np.ndarray, faces: np.ndarray) -> int:
        position = self.accessor(vertices.astype(np.float32), gl.VEC3, gl.ARRAY_BUFFER, bounds=True)
        if len(faces):
            indices = self.accessor(faces.astype(np.uint32).reshape(-1), gl.SCALAR, gl.ELEMENT_ARRAY_BUFFER)
            primitive = gl.Primitive(attributes=gl.Attributes(POSITION=position), indices=indices,
                                     mode=gl.TRIANGLES)
        else:  # a point cloud
            primitive = gl.Primitive(attributes=gl.Attributes(POSITION=position), mode=gl.POINTS)
        self.gltf.meshes.append(gl.Mesh(name=name, primitives=[primitive]))
        return len(self.gltf.meshes) - 1

    def node(self, **fields) -> int:
        self.gltf.nodes.append(gl.Node(**fields))
        return len(self.gltf.nodes) - 1


def gltf_quaternions(q: np.ndarray) -> np.ndarray:
    """Scalar-first (w, x, y, z) → glTF's (x, y, z, w), float32."""
    return np.asarray(q, np.float64)[..., [1, 2, 3, 0]].astype(np.float32)


def build_gltf(motion: Motion) -> gl.GLTF2:
    b = _Builder()
    rotations = gltf_quaternions(motion.q)  # (F, B, 4)
    translations = motion.x.astype(np.float32)  # (F, B, 3)
    roots, meshes = [], {}
    for i, name in enumerate(motion.names):
        # Copies of one body (a scene's count = N) share one mesh: linked duplicates in Blender.
        key = (motion.vertices[i].astype(np.float32).tobytes(), motion.faces[i].tobytes())
        mesh = meshes.setdefault(key, None)
        if mesh is None:
            mesh = meshes[key] = b.mesh(name, motion.vertices[i], motion.faces[i])
        roots.append(b.node(name=name, mesh=mesh, translation=translations[0, i].tolist(),
                            rotation=rotations[0, i].tolist()))
    if motion.box is not None:
        children = [b.node(name=name, mesh=b.mesh(name, v, f)) for name, v, f in box_meshes(*motion.box)]
        roots.append(b.node(name="box", children=children))
    b.gltf.scenes = [gl.Scene(name="simulation", nodes=roots)]
    b.gltf.scene = 0

    times = b.accessor(motion.t.astype(np.float32), gl.SCALAR, bounds=True)
    animation = gl.Animation(name="simulation")
    for i in range(motion.num_bodies):
        if motion.is_static(i):  # a [[static]] mesh: its node's transform, no channels
            continue
        for path, values, kind in (("translation", translations[:, i], gl.VEC3),
                                   ("rotation", rotations[:, i], gl.VEC4)):
            output = b.accessor(values, kind)
            animation.samplers.append(gl.AnimationSampler(input=times, output=output, interpolation=gl.ANIM_LINEAR))
            animation.channels.append(gl.AnimationChannel(sampler=len(animation.samplers) - 1,
                                                          target=gl.AnimationChannelTarget(node=roots[i], path=path)))
    b.gltf.animations = [animation]

    b.gltf.buffers = [gl.Buffer(byteLength=len(b.blob))]
    b.gltf.set_binary_blob(bytes(b.blob))
    return b.gltf


def gltf_bytes(motion: Motion, binary: bool) -> bytes:
    """The file's bytes: GLB (binary chunk) or glTF JSON with the buffer as a data URI."""
    gltf = build_gltf(motion)
    if binary:
        return b"".join(gltf.save_to_bytes())
    gltf.convert_buffers(gl.BufferFormat.DATAURI)
    return gltf.gltf_to_json().encode("utf-8")


def write_gltf(path, motion: Motion) -> None:
    """Write ``path`` (.glb or .gltf; the caller makes the write atomic)."""
    from pathlib import Path

    path = Path(path)
    path.write_bytes(gltf_bytes(motion, binary=path.suffix.lower() == ".glb"))
