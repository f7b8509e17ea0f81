"""The engine: Taichi fields and kernels that step the bodies (Model, State, the substep, the frame).

May import the base modules (``rigid.config``, ``rigid.errors``) and ``rigid.bodies``; never
``run``, ``view``, ``science``, ``bench``, ``report``, ``grading`` or the CLI: no drawing, no files.
"""
