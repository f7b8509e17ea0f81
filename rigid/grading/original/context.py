"""What is around a TODO region of the original format: its loop, the given lines before it, the local it hands on.

``loop_and_context(region, lines, cont, student)`` fills a regions.Region's loop (header, its
variable, the given lines of its body before the TODO, the given ``name = ...`` lines before the
loop) and context (the given ``name = ...`` lines before the TODO at its own level); the harness
(harness.py) rebuilds them around the region alone. ``shared_name(region, lines)`` is the local
TODO 1, 3 or 4 hands on to the code after it (the inertia, the total force, the total torque).
Lines of TODO regions (``student``) are never context.
"""
import re

from .handout_shape import SHARED
from .scan import indent_of

FOR = re.compile(r"^\s*for\s+(?P<var>[A-Za-z_]\w*)\s+in\b.*:\s*(#.*)?$")
ASSIGN = re.compile(r"^\s*(?P<name>[A-Za-z_]\w*)\s*(?P<op>\+?=)(?!=)")
IDENT = re.compile(r"[A-Za-z_]\w*")


def loop_and_context(region, lines, cont, student) -> None:
    """The innermost enclosing for loop (header, its body's given lines before the TODO, the given
    ``name = ...`` lines before it at its level) and the given ``name = ...`` lines before the TODO at its
    own level. Lines of TODO regions are never context."""
    level = region.level
    first = region.kernel_lines[0]
    header = None
    for j in range(region.start - 1, first, -1):  # a real marker line is a comment: skipped
        text = lines[j].strip()
        if not text or text.startswith("#") or j in cont or j in student:
            continue
        if indent_of(lines[j]) < level:
            if FOR.match(lines[j]):
                header = j
            break
    if header is not None:
        region.loop_header = lines[header].strip()
        region.loop_var = FOR.match(lines[header])["var"]
        region.loop_context = _statements(lines, header + 1, region.start, cont, student)
        outer_level = indent_of(lines[header])
        outer_start = _block_start(lines, header, first, outer_level, cont | student)
        region.outer = [line for line in _statements(lines, outer_start, header, cont, student)
                        if indent_of(line) == outer_level and ASSIGN.match(line) and ASSIGN.match(line)["op"] == "="]
    block_start = header + 1 if header is not None else _block_start(lines, region.start, first, level,
                                                                     cont | student)
    region.context = [line for line in _statements(lines, block_start, region.start, cont, student)
                      if indent_of(line) == level and ASSIGN.match(line) and ASSIGN.match(line)["op"] == "="]


def _block_start(lines, marker, first, level, skip) -> int:
    """First line of the block the line ``marker`` sits in."""
    for j in range(marker - 1, first, -1):
        text = lines[j].strip()
        if text and not text.startswith("#") and j not in skip and indent_of(lines[j]) < level:
            return j + 1
    return first + 1


def _statements(lines, start, stop, cont, student) -> list:
    """Given statements between two line indices, each with its continuation lines; comments left out."""
    out = []
    for j in range(start, stop):
        text = lines[j].strip()
        if j in student:
            continue
        if j in cont:
            if out:
                out[-1] += "\n" + lines[j]
        elif text and not text.startswith("#"):
            out.append(lines[j])
    return out


def shared_name(region, lines) -> str:
    """The local variable TODO 1, 3 or 4 hands on to the code after it."""
    first, last = region.kernel_lines
    after = set(IDENT.findall("\n".join(lines[region.end:last])))
    inside = set(IDENT.findall("\n".join(line.split("#")[0] for line in region.code(lines))))
    given = [ASSIGN.match(line)["name"] for line in region.outer + region.context]
    given = [n for n in given if n in after or n in inside]
    level = region.level
    assigned = []
    for line in region.code(lines):
        m = ASSIGN.match(line)
        if m and (m["op"] == "+=" or indent_of(line) == level) and m["name"] not in assigned:
            assigned.append(m["name"])
    if SHARED[region.k] in given and (SHARED[region.k] in assigned or SHARED[region.k] in after):
        return SHARED[region.k]
    if given and (given[-1] in assigned or not [n for n in assigned if n in after]):
        return given[-1]
    own = [n for n in assigned if n in after]
    if own:
        return own[0]
    return given[-1] if given else SHARED[region.k]
