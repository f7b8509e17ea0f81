"""Meshes in, particles out: mesh files, the plain-OBJ reader, volume sampling, the shipped assets;
the scene's materials and static colliders (colliders.py, statics.py) and the start checks (overlap.py).

Plain numpy (no Taichi). May import only the base modules (``rigid.config``, ``rigid.errors``).
"""
