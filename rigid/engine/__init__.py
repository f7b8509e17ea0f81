"""The engine: one pipeline for one body or many, its kernels compiled once per process.

  arrays.py     the argument packs the kernels take (Model, State, World, Scratch, Rows), and the
                copies between numpy and the arrays (bytes on the CPU: no kernel per array)
  model.py      static data (Model); state.py: per-step State and runtime Params (+ the box's planes)
  blocks.py     particles in compact blocks (the unit of work and of summation)
  scratch.py    the arrays a substep rewrites (forces, grid, lists, RK4), sized for a scene
  stages.py     the stages of a substep; pair_stages.py: those only bodies in contact need;
                pair_once.py: on one thread, each pair's force computed once for both sides;
                pair_parts.py: the same sweep in parts for a CPU's threads, the bodies cut into
                them by where they are (part_cut.py)
  contact.py    the one contact law; grid.py, scan.py, neighbours.py: the grid and neighbour lists;
                motion.py: when the lists must be rebuilt (each body's motion, the pairs near enough to touch);
                list_growth.py: longer lists where one overflowed (the chunk run again); skin.py: the
                lists' skin adapted to how often they are rebuilt
  sleep.py      bodies at rest stop being integrated until something touches them
  forces.py     the one place for forces other than contact: on every particle (drag), at points of
                a body (the grab, [[spring]]s), all through TODO 3 and 4
  grab.py       the mouse's spring's runtime values (WorldArgs.values); pushes.py: impulses, the grab,
                waking sleepers (the Simulator's methods)
  materials.py  restitution e -> each contact's damper, the pair rules; damping_table.py: ζ'(e, ωΔt,
                load) from each scheme's own clamped oscillator; material_stages.py: the force
                stages when a scene sets materials, planes or static meshes
  schemes.py    the updates from (F, τ): explicit Euler (TODO 5-7), symplectic Euler, RK4
  kernels.py    the kernels, cached per (TODO units, scheme; compact particle loops for the grader);
                schedule.py: serial or parallel; launch.py: launches with their arguments set once;
                threads.py: Taichi's CPU workers pinned one to a core for the parallel schedule
  rows.py       a row of state per frame, for the host; simulator.py: the facade
  units.py      the TODO units' contract; rotation.py, matvec.py: helpers

Nothing here replaces a function of Taichi's (tests/test_backends.py checks).

May import the base modules (``rigid.config``, ``rigid.errors``) and ``rigid.bodies``; never
``run``, ``view``, ``science``, ``bench``, ``report``, ``grading`` or the CLI: no drawing, no files.
"""
