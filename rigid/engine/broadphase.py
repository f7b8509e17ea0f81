"""The broadphase's arrays, each value in a named place, and the accessors the kernels read and
write them through.

The broadphase finds the pairs of particles that may touch: it builds the grid and the neighbour
lists (grid.py, neighbours.py), refreshes the lists of the bodies that moved (refresh.py), hands
the pair stages each particle's candidates (candidates.each_candidate; the active list, a body's
run of it, the pair stage's parts) and passes over sleepers (see_sleeper ...). Its per-particle
arrays are named in grid.py and neighbours.py (``cell_count``, ``sorted_x``, ``nbr_list``,
``build_x``, ``active`` ...); its scalars and per-body values live in four arrays of ScratchArgs,
each index a named constant below (arrays.py: a kernel taking every pack is at the x64 backend's
64 argument elements, so these four hold what used to be four arrays; Taichi 1.7's ndarrays have
no struct dtype, so they are packed by kind and meaning: int scalars, float scalars, a table of
per-body ints, a table of per-body floats). Every read and write goes through this module:
other modules name a slot (``get(scratch, REBUILD)``) or call an accessor, never an offset;
the host's side (the arrays made, reset, read): broadphase_host.py.

``broadphase_ints``  (INTS,) i32, the int scalars:
  REBUILD      0 none; 1 rebuild the lists at the next placement; MAYBE, VIOLATED while the
               motion test decides (motion.py); refresh.PENDING while a refresh searches
  BUILDS       full builds so far (benchmarks, skin.py)
  ACTIVE       particles in the active list (``active[0 .. ACTIVE)``: those with a candidate)
  SLEEP_MODE   pair_parts.prepare's mode this substep (0 none asleep, 1 a few, 2 many)
  OVERFLOW     1 once a list overflowed (list_growth.py lowers it before a chunk)
  REFRESHED_BODIES, REFRESHED_PARTICLES   the bodies refreshed since the last full build, their
               particles; REFRESHES   refreshes so far (benchmarks); SEARCHING   the particles a
               pending refresh searches for; BUCKETS   its hash's H; SEARCH_FULL   1 if a list
               was full; REFRESH_COST   the last full build's and the refreshes' cost since it;
               MOTION_TESTS   the motion tests since it (refresh.py)
  GRID_DIM, GRID_CELLS, GRID_CHUNKS   the grid's cells per axis D, cells D³, scan chunks (grid.py)
``broadphase_floats``  (FLOATS,) float, the float scalars:
  INV_CELL     1 / the grid's cell (the largest diameter + the skin); SKIN   the lists' skin;
  ALLOWED      the relative motion allowed before a rebuild (the skin less 2 % for round-off);
  R_MAX        the largest particle radius (pair_stages.pair_between's reach);
  MAX_REFRESHED   the share of the particles refreshed since a full build at most (refresh.py,
               0: never); FULL_BUILD_COST   a full build's cost in refreshed particles, per particle
  SHIFT_LO[k], SHIFT_HI[k], E_FIRST, E_SECOND, E_TIES   motion.note_motion_spread's reductions
               (off a CPU): the least and largest Δx per axis, the largest e_b, the largest below
               it, the count of its ties
``broadphase_body_ints``  (BODY_INTS, B + 1) i32, row ``what`` a per-body list (index b a body,
  or a position where the list says so):
  SLEEPER_SEEN   1 when b sleeps and a body that does not rest has it in its lists (pair_once.py)
  RUN_START    where b's run of the active list starts, at B its end (index_active_by_body)
  PART         b's part of the pair stage this substep (part_cut.py)
  REFRESH_STATE   b's bits MARKED (refreshed now), REFRESHED (since the last full build)
  REFRESH_ORDER   at k: the k-th body refreshed since the last full build
  TOUCHES      b's touching particles when the pair stage's parts last ran (the cut's weight)
  CUT_INDEX    at t: the body at position t of the cut's selection (part_cut.py)
``broadphase_body_floats``  (B, BODY_FLOATS) float, per body b:
  POSE_X[0..2], POSE_R[0..8]   its x and R (row by row) at the last build or its last refresh
  RHO          ρ_b, its particles' largest |r0| (rounded up; set at a reset)
  MOTION       e_b, the bound on its particles' motion since then (motion.note_motion)
  REACH        ρ'_b >= its particles' distance from its centre now (motion.py)
  MOVED        e⁰_b, that bound with no common shift (refresh.py)
  CUT_KEY      at t: the coordinate of the body at position t of the cut's selection (part_cut.py)
"""
import taichi as ti

# broadphase_ints
(REBUILD, BUILDS, ACTIVE, SLEEP_MODE, OVERFLOW, REFRESHED_BODIES, REFRESHED_PARTICLES, REFRESHES, SEARCHING,
 BUCKETS, SEARCH_FULL, REFRESH_COST, MOTION_TESTS, GRID_DIM, GRID_CELLS, GRID_CHUNKS) = range(16)
INTS = 16

# broadphase_floats
INV_CELL, SKIN, ALLOWED, R_MAX, MAX_REFRESHED, FULL_BUILD_COST = range(6)
SHIFT_LO, SHIFT_HI = (6, 7, 8), (9, 10, 11)
E_FIRST, E_SECOND, E_TIES = 12, 13, 14
FLOATS = 15

# broadphase_body_ints
SLEEPER_SEEN, RUN_START, PART, REFRESH_STATE, REFRESH_ORDER, TOUCHES, CUT_INDEX = range(7)
BODY_INTS = 7
MARKED, REFRESHED = 1, 2  # REFRESH_STATE's bits

# broadphase_body_floats
POSE_X = (0, 1, 2)
POSE_R = tuple(range(3, 12))
RHO, MOTION, REACH, MOVED, CUT_KEY = range(12, 17)
BODY_FLOATS = 17


@ti.func
def get(scratch: ti.template(), what: ti.template()):
    """The int scalar ``what`` (REBUILD ... GRID_CHUNKS)."""
    return scratch.broadphase_ints[what]


@ti.func
def put(scratch: ti.template(), what: ti.template(), value):
    scratch.broadphase_ints[what] = value


@ti.func
def claim_active(scratch: ti.template()):
    """The next place in the active list (atomic: ACTIVE + 1, the old value returned)."""
    return ti.atomic_add(scratch.broadphase_ints[ACTIVE], 1)


@ti.func
def value(scratch: ti.template(), what: ti.template()):
    """The float scalar ``what`` (INV_CELL ... E_TIES)."""
    return scratch.broadphase_floats[what]


@ti.func
def set_value(scratch: ti.template(), what: ti.template(), v):
    scratch.broadphase_floats[what] = v


@ti.func
def lower_value(scratch: ti.template(), what: ti.template(), v):
    """The float scalar ``what`` = min(itself, v), atomically (a reduction's threads)."""
    ti.atomic_min(scratch.broadphase_floats[what], v)


@ti.func
def raise_value(scratch: ti.template(), what: ti.template(), v):
    ti.atomic_max(scratch.broadphase_floats[what], v)


@ti.func
def add_value(scratch: ti.template(), what: ti.template(), v):
    ti.atomic_add(scratch.broadphase_floats[what], v)


@ti.func
def body_int(scratch: ti.template(), b, what: ti.template()):
    """Entry b of the per-body list ``what`` (SLEEPER_SEEN ... CUT_INDEX)."""
    return scratch.broadphase_body_ints[what, b]


@ti.func
def set_body_int(scratch: ti.template(), b, what: ti.template(), v):
    scratch.broadphase_body_ints[what, b] = v


@ti.func
def body_float(scratch: ti.template(), b, what: ti.template()):
    """Body b's float ``what`` (RHO, MOTION, REACH, MOVED, CUT_KEY)."""
    return scratch.broadphase_body_floats[b, what]


@ti.func
def set_body_float(scratch: ti.template(), b, what: ti.template(), v):
    scratch.broadphase_body_floats[b, what] = v


@ti.func
def reference_x(scratch: ti.template(), b):
    """x of body b at the last build or its last refresh."""
    return ti.Vector([scratch.broadphase_body_floats[b, POSE_X[k]] for k in ti.static(range(3))])


@ti.func
def reference_R(scratch: ti.template(), b):
    """R of body b at the last build or its last refresh."""
    return ti.Matrix([[scratch.broadphase_body_floats[b, POSE_R[3 * r + c]] for c in ti.static(range(3))]
                      for r in ti.static(range(3))])


@ti.func
def keep_reference_pose(scratch: ti.template(), b, x, R):
    """Body b's reference pose ← (x, R) (a build or its refresh)."""
    for k in ti.static(range(3)):
        scratch.broadphase_body_floats[b, POSE_X[k]] = x[k]
    for r, c in ti.static(ti.ndrange(3, 3)):
        scratch.broadphase_body_floats[b, POSE_R[3 * r + c]] = R[r, c]


# The accessors the physics modules call.

@ti.func
def body_radius(scratch: ti.template(), b):
    """ρ_b, body b's particles' largest distance from its centre (sleep.speed_bound)."""
    return body_float(scratch, b, RHO)


@ti.func
def largest_radius(scratch: ti.template()):
    """The largest particle radius (a pair's reach at most r_a + this)."""
    return value(scratch, R_MAX)


@ti.func
def part_of(scratch: ti.template(), b):
    """The part body b's particles belong to (after part_cut.cut_bodies in this substep)."""
    return body_int(scratch, b, PART)


@ti.func
def see_sleeper(scratch: ti.template(), b):
    set_body_int(scratch, b, SLEEPER_SEEN, 1)


@ti.func
def unsee_sleeper(scratch: ti.template(), b):
    set_body_int(scratch, b, SLEEPER_SEEN, 0)


@ti.func
def seen_sleeper(scratch: ti.template(), b):
    return body_int(scratch, b, SLEEPER_SEEN) != 0


@ti.func
def body_active_range(scratch: ti.template(), b):
    """(first, end) of body b's run of the active list (neighbours.index_active_by_body)."""
    return body_int(scratch, b, RUN_START), body_int(scratch, b + 1, RUN_START)


# The partial rebuilds' (refresh.py).

@ti.func
def body_state(scratch: ti.template(), b):
    """Body b's REFRESH_STATE bits (MARKED, REFRESHED)."""
    return body_int(scratch, b, REFRESH_STATE)


@ti.func
def marked(scratch: ti.template(), b):
    return body_state(scratch, b) & MARKED != 0


@ti.func
def refreshed_body(scratch: ti.template(), k):
    """The k-th body refreshed since the last full build."""
    return body_int(scratch, k, REFRESH_ORDER)


@ti.func
def searching(scratch: ti.template()):
    """How many particles the pending refresh searches for (scratch.active[0 .. n - 1])."""
    return get(scratch, SEARCHING)
