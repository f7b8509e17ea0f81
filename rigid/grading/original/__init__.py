"""Grading files in the format of the course's original handout (one module-level script).

Such a file calls ``ti.init`` at import, keeps the body in global fields
(``body_cm_position``, ``particle_force``, ...), has kernels ``initial()`` and
``substep()`` whose TODOs are marked only by ``# TODO k: title`` (no END
marker), and runs a GGUI ``while window.running:`` loop at module level.

- detect.py     which format a submission is in
- regions.py    where each TODO's code starts and ends (from its comment, else align.py), its kernel
- align.py      where a TODO is when its comment is gone: its place among the handout's given code
- context.py    what is around a region: its loop, the given lines before it, the local it hands on
- keep.py       the student's lines of a region that stay when the reference lines replace it
- handout_shape.py  the handout's markers, titles and given code, as tables and regexes (read by regions.py)
- scan.py       which lines continue a statement (brackets, strings), for a file that may not parse
- reference.py  the project's reference lines for each TODO, written for the handout's names
- variants.py   the file with some regions replaced, other parameters, the grader's harness kernels
- harness.py    each region alone in a kernel, called on the seeded inputs of specs.py (the direct check)
- headless.py   stand-ins for ti.init, ti.ui and ti.GUI: no window, N frames, a snapshot per frame
- fields.py     one set of fields for all the versions of a file, zeroed before each (kernels compile once)
- runner.py     import a variant under the stand-ins and return its trajectory
- attribution.py  per-TODO trajectory runs (joint, then halves) with the file's and perturbed parameters
- child.py      the sandboxed child's work for this format (same events as ../child.py)
- meshes.py     which mesh files a submission reads, and what the sandbox gets in their place
- warm.py       the TA's handout solved with the reference lines, graded once: its kernels warm every child

Runs inside the grading child, like ../checks.py. May import what rigid.grading may import
(the base modules, ``bodies``, ``engine``, ``run``) and the rest of ``rigid.grading``.
"""
