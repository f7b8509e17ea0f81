"""Differentiable mode: gradients through a run of the engine's physics, and fitting to data.

  scope.py     what the mode takes: one line for a scene feature, a wrt name or a cotangent it refuses
  problem.py   a scene as the pass reads it (the engine's placement, planes and materials)
  tape.py      the fields: state with a step axis for one segment, parameters, rows
  transfers.py copies between the host and a tape's fields, one launch each
  kernels.py   the substep written time-indexed, from the student's TODO units and the engine's
               contact law (rigid.engine.contact, rigid.engine.materials)
  passes.py    forward and backward, in segments with checkpoints (bounded memory)
  gradient.py  rigid.gradient: cotangents of the rows -> gradients of the scene's keys
  fit.py       rigid.fit: least squares of simulated rows against observed ones (L-BFGS-B)

May import the base modules and rigid.engine, rigid.bodies; nothing imports it but the API.
"""
from .fit import fit
from .gradient import gradient

__all__ = ["gradient", "fit"]
