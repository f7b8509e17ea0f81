"""Where each TODO's code is in a file of the original handout's format.

A TODO's region starts after its line ``# TODO k: title`` and runs until the
first line (continuation lines of a statement never count) that is

- another ``# TODO j`` line (or an ``# END TODO`` line),
- less indented than the TODO line (the enclosing loop or kernel ends),
- a comment as indented as the TODO line that starts given code: its first word
  begins with one of GIVEN_WORDS ("# Collision force ...", "# computer the torque ...",
  "# update the particles", "# normalize ...") and the code after it does not do
  the TODO's job (JOB: a student's own "# update the velocity" above their TODO 5
  lines is followed by writes of body_velocity, so it stays in the region); other
  comments (hints, the student's own notes) stay in the region,
- for TODOs 1 and 6, a line as indented that writes a field the given code after them
  sets (``body_origin_inverse_inertia[None] = ...``, ``body_rotation[None] = ...``).

Trailing blank lines are left out. The file need not parse (a syntax error in
one TODO costs that TODO only); a TODO whose marker is missing or doubled is
reported in ``problems`` and cannot be graded, the others can. Each region
knows its kernel, the innermost
``for`` loop around it (TODO 2 sits in the given particle loop) and, for TODOs
1, 3 and 4, the local variable it hands on (the inertia, the total force, the
total torque): the one the handout declares before it, or failing that the one
the student's region assigns and later code reads.
"""
import re
from dataclasses import dataclass, field

from .scan import continuation_lines, indent_of

MARKER = re.compile(r"^(?P<indent>[ \t]*)#\s*TODO\s*(?P<k>[1-7])(?![0-9])\s*:?\s*(?P<title>.*)$", re.IGNORECASE)
END_MARKER = re.compile(r"^\s*#\s*END\s+TODO", re.IGNORECASE)
GIVEN_WORDS = ("collision", "comput", "update", "normali", "given", "render", "draw")
GIVEN_AFTER = {1: ("body_origin_inverse_inertia", "body_angular_momentum", "body_velocity"),
               6: ("body_rotation",)}
SHARED = {1: "inertia", 3: "body_force", 4: "body_torque"}  # default names of the locals handed on
JOB = {  # what the code of each TODO does, to tell a student's comment from the given code's
    1: r"outer_product|particle_origin_vertices|particle_vertices",
    2: r"\bgravity\b",
    3: r"particle_force\s*\[",
    4: r"cross",
    5: r"\b(body_cm_position|body_velocity)\s*\[\s*None\s*\]\s*[-+*/]?=(?!=)",
    6: r"\bdt\b",
    7: r"\b(body_angular_momentum|body_angular_velocity)\s*\[\s*None\s*\]\s*[-+*/]?=(?!=)",
}
DEF = re.compile(r"^(?P<indent>[ \t]*)def\s+(?P<name>[A-Za-z_]\w*)\s*\(")
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


def find_regions(text: str) -> tuple:
    """({k: Region} of the TODOs found, {k: why TODO k cannot be located}); RegionError if none is usable."""
    lines = text.splitlines()
    cont = continuation_lines(text)
    functions = _functions(lines, cont)
    markers, problems = {}, {}
    for i, line in enumerate(lines):
        m = MARKER.match(line)  # continuation lines are not skipped: an unclosed bracket must not hide them
        if m:
            k = int(m["k"])
            if k in markers:
                problems[k] = (f"'# TODO {k}' appears twice (lines {markers[k] + 1} and {i + 1}); keep one "
                               f"marker per TODO")
            markers.setdefault(k, i)
    for k in range(1, 8):
        if k not in markers:
            problems[k] = f"no '# TODO {k}:' line; keep the handout's TODO comments"
    regions = {}
    for k, i in markers.items():
        try:
            regions[k] = _region(k, i, lines, functions, cont)
        except RegionError as err:
            problems[k] = str(err)
    regions = {k: r for k, r in regions.items() if k not in problems}
    if not regions:
        raise RegionError(problems[min(problems)])
    student = {j for r in regions.values() for j in range(r.marker, r.end)}
    for region in regions.values():
        _loop_and_context(region, lines, cont, student)
    for k in (1, 3, 4):
        if k in regions:
            regions[k].shared = _shared_name(regions[k], lines)
    return regions, problems


def _functions(lines, cont) -> list:
    """(first line with decorators, last line + 1, name) of every def, from the text (it need not parse)."""
    out = []
    for i, line in enumerate(lines):
        m = DEF.match(line)
        if not m or i in cont:
            continue
        level, first = indent_of(line), i
        while first > 0 and lines[first - 1].strip().startswith("@"):
            first -= 1
        end = i + 1
        for j in range(i + 1, len(lines)):
            text = lines[j].strip()
            if text and not text.startswith("#") and j not in cont and indent_of(lines[j]) <= level:
                break
            if text and not (text.startswith("#") and indent_of(lines[j]) <= level):
                end = j + 1
        out.append((first, end, m["name"]))
    return out


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
        if MARKER.match(lines[j]) or END_MARKER.match(lines[j]):
            end = j
            break
        if not text or j in cont:
            continue
        if indent_of(lines[j]) < level:
            end = j
            break
        if indent_of(lines[j]) == level and _starts_given_code(k, text) and not _does_the_job(k, lines, j, level, cont):
            end = j
            break
    while end > marker + 1 and not lines[end - 1].strip():
        end -= 1
    return Region(k, marker, marker + 1, end, indent, name, (first, last))


def _does_the_job(k, lines, start, level, cont) -> bool:
    """Whether the code after the comment at ``start`` (up to the next comment of its level, TODO line or
    dedent) does TODO k's job: then the comment is the student's own, not the start of given code."""
    code = []
    for j in range(start + 1, len(lines)):
        text = lines[j].strip()
        if not text:
            continue
        if j not in cont and (indent_of(lines[j]) < level or MARKER.match(lines[j])
                              or (text.startswith("#") and indent_of(lines[j]) == level)):
            break
        if not text.startswith("#"):
            code.append(text)
    return bool(re.search(JOB[k], "\n".join(code)))


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
