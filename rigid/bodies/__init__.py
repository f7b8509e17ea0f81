"""Meshes in, particles out: mesh files, the plain-OBJ reader, volume sampling, the shipped assets.

Plain numpy (no Taichi). May import only the base modules (``rigid.config``, ``rigid.errors``).
"""
