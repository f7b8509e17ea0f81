"""Versions of a submission: some TODO regions replaced, other parameters, extra kernels.

``FileModel(text, renames)`` reads the TODO regions (regions.py) and the
module-level assignments. These come from the version with reference lines in
every region, so a syntax error inside one TODO does not stop the others from
being graded; one outside the TODOs raises RegionError. ``build(student, ...)``
keeps the student's code for the TODOs in ``student`` and puts the reference
lines (reference.py) in the other regions, with the student's lines there that
the rest of the file reads (keep.py); every line outside the regions
(given code, parameters, mesh, bonus code, the window loop) stays the
student's. ``params`` replaces the module-level assignments of those parameters
(``particle_mass = 1`` -> ``particle_mass = 0.7``), ``extra`` is inserted after
the last kernel holding a TODO (the harness kernels), and the file's quoted
paths in ``renames`` are rewritten (a mesh path the sandbox cannot offer).

Bonus terms (the policy): the TODOs are graded with the file's bonus
parameters set to zero, as the slides' model has no damping or friction:
every module-level number whose name reads as one (given.BONUS: damping,
friction, drag, ...; the handout declares ``velocity_damping_stiffness`` and
``friction_stiffness`` and never uses them) and that the file's code reads
is 0 in every version built (``bonus`` lists them), so a damping term inside
TODO 2 or 5, or added to ``body_force`` after TODO 4's loop, costs no TODO.
``build(..., keep_bonus=True)`` keeps the file's values, for the note on what
the bonus terms did. A bonus term written with a bare number
(``body_velocity[None] *= 0.99``) cannot be told from the TODO's physics and
is graded with it. A version remembers, for each of its lines, the line of the student's file it
came from, so errors name the student's lines.
"""
import ast
import re
from dataclasses import dataclass

from .given import BONUS
from .keep import kept
from .reference import lines_for
from .regions import RegionError, find_regions_with_notes
from .scan import continuation_lines

PERTURBED = {  # other parameters than the handout's: a missing mass factor or Δt cannot hide, and it spins
    "particle_mass": (0.7, 1.3),  # the first that differs from the file's own value
    "dt": (8e-4, 6e-4),
    "initial_velocity": ((2.5, 0.0, 1.5),),  # reaches the wall x = 1 and the floor within half a second
    "initial_angular_velocity": ((4.0, -3.0, 6.0),),
}


@dataclass
class Variant:
    text: str
    origin: list  # for each line of text: the 1-based line of the student's file, or None (grader's line)

    def student_line(self, line: int):
        """The student's line number for line ``line`` (1-based) of this variant, or None."""
        return self.origin[line - 1] if line and 0 < line <= len(self.origin) else None


class FileModel:
    def __init__(self, text: str, renames: dict | None = None):
        self.text, self.renames = text, renames or {}
        self.lines = [line if line.endswith("\n") else line + "\n" for line in text.splitlines(keepends=True)]
        self.regions, self.problems, self.notes = find_regions_with_notes(text)
        self.shared = {k: self.regions[k].shared if k in self.regions else None for k in (1, 3, 4)}
        cont = continuation_lines(text)
        self.kept = {k: kept(r, text.splitlines(), cont) for k, r in self.regions.items()}
        reference = self.build()
        try:
            tree = ast.parse(reference.text)
        except SyntaxError as err:
            raise RegionError(f"the file has a syntax error at line {reference.student_line(err.lineno)} "
                              f"(outside the TODOs): {err.msg}")
        self.reference_text = reference.text
        self.assignments = {}  # name -> (first line index, end index, indent, source of the value)
        for node in tree.body:
            if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
                first, last = reference.student_line(node.lineno), reference.student_line(node.end_lineno)
                if first and last:
                    indent = self.lines[first - 1][:node.col_offset]
                    self.assignments[node.targets[0].id] = (first - 1, last, indent,
                                                            ast.get_source_segment(reference.text, node.value))
        code = "\n".join(line.split("#")[0] for line in text.splitlines())  # the student's TODOs too
        read = {name for name in self.assignments if len(re.findall(rf"(?<![.\w]){name}\b", code)) > 1}
        self.bonus = {name: value for name, a in self.assignments.items()
                      if BONUS.search(name) and name in read and (value := _literal(a[3])) not in (None, 0.0)
                      and isinstance(value, float)}

    def build(self, student=(), form: str = "position-first", params: dict | None = None,
              extra: list | None = None, keep_bonus: bool = False) -> Variant:
        if not keep_bonus and getattr(self, "bonus", None):
            params = {**{name: 0.0 for name in self.bonus}, **(params or {})}
        splices = []  # (start, end, new lines)
        for k, region in self.regions.items():
            if k not in student:  # the student's lines the rest of the file reads stay (keep.py)
                before, after = self.kept[k]
                splices.append((region.start, region.end, before + lines_for(k, region, self.shared, form) + after))
        for name, value in (params or {}).items():
            if name in self.assignments:
                first, end, indent, old = self.assignments[name]
                splices.append((first, end, [f"{indent}{name} = {_like(old, value)}\n"]))
        if extra:
            at = max(r.kernel_lines[1] for r in self.regions.values())
            splices.append((at, at, ["\n\n"] + extra))
        out, origin, i = [], [], 0
        for start, end, new in sorted(splices, key=lambda s: (s[0], s[1])):
            out += self.lines[i:start]
            origin += list(range(i + 1, start + 1))
            for chunk in new:
                parts = chunk.splitlines(keepends=True) or [chunk]
                out += parts
                origin += [None] * len(parts)
            i = end
        out += self.lines[i:]
        origin += list(range(i + 1, len(self.lines) + 1))
        text = "".join(out)
        for old, new in self.renames.items():  # a quoted path, in either quotes
            text = text.replace(f'"{old}"', f'"{new}"').replace(f"'{old}'", f"'{new}'")
        return Variant(text, origin)

    def values(self) -> dict:
        """name -> the source text of the value of its module-level assignment (the file's parameters)."""
        return {name: a[3] for name, a in self.assignments.items()}

    def perturbed(self) -> tuple:
        """(params for build, notes): the perturbed run's values, each different from the file's own."""
        params, notes = {}, []
        for name, choices in PERTURBED.items():
            if name not in self.assignments:
                notes.append(f"the file sets no module-level {name}, so the perturbed run keeps its own value")
                continue
            own = _literal(self.assignments[name][3])
            params[name] = next((c for c in choices if own != c), choices[-1])
        return params, notes


def _literal(source):
    """The value of a parameter's source text if it is plain numbers ('1', 'ti.Vector([0.0, 1, 0])'), else None."""
    try:
        node = ast.parse(source, mode="eval").body
    except (SyntaxError, ValueError, TypeError):
        return None
    if isinstance(node, ast.Call) and len(node.args) == 1:
        node = node.args[0]
    try:
        value = ast.literal_eval(node)
    except ValueError:
        return None
    if isinstance(value, (list, tuple)):
        return tuple(float(v) for v in value)
    return float(value) if isinstance(value, (int, float)) else None


def _like(old: str, value) -> str:
    """``value`` written the way the file wrote the old one (ti.Vector, ti.math.vec3, np.array, list, tuple)."""
    if not isinstance(value, tuple):
        return repr(value)
    numbers = ", ".join(repr(float(v)) for v in value)
    head = old.split("(")[0].strip() if "(" in old and not old.lstrip().startswith("(") else ""
    if head.endswith(("Vector", "array", "asarray")):
        return f"{head}([{numbers}])"
    if head.endswith(("vec3", "Vector3")):
        return f"{head}({numbers})"
    return f"[{numbers}]" if old.lstrip().startswith("[") else f"({numbers})"
