"""Animated USD (.usda text, .usdc or .usd binary crate), through usd-core's ``pxr``.

Layout (up axis Y, metres per unit 1, as the simulation), under the default prim /World:

- per body an Xform ``/World/<name>`` with time-sampled ``xformOp:translate`` (double3,
  the centre of mass) and ``xformOp:orient`` (quatd, our scalar-first q as USD's real-first
  Gf.Quatd), and its mesh as a child prim named after the body, ``/World/<name>/<name>``,
  in the body frame about the centre of mass (a body without triangles: a Points prim).
- a static Xform ``/World/box`` (when the run has walls) holding the Meshes ``floor`` and
  ``walls`` in world coordinates, facing inwards.
- time code k is rendered frame k: ``timeCodesPerSecond`` = ``framesPerSecond`` =
  1 / (substeps × Δt) (62.5 at the defaults), start 0, end F − 1. So time code k is at
  k / timeCodesPerSecond seconds, the NPZ's t[k].

Names that are not USD identifiers are made into ones (``Tf.MakeValidIdentifier``), unique.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .export_motion import Motion, box_meshes

INSTALL_HINT = "install the usd extra: pip install -e '.[usd]' in this repository (or pip install usd-core)"


def require_usd() -> None:
    """Import usd-core's pxr now (before a simulation), or raise ImportError."""
    from pxr import Gf, Sdf, Tf, Usd, UsdGeom, Vt  # noqa: F401


def _unique_names(names: list[str]) -> list[str]:
    from pxr import Tf

    taken, out = {"box"}, []
    for name in names:
        base = Tf.MakeValidIdentifier(name)
        candidate, k = base, 2
        while candidate in taken:
            candidate, k = f"{base}_{k}", k + 1
        taken.add(candidate)
        out.append(candidate)
    return out


def _surface(stage, path: str, vertices: np.ndarray, faces: np.ndarray) -> None:
    from pxr import Gf, UsdGeom, Vt

    points = Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(vertices, np.float32))
    extent = Vt.Vec3fArray([Gf.Vec3f(*map(float, vertices.min(axis=0))), Gf.Vec3f(*map(float, vertices.max(axis=0)))])
    if len(faces):
        mesh = UsdGeom.Mesh.Define(stage, path)
        mesh.CreateFaceVertexCountsAttr(Vt.IntArray([3] * len(faces)))
        mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(np.ascontiguousarray(faces, np.int32).reshape(-1)))
        mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)  # flat triangles, not a subdivision cage
        geometry = mesh
    else:  # a point cloud
        geometry = UsdGeom.Points.Define(stage, path)
    geometry.CreatePointsAttr(points)
    geometry.CreateExtentAttr(extent)


def build_stage(motion: Motion):
    from pxr import Gf, Sdf, Usd, UsdGeom

    stage = Usd.Stage.CreateInMemory()
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    rate = 1.0 / motion.frame_time
    stage.SetTimeCodesPerSecond(rate)
    stage.SetFramesPerSecond(rate)
    stage.SetStartTimeCode(0)
    stage.SetEndTimeCode(motion.num_keys - 1)
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())

    layer = stage.GetRootLayer()
    for i, name in enumerate(_unique_names(motion.names)):
        body = UsdGeom.Xform.Define(stage, f"/World/{name}")
        translate = body.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble).GetAttr().GetPath()
        orient = body.AddOrientOp(UsdGeom.XformOp.PrecisionDouble).GetAttr().GetPath()
        if motion.is_static(i):  # a [[static]] mesh: one default value, no time samples
            body.GetPrim().GetAttributeAtPath(translate).Set(Gf.Vec3d(*motion.x[0, i].tolist()))
            q = motion.q[0, i].tolist()
            body.GetPrim().GetAttributeAtPath(orient).Set(Gf.Quatd(q[0], Gf.Vec3d(*q[1:])))
            _surface(stage, f"/World/{name}/{name}", motion.vertices[i], motion.faces[i])
            continue
        with Sdf.ChangeBlock():  # straight into the layer: faster than attribute.Set per sample
            for k, (x, q) in enumerate(zip(motion.x[:, i].tolist(), motion.q[:, i].tolist())):
                layer.SetTimeSample(translate, float(k), Gf.Vec3d(*x))
                layer.SetTimeSample(orient, float(k), Gf.Quatd(q[0], Gf.Vec3d(*q[1:])))
        _surface(stage, f"/World/{name}/{name}", motion.vertices[i], motion.faces[i])
    if motion.box is not None:
        UsdGeom.Xform.Define(stage, "/World/box")
        for name, vertices, faces in box_meshes(*motion.box):
            _surface(stage, f"/World/box/{name}", vertices, faces)
    return stage


def write_usd(path, motion: Motion) -> None:
    """Write ``path`` (.usda, .usdc or .usd, the format from its suffix; the caller makes
    the write atomic)."""
    stage = build_stage(motion)
    if not stage.GetRootLayer().Export(str(Path(path))):
        raise OSError(f"usd-core could not write {path}")
