"""The engine: one pipeline for one body or many, its kernels compiled once per process.

  arrays.py     the argument packs the kernels take (Model, State, World, Scratch, Rows), and the
                copies between numpy and the arrays (bytes on the CPU: no kernel per array)
  model.py      static data (Model); state.py: per-step State and runtime Params (+ the box's planes)
  blocks.py     particles in compact blocks (the unit of work and of summation)
  scratch.py    the arrays a substep rewrites (forces, grid, lists, RK4), sized for a scene
  substep.py    the substep top to bottom: place (1-2), step (3a pairs, 3b forces, 4 update);
                every schedule runs it
  stages.py     placement, planes in reach, the bodies' wrenches, the contact energy;
                force_loop.py: the one force loop (TODO 2 + planes + pairs, TODO 3 and 4),
                plane_terms.py: a particle's planes under the handout's law or the materials';
                static_faces.py: a convex [[static]] mesh touched at its faces (planes bounded by
                the mesh, out of the pair stage);
                pair_stages.py: the pair forces, each particle's full candidate list;
                pair_once.py: on one thread, each pair's force computed once for both sides;
                pair_parts.py: the same sweep in parts for a CPU's threads, the bodies cut into
                them by where they are (part_cut.py)
  candidates.py the one walk over a particle's contact candidates (its list, or the grid where
                it overflowed), which every pair consumer calls with a visitor; pair_slip.py:
                with materials, each contact pair's sticking spring kept per list entry and
                carried across rebuilds
  contact.py    the one contact law
  find_pairs.py the broadphase's one interface (stage 2): update (the motion test, then the lists
                kept, refreshed or built), place_and_build, each_candidate; broadphase.py: its
                named scalars and per-body tables and their accessors (broadphase_host.py: the
                host's side); grid.py, scan.py,
                neighbours.py: the grid and neighbour lists;
                motion.py: when the lists must be rebuilt (each body's motion, the pairs near enough to touch);
                refresh.py, refresh_search.py: only the moved bodies' lists rebuilt;
                list_growth.py: longer lists where one overflowed (the chunk run again); skin.py: the
                lists' skin adapted to how often they are rebuilt
  sleep.py      bodies at rest stop being integrated until something touches them
  forces.py     the one place for forces other than contact: on every particle (drag), at points of
                a body (the grab, [[spring]]s), all through TODO 3 and 4
  grab.py       the mouse's spring's runtime values (WorldArgs.values); pushes.py: impulses, the grab,
                waking sleepers (the Simulator's methods)
  materials.py  restitution e -> each contact's damper, the pair rules; damping_table.py: ζ'(e, ωΔt,
                load) from each scheme's own clamped oscillator (damping_tables.npz: the three
                schemes' tables, shipped); material_stages.py: the pair
                stage and the contact counts when a scene sets materials, planes or static meshes
  schemes.py    the updates from (F, τ): explicit Euler (TODO 5-7), symplectic Euler, RK4
  kernels.py    the kernels, cached per (TODO units, scheme; compact particle loops for the grader),
                each a driver of substep.py's stages; schedule.py: serial or parallel;
                split_substep.py: the parallel substep in parts; launch.py: launches with their arguments set once;
                threads.py: Taichi's CPU workers pinned one to a core for the parallel schedule
  rows.py       a row of state per frame, for the host; simulator.py: the facade
  worlds.py     many worlds in one Simulator: copies of a scene, none touching another
  units.py      the TODO units' contract; rotation.py; matvec.py: M v, dot, cross, norm written out (compile time)

Nothing here replaces a function of Taichi's (tests/test_backends.py checks).

May import the base modules (``rigid.config``, ``rigid.errors``) and ``rigid.bodies``; never
``run``, ``view``, ``science``, ``bench``, ``report``, ``grading`` or the CLI: no drawing, no files.
"""
