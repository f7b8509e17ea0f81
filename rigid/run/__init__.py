"""Driving a simulator over frames: the frame loop, blow-up checks, trajectories, atomic outputs.

May import the base modules, ``bodies`` and ``engine``; never ``view`` (drawing calls into here).
"""
