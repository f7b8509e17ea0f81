"""Where a TODO is when its ``# TODO k:`` comment is gone: its place among the handout's given code.

Students delete, reword and move the TODO comments; the given code around each TODO stays. A
statement is *given* when its fingerprint is one of the handout's (given.HASHES); a block (a
statement with the lines indented under it) is given when all its statements are. In the
handout's two kernels:

- TODO 1 (initial): the blocks that are not given just before ``body_origin_inverse_inertia[None] = ...``;
- TODOs 2, 3, 4 (substep): the bodies of the loops over the particles: the loop that holds the
  given collision code (TODO 2: the lines before its ``if particle_vertices[i][1] < -1:``), then
  the next two loops (TODO 3, TODO 4);
- TODOs 5 and 6: the blocks after TODO 4's loop and before the quaternion's normalisation (or the
  rotation matrix's update): TODO 5 up to its last write of ``body_cm_position``/``body_velocity``,
  TODO 6 from there (its locals, then its write of ``body_rotation_quaternion``);
- TODO 7: the blocks that are not given between ``body_rotation[None] = ...`` and the particle update loop.

``virtual_markers(...)`` returns, for each TODO asked, (the index of the line before its code,
the indentation of its code, the line its region ends by at the latest), which regions.py reads as
it reads a marker line. Where the student's code does not follow the handout's order (TODOs 3 and 4
in one loop, TODO 6's update before TODO 5's) those TODOs are not placed. A TODO it cannot
place is left out (it stays "not graded", with the message naming the comment expected).
"""
import re

from .given import HASHES, HASHES_2023, fingerprint
from .handout_shape import ANCHORS, JOB, NORMALISE, WRITES
from .scan import indent_of

KNOWN = HASHES | HASHES_2023
FOR = re.compile(r"^for\b")


def _blocks(lines, cont, first, end):
    """Top-level blocks of the function body between ``first`` (its def line) and ``end``:
    [(first line, end line, indentation string, [statement texts])]."""
    code = [j for j in range(first + 1, end) if lines[j].strip() and not lines[j].strip().startswith("#")
            and j not in cont]
    if not code:
        return []
    level = indent_of(lines[code[0]])
    out = []
    for j in code:
        if indent_of(lines[j]) == level:
            out.append([j, j + 1, lines[j][:len(lines[j]) - len(lines[j].lstrip())], []])
        elif indent_of(lines[j]) < level:
            break
        statement, last = lines[j], j + 1
        while last < end and last in cont:  # the statement's continuation lines
            statement, last = statement + "\n" + lines[last], last + 1
        out[-1][1] = last
        out[-1][3].append(statement)
    return [tuple(b) for b in out]


def _given(block) -> bool:
    return all(fingerprint(s) in KNOWN for s in block[3])


def _head(block) -> str:
    return block[3][0].strip()


def _before(blocks, i, stop=lambda b: False):
    """The first index of the run of blocks that are not given (nor ``stop``) just before block ``i``."""
    j = i
    while j > 0 and not _given(blocks[j - 1]) and not stop(blocks[j - 1]):
        j -= 1
    return j


def _place(blocks, i, end_line):
    """(marker index, indentation, end) of a region from block ``i`` to the line ``end_line`` (maybe empty)."""
    if i < len(blocks) and blocks[i][0] < end_line:
        return blocks[i][0] - 1, blocks[i][2], end_line
    return end_line - 1, blocks[i][2] if i < len(blocks) else "", end_line


def _loop_body(lines, cont, block):
    """(marker index, indentation, end) of a loop's body: after its header, at its first statement's indentation."""
    header = block[0]
    inner = [j for j in range(header + 1, block[1]) if lines[j].strip() and not lines[j].strip().startswith("#")
             and j not in cont]
    indent = lines[inner[0]][:len(lines[inner[0]]) - len(lines[inner[0]].lstrip())] if inner else \
        block[2] + "    "
    return header, indent, block[1]


def virtual_markers(lines, cont, functions, wanted) -> dict:
    out = {}
    kernels = {name: (first, end) for first, end, name in functions}
    if 1 in wanted and "initial" in kernels:
        blocks = _blocks(lines, cont, lines_def(lines, kernels["initial"]), kernels["initial"][1])
        anchor = next((i for i, b in enumerate(blocks) if ANCHORS[1].match(_head(b))
                       and _head(b).startswith("body_origin_inverse_inertia")), None)
        if anchor is not None:
            out[1] = _place(blocks, _before(blocks, anchor), blocks[anchor][0])
    if "substep" not in kernels:
        return out
    blocks = _blocks(lines, cont, lines_def(lines, kernels["substep"]), kernels["substep"][1])
    rotation = next((i for i, b in enumerate(blocks) if ANCHORS[6].match(_head(b))), len(blocks))
    loops = [i for i, b in enumerate(blocks[:rotation]) if FOR.match(_head(b))]
    collision = next((n for n, i in enumerate(loops) if any(ANCHORS[2].match(s.strip()) and s.strip().startswith("if")
                                                             for s in blocks[i][3])), None)
    if collision is not None:
        if collision + 1 < len(loops) and re.search(JOB[4], "\n".join(blocks[loops[collision + 1]][3][1:])):
            wanted = [k for k in wanted if k not in (3, 4)]  # TODOs 3 and 4 in one loop: neither has its place
        for n, k in enumerate((2, 3, 4)):
            if k in wanted and collision + n < len(loops):
                out[k] = _loop_body(lines, cont, blocks[loops[collision + n]])
    last_loop = loops[collision + 2] if collision is not None and collision + 2 < len(loops) else None
    if last_loop is not None:
        normalise = next((i for i in range(last_loop + 1, rotation + 1) if i < len(blocks)
                          and NORMALISE.match(_head(blocks[i]))), rotation)
        between = range(last_loop + 1, normalise)
        writes5 = [i for i in between if any(WRITES[5].match(s.strip()) for s in blocks[i][3])]
        split = writes5[-1] + 1 if writes5 else last_loop + 1
        if any(WRITES[6].match(s.strip()) for i in range(last_loop + 1, split) for s in blocks[i][3]):
            wanted = [k for k in wanted if k not in (5, 6)]  # TODO 6's update before TODO 5's: no place for either
        if 5 in wanted:
            first5 = next((i for i in between if not _given(blocks[i])), split)
            out[5] = _place(blocks, min(first5, split), blocks[split][0] if split < len(blocks) else
                            kernels["substep"][1])
        if 6 in wanted and normalise < len(blocks):
            out[6] = _place(blocks, split, blocks[normalise][0])
    if 7 in wanted and rotation < len(blocks):
        update = next((i for i in range(rotation + 1, len(blocks)) if ANCHORS[7].match(_head(blocks[i]))), None)
        if update is not None:
            out[7] = _place(blocks, _before(blocks, update), blocks[update][0])
    return out


def lines_def(lines, span) -> int:
    """The index of the ``def`` line of a function whose span (from its first decorator) is ``span``."""
    first, end = span
    return next(j for j in range(first, end) if lines[j].lstrip().startswith("def "))
