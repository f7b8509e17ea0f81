"""TA tools: the student handout and the autograder (see scripts/make_handout.py, scripts/grade.py).

- handout.py      the student starter from rigid_body_dynamic.py (TODO bodies -> hints + placeholders)
- bundle.py       write the handout with its answers file, or the zip of all a student needs
- submissions.py  find submissions in files, folders and zips
- batch.py        grade many in parallel, one sandboxed child process each (sandbox.py)
- box.py          the bubblewrap box each child runs in (no network, no files but its own)
- child.py        inside the child: import the submission, check each TODO, report events
- attempts.py     inside the child: note what a submission tries outside its folder
- specs.py, direct.py, diagnose.py, mistakes.py, inertia_words.py, trajectory.py, alternatives.py  the checks
- original/       submissions written for the course's original handout (a module-level script)
- report.py       the terminal table, JSON and CSV
- answers.py, selfcheck.py  the answers file beside the handout and ``rigid_body_dynamic.py --check``

This package imports nothing heavy at import time: the child sets its resource
limits before numpy and Taichi load. May import the base modules, ``bodies``, ``engine`` and
``run``; never ``view``, ``report`` or the CLI.
"""
