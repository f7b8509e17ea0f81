"""Where each TODO's code is in a file of the original handout's format.

A TODO's region starts after its line ``# TODO k: title`` and runs until the
first line (continuation lines of a statement never count) that is

- another ``# TODO j`` line (or an ``# END TODO`` line),
- less indented than the TODO line (the enclosing loop or kernel ends),
- a comment as indented as the TODO line that starts given code: its first word
  begins with one of GIVEN_WORDS ("# Collision force ...", "# computer the torque ...",
  "# update the particles", "# normalize ..."); other comments (hints, the student's
  own notes) stay in the region,
- for TODOs 1 and 6, a line as indented that writes a field the given code after them
  sets (``body_origin_inverse_inertia[None] = ...``, ``body_rotation[None] = ...``).

Trailing blank lines are left out. Each region knows its kernel, the innermost
``for`` loop around it (TODO 2 sits in the given particle loop) and, for TODOs
1, 3 and 4, the local variable it hands on (the inertia, the total force, the
total torque): the one the handout declares before it, or failing that the one
the student's region assigns and later code reads.
"""
import ast
import io
import re
import tokenize
from dataclasses import dataclass, field

MARKER = re.compile(r"^(?P<indent>[ \t]*)#\s*TODO\s*(?P<k>[1-7])(?![0-9])\s*:?\s*(?P<title>.*)$", re.IGNORECASE)
END_MARKER = re.compile(r"^\s*#\s*END\s+TODO", re.IGNORECASE)
GIVEN_WORDS = ("collision", "comput", "update", "normali", "given", "render", "draw")
GIVEN_AFTER = {1: ("body_origin_inverse_inertia", "body_angular_momentum", "body_velocity"),
               6: ("body_rotation",)}
SHARED = {1: "inertia", 3: "body_force", 4: "body_torque"}  # default names of the locals handed on
FOR = re.compile(r"^\s*for\s+(?P<var>[A-Za-z_]\w*)\s+in\b.*:\s*(#.*)?$")
ASSIGN = re.compile(r"^\s*(?P<name>[A-Za-z_]\w*)\s*(?P<op>\+?=)(?!=)")
IDENT = re.compile(r"[A-Za-z_]\w*")


@dataclass
class Region:
    k: int
    marker: int  # index of the '# TODO k' line
    start: int  # first line of the region (marker + 1)
    end: int  # first line after it
    indent: str  # the TODO line's indentation
    kernel: str  # name of the function around it
    kernel_lines: tuple  # (first, last + 1) line indices of that function
    loop_var: str | None = None  # variable of the innermost given for loop around it
    loop_header: str | None = None
    loop_context: list = field(default_factory=list)  # given lines of that loop's body before the TODO
    context: list = field(default_factory=list)  # given 'name = ...' lines before it at its own level
    shared: str | None = None  # TODOs 1, 3, 4: the local handed on

    def code(self, lines) -> list:
        return lines[self.start:self.end]

    def has_code(self, lines) -> bool:
        return any(line.strip() and not line.strip().startswith("#") for line in self.code(lines))


class RegionError(Exception):
    """The file's TODO markers cannot be read; the message is for the student."""


def indent_of(line: str) -> int:
    return len(line.expandtabs(4)) - len(line.expandtabs(4).lstrip())


def continuation_lines(text: str) -> set:
    """Indices of lines that continue a statement (inside brackets, a string or after a backslash)."""
    cont, depth = set(), 0
    try:
        for tok in tokenize.generate_tokens(io.StringIO(text).readline):
            if tok.type == tokenize.OP and tok.string in "([{":
                depth += 1
            elif tok.type == tokenize.OP and tok.string in ")]}":
                depth = max(0, depth - 1)
            elif tok.type in (tokenize.NL, tokenize.NEWLINE) and depth:
                cont.add(tok.start[0])  # 1-based: the next line (index tok.start[0]) continues
            if tok.end[0] > tok.start[0]:  # a string over several lines
                cont.update(range(tok.start[0], tok.end[0]))
    except (tokenize.TokenError, IndentationError, SyntaxError):
        pass
    for i, line in enumerate(text.splitlines()):
        if line.rstrip().endswith("\\"):
            cont.add(i + 1)
    return cont


def find_regions(text: str) -> dict:
    """k -> Region for k = 1..7; RegionError (one line for the student) if the markers cannot be read."""
    try:
        tree = ast.parse(text)
    except SyntaxError as err:
        raise RegionError(f"the file has a syntax error at line {err.lineno}: {err.msg}")
    lines = text.splitlines()
    functions = [(n.lineno - 1 - len(n.decorator_list), n.end_lineno, n.name) for n in ast.walk(tree)
                 if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]
    cont = continuation_lines(text)
    markers = {}
    for i, line in enumerate(lines):
        m = MARKER.match(line)
        if m and i not in cont:
            k = int(m["k"])
            if k in markers:
                raise RegionError(f"'# TODO {k}' appears twice (lines {markers[k] + 1} and {i + 1}); "
                                  f"keep one marker per TODO")
            markers[k] = i
    missing = [k for k in range(1, 8) if k not in markers]
    if missing:
        raise RegionError(f"no '# TODO {missing[0]}:' line; keep the handout's TODO comments")
    regions = {k: _region(k, i, lines, functions, cont) for k, i in markers.items()}
    student = {j for r in regions.values() for j in range(r.marker, r.end)}
    for region in regions.values():
        _loop_and_context(region, lines, cont, student)
    for k in (1, 3, 4):
        regions[k].shared = _shared_name(regions[k], lines)
    return regions


def _region(k, marker, lines, functions, cont) -> Region:
    around = [f for f in functions if f[0] <= marker < f[1]]
    if not around:
        raise RegionError(f"'# TODO {k}' (line {marker + 1}) is not inside a kernel")
    first, last, name = max(around, key=lambda f: f[0])  # the innermost
    indent = MARKER.match(lines[marker])["indent"]
    level = indent_of(lines[marker])
    end = len(lines)
    for j in range(marker + 1, len(lines)):
        text = lines[j].strip()
        if not text or j in cont:
            continue
        if indent_of(lines[j]) < level or MARKER.match(lines[j]) or END_MARKER.match(lines[j]):
            end = j
            break
        if indent_of(lines[j]) == level and _starts_given_code(k, text):
            end = j
            break
    while end > marker + 1 and not lines[end - 1].strip():
        end -= 1
    return Region(k, marker, marker + 1, end, indent, name, (first, last))


def _starts_given_code(k, text) -> bool:
    if text.startswith("#"):
        word = text.lstrip("#").strip().lower()
        return word.startswith(GIVEN_WORDS)
    return any(re.match(rf"{f}\s*\[", text) for f in GIVEN_AFTER.get(k, ()))


def _loop_and_context(region, lines, cont, student) -> None:
    """The innermost enclosing for loop (header, its body's given lines before the TODO) and the given
    ``name = ...`` lines before the TODO at its own level. Lines of TODO regions are never context."""
    level = indent_of(lines[region.marker])
    first = region.kernel_lines[0]
    header = None
    for j in range(region.marker - 1, first, -1):
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
        region.loop_context = _statements(lines, header + 1, region.marker, cont, student)
    block_start = header + 1 if header is not None else _block_start(lines, region.marker, first, level,
                                                                     cont | student)
    region.context = [line for line in _statements(lines, block_start, region.marker, cont, student)
                      if indent_of(line) == level and ASSIGN.match(line) and ASSIGN.match(line)["op"] == "="]


def _block_start(lines, marker, first, level, skip) -> int:
    """First line of the block the TODO line sits in."""
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


def _shared_name(region, lines) -> str:
    """The local variable TODO 1, 3 or 4 hands on to the code after it."""
    first, last = region.kernel_lines
    after = set(IDENT.findall("\n".join(lines[region.end:last])))
    given = [ASSIGN.match(line)["name"] for line in region.context]
    given = [n for n in given if n in after]
    level = indent_of(lines[region.marker])
    assigned = []
    for line in region.code(lines):
        m = ASSIGN.match(line)
        if m and (m["op"] == "+=" or indent_of(line) == level) and m["name"] not in assigned:
            assigned.append(m["name"])
    if given and (given[-1] in assigned or not [n for n in assigned if n in after]):
        return given[-1]
    own = [n for n in assigned if n in after]
    if own:
        return own[0]
    return given[-1] if given else SHARED[region.k]
