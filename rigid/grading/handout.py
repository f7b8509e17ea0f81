"""The student handout, generated from the solution file, so the two never drift apart.

Between the markers ``# TODO k: title`` and ``# END TODO k`` (DESIGN's
contract) the solution's code is replaced by its hint comments (lines starting
``# Hint`` and their indented ``#`` continuation lines) and by a placeholder
that keeps the file importable and runnable: the body then sits still (zero
forces, no motion, a zero inertia tensor, which the engine reports and then
runs without rotation). Every other line is kept as it is.
"""
import re

from ..errors import UserError

START = re.compile(r"^(?P<indent>\s*)# TODO (?P<k>\d+):")
END = re.compile(r"^\s*# END TODO (?P<k>\d+)\b")
PLACEHOLDER_NOTE = "# Placeholder so that the file runs: replace it with your code."
PLACEHOLDERS = {
    1: ["inertia = ti.Matrix.zero(float, 3, 3)"],
    2: ["force = ti.Vector.zero(float, 3)"],
    3: ["term = ti.Vector.zero(float, 3)"],
    4: ["term = ti.Vector.zero(float, 3)"],
    5: ["new_position = position", "new_momentum = momentum"],
    6: ["new_q = q"],
    7: ["new_L = angular_momentum", "inertia_inv = ti.Matrix.zero(float, 3, 3)",
        "omega = ti.Vector.zero(float, 3)"],
}


def todo_blocks(lines: list) -> dict:
    """k -> (index of the TODO line, index of the END line); UserError unless each of 1..7 is once, well formed."""
    blocks, open_k = {}, None
    for i, line in enumerate(lines):
        start, end = START.match(line), END.match(line)
        if start:
            k = int(start["k"])
            if open_k is not None:
                raise UserError(f"line {i + 1}: TODO {k} starts inside TODO {open_k}; close it with "
                                f"'# END TODO {open_k}'")
            if k in blocks:
                raise UserError(f"line {i + 1}: TODO {k} appears twice")
            open_k, blocks[k] = k, (i, None)
        elif end:
            k = int(end["k"])
            if k != open_k:
                raise UserError(f"line {i + 1}: '# END TODO {k}' without an open '# TODO {k}:'")
            blocks[k], open_k = (blocks[k][0], i), None
    if open_k is not None:
        raise UserError(f"TODO {open_k} has no '# END TODO {open_k}' line")
    missing = sorted(set(PLACEHOLDERS) - set(blocks))
    if missing:
        raise UserError(f"no '# TODO {missing[0]}:' marker; the solution must mark TODOs 1 to 7")
    return blocks


def hint_lines(body: list) -> list:
    """The '# Hint' comment lines of a block and their continuation lines ('#' then 2+ spaces)."""
    kept, in_hint = [], False
    for line in body:
        text = line.strip()
        if text.startswith("# Hint"):
            kept.append(line)
            in_hint = True
        elif in_hint and text.startswith("#  "):
            kept.append(line)
        else:
            in_hint = False
    return kept


def make_handout(solution: str) -> str:
    """The handout's text from the solution's text."""
    lines = solution.splitlines(keepends=True)
    blocks = todo_blocks(lines)
    out, i = [], 0
    for k in sorted(blocks, key=lambda k: blocks[k][0]):
        start, end = blocks[k]
        indent = START.match(lines[start])["indent"]
        out.extend(lines[i:start + 1])
        out.extend(hint_lines(lines[start + 1:end]))
        out.append(f"{indent}{PLACEHOLDER_NOTE}\n")
        out.extend(f"{indent}{code}\n" for code in PLACEHOLDERS[k])
        i = end
    out.extend(lines[i:])
    return "".join(out)


def solution_lines(solution: str) -> set:
    """The solution's code lines inside the TODO blocks, stripped (what the handout must never show)."""
    lines = solution.splitlines()
    code = set()
    for start, end in todo_blocks(lines).values():
        code.update(line.strip() for line in lines[start + 1:end]
                    if line.strip() and not line.strip().startswith("#"))
    return code
