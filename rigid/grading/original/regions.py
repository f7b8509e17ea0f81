"""Where each TODO's code is in a file of the original handout's format.

A TODO's marker is a comment line ``# TODO k: title`` in any reasonable spelling
(``#TODO 1``, ``# todo 1:``, ``# TODO: 1: Compute ...``, ``# TODO #1``,
``## TODO(1)``), at any indentation. Its region starts after the marker and
runs until the first line (continuation lines of a statement never count) that is

- another TODO marker (or an ``# END TODO`` line),
- a code line less indented than the marker (the enclosing loop or kernel ends);
  comments never end a region by their indentation (a comment at 3 spaces inside
  a 4-space block stays in),
- a comment no more indented than the marker that starts given code: its first word
  begins with one of GIVEN_WORDS ("# Collision force ...", "# computer the torque ...",
  "# update the particles", "# normalize ...") and the code after it does not do
  the TODO's job (JOB: a student's own "# update the velocity" above their TODO 5
  lines is followed by writes of body_velocity, so it stays in the region); other
  comments (hints, the student's own notes) stay in the region,
- a code line no more indented than the marker that is given code after this TODO
  in the handout (ANCHORS: ``body_origin_inverse_inertia[None] = ...`` after TODO 1,
  the collision ``if particle_vertices[i][1] < -1:`` after TODO 2, the declaration
  of a later TODO's local ``body_torque = ...``, the quaternion's normalisation after
  TODO 6's own update, the particle loop after TODO 7), or that does the job of a
  later TODO whose marker is missing.

Trailing blank and comment lines are left out. The file need not parse (a syntax
error in one TODO costs that TODO only); a TODO whose marker is missing (the
message names the line expected, EXPECTED) or ambiguous is reported in
``problems`` and cannot be graded, the others can. Each region knows its kernel,
the innermost ``for`` loop around it (TODO 2 sits in the given particle loop; in
the handout TODOs 3 and 4 sit in loops too) and, for TODOs 1, 3 and 4, the local
variable it hands on (the inertia, the total force, the total torque): the one the
given code declares before it (before its loop, as the handout does for
``body_force`` and ``body_torque``), or failing that the one the student's region
assigns and later code reads. The tables named in capitals are in handout_shape.py.
"""
import re
from dataclasses import dataclass, field

from .align import virtual_markers
from .context import loop_and_context, shared_name
from .handout_shape import ANCHORS, END_MARKER, EXPECTED, GIVEN_WORDS, JOB, MARKER, NORMALISE, TITLES, WRITES
from .scan import continuation_lines, indent_of

DEF = re.compile(r"^(?P<indent>[ \t]*)def\s+(?P<name>[A-Za-z_]\w*)\s*\(")


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
    outer: list = field(default_factory=list)  # given 'name = ...' lines before its loop, at the loop's level
    shared: str | None = None  # TODOs 1, 3, 4: the local handed on
    marker_text: str = ""  # the marker line as the student wrote it ("" when found by align.py)

    @property
    def level(self) -> int:
        return indent_of(self.indent)

    def where(self) -> str:
        """Its lines, for a message: 'lines 98-101', or 'empty, at line 147'."""
        return f"lines {self.start + 1}-{self.end}" if self.end > self.start else f"empty, at line {self.start + 1}"

    def code(self, lines) -> list:
        return lines[self.start:self.end]

    def has_code(self, lines) -> bool:
        return any(line.strip() and not line.strip().startswith("#") for line in self.code(lines))


class RegionError(Exception):
    """The file's TODO markers cannot be read; the message is for the student."""


def _title_score(k: int, title: str) -> int:
    words = set(re.findall(r"[a-z]+", TITLES[k].lower()))
    return len(words & set(re.findall(r"[a-z]+", title.lower())))


def find_markers(lines) -> tuple:
    """({k: line index of its marker}, {k: why it cannot be used}, [notes])."""
    found = {}
    for i, line in enumerate(lines):
        m = MARKER.match(line)  # continuation lines are not skipped: an unclosed bracket must not hide them
        if m:
            found.setdefault(int(m["k"]), []).append((i, m["title"]))
    markers, problems, notes = {}, {}, []
    for k, candidates in found.items():
        if len(candidates) == 1:
            markers[k] = candidates[0][0]
            continue
        scores = [_title_score(k, title) for _, title in candidates]
        best = max(scores)
        if scores.count(best) > 1:
            where = " and ".join(str(i + 1) for i, _ in candidates)
            problems[k] = f"'# TODO {k}' appears {len(candidates)} times (lines {where}); keep one marker per TODO"
            continue
        markers[k] = candidates[scores.index(best)][0]
        others = ", ".join(str(i + 1) for i, _ in candidates if i != markers[k])
        notes.append(f"TODO {k}: the marker at line {markers[k] + 1} was used (its title matches the handout's); "
                     f"the comment at line {others} also reads as a TODO {k} marker")
    for k in range(1, 8):
        if k not in markers and k not in problems:
            problems[k] = (f"no '# TODO {k}:' line; expected '# TODO {k}: {TITLES[k]}' {EXPECTED[k]} "
                           f"(keep the handout's TODO comments)")
    return markers, problems, notes


def find_regions(text: str) -> tuple:
    """({k: Region} of the TODOs found, {k: why TODO k cannot be located}); RegionError if none is usable."""
    regions, problems, _notes = find_regions_with_notes(text)
    return regions, problems


def find_regions_with_notes(text: str) -> tuple:
    lines = text.splitlines()
    cont = continuation_lines(text)
    functions = _functions(lines, cont)
    markers, problems, notes = find_markers(lines)
    regions = {}
    for k, i in markers.items():
        try:
            regions[k] = _region(k, i, lines, functions, cont, set(markers))
        except RegionError as err:
            problems[k] = str(err)
    lost = [k for k in problems if k not in markers and problems[k].startswith("no '# TODO")]
    placed = []
    for k, (i, indent, limit) in virtual_markers(lines, cont, functions, lost).items():
        try:
            regions[k] = _region(k, i, lines, functions, cont, set(markers), indent, limit)
        except RegionError:
            continue
        del problems[k]
        placed.append(k)
    if placed:
        ks = ", ".join(map(str, sorted(placed)))
        notes.append(f"TODO comments missing (TODO{'s' if len(placed) > 1 else ''} {ks}): found by "
                     f"{'their' if len(placed) > 1 else 'its'} place among the handout's given code ("
                     + "; ".join(f"TODO {k}: {regions[k].where()}" for k in sorted(placed)) + ")")
    regions = {k: r for k, r in regions.items() if k not in problems}
    if not regions:
        raise RegionError(problems[min(problems)])
    _no_overlap(regions, lines)
    student = {j for r in regions.values() for j in range(r.start, r.end)}
    for region in regions.values():
        loop_and_context(region, lines, cont, student)
    for k in (1, 3, 4):
        if k in regions:
            regions[k].shared = shared_name(regions[k], lines)
    return regions, problems, sorted(notes)


def _no_overlap(regions, lines) -> None:
    """A region ends where the next one (in the file) starts: a TODO found by its place (align.py) may
    begin inside the span regions.py gave the one before it."""
    ordered = sorted(regions.values(), key=lambda r: r.start)
    for region, after in zip(ordered, ordered[1:]):
        if region.end > after.start:
            region.end = max(region.start, after.start if after.marker_text == "" else after.marker)
            while region.end > region.start and (not lines[region.end - 1].strip()
                                                 or lines[region.end - 1].strip().startswith("#")):
                region.end -= 1


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


def _region(k, marker, lines, functions, cont, present, indent=None, limit=None) -> Region:
    """TODO k's region after line ``marker`` (its comment, or with ``indent`` the line before the code
    align.py placed, which ends by the line ``limit``)."""
    around = [f for f in functions if f[0] <= marker + (indent is not None) < f[1]]
    if not around:
        raise RegionError(f"'# TODO {k}' (line {marker + 1}) is not inside a kernel; expected it {EXPECTED[k]}")
    first, last, name = max(around, key=lambda f: f[0])  # the innermost
    text = indent if indent is not None else MARKER.match(lines[marker])["indent"]
    level = indent_of(text)
    later_missing = [WRITES[j] for j in WRITES if j > k and j not in present]
    end, updated = limit or len(lines), False
    for j in range(marker + 1, end):
        text = lines[j].strip()
        if MARKER.match(lines[j]) or END_MARKER.match(lines[j]):
            end = j
            break
        if not text or j in cont:
            continue
        if text.startswith("#"):
            if (indent_of(lines[j]) <= level and _starts_given_code(text)
                    and not _does_the_job(k, lines, j, level, cont)):
                end = j
                break
            continue
        if indent_of(lines[j]) < level:
            end = j
            break
        if indent_of(lines[j]) == level and (
                (k in ANCHORS and ANCHORS[k].match(text)) or any(w.match(text) for w in later_missing)
                or (k == 6 and updated and NORMALISE.match(text))):
            end = j
            break
        updated = updated or bool(k == 6 and WRITES[6].match(text))
    while end > marker + 1 and (not lines[end - 1].strip() or lines[end - 1].strip().startswith("#")):
        end -= 1
    code = [lines[j] for j in range(marker + 1, end) if j not in cont and lines[j].strip()
            and not lines[j].strip().startswith("#") and indent_of(lines[j]) == level]
    if code or (end < len(lines) and indent_of(lines[end]) == level and lines[end].strip()):
        line = code[0] if code else lines[end]  # the code's own indentation (tabs where the comment has spaces)
        text = line[:len(line) - len(line.lstrip())]
    return Region(k, marker, marker + 1, end, text, name, (first, last),
                  marker_text=lines[marker].strip() if indent is None else "")


def _does_the_job(k, lines, start, level, cont) -> bool:
    """Whether the code after the comment at ``start`` (up to the next comment of its level, TODO line or
    dedent) does TODO k's job: then the comment is the student's own, not the start of given code."""
    code = []
    for j in range(start + 1, len(lines)):
        text = lines[j].strip()
        if not text:
            continue
        if MARKER.match(lines[j]) or (j not in cont and not text.startswith("#") and indent_of(lines[j]) < level):
            break
        if text.startswith("#"):
            if indent_of(lines[j]) <= level and _starts_given_code(text):
                break
            continue
        code.append(text)
    return bool(re.search(JOB[k], "\n".join(code)))


def _starts_given_code(text) -> bool:
    word = text.lstrip("#").strip().lower()
    return word.startswith(GIVEN_WORDS)
