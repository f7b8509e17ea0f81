"""Versions of a submission: some TODO regions replaced, other parameters, extra kernels.

``build(text, regions, student, ...)`` keeps the student's code for the TODOs in
``student`` and puts the reference lines (reference.py) in the other regions;
every line outside the regions (given code, parameters, mesh, bonus code, the
window loop) stays the student's. ``params`` replaces the module-level
assignments of those parameters (``particle_mass = 1`` -> ``particle_mass =
0.7``), ``extra`` is inserted after the last kernel holding a TODO (the
harness kernels), ``renames`` rewrites string literals (a mesh path the
sandbox cannot offer). The result remembers, for each of its lines, the line
of the student's file it came from, so errors name the student's lines.
"""
import ast
from dataclasses import dataclass

from .reference import lines_for

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
        return self.origin[line - 1] if 0 < line <= len(self.origin) else None


def shared_names(regions) -> dict:
    return {k: regions[k].shared for k in (1, 3, 4)}


def build(text: str, regions: dict, student=(), form: str = "position-first", params: dict | None = None,
          extra: list | None = None, renames: dict | None = None) -> Variant:
    lines = text.splitlines(keepends=True)
    lines = [line if line.endswith("\n") else line + "\n" for line in lines]
    splices = []  # (start, end, new lines)
    shared = shared_names(regions)
    for k, region in regions.items():
        if k not in student:
            splices.append((region.start, region.end, lines_for(k, region, shared, form)))
    if params:
        splices += param_splices(text, params)
    if extra:
        at = max(r.kernel_lines[1] for r in regions.values())
        splices.append((at, at, ["\n\n"] + extra))
    out, origin, i = [], [], 0
    for start, end, new in sorted(splices, key=lambda s: (s[0], s[1])):
        if start < i:
            continue  # overlaps an earlier splice (a parameter assigned inside a TODO): keep the first
        out += lines[i:start]
        origin += list(range(i + 1, start + 1))
        for chunk in new:
            parts = chunk.splitlines(keepends=True) or [chunk]
            out += parts
            origin += [None] * len(parts)
        i = end
    out += lines[i:]
    origin += list(range(i + 1, len(lines) + 1))
    text_out = "".join(out)
    for old, new in (renames or {}).items():  # a quoted path, in either quotes
        text_out = text_out.replace(f'"{old}"', f'"{new}"').replace(f"'{old}'", f"'{new}'")
    return Variant(text_out, origin)


def module_values(text: str) -> dict:
    """name -> the source text of its last module-level assignment (the file's parameters)."""
    found = {}
    tree = ast.parse(text)
    for node in tree.body:
        if isinstance(node, ast.Assign) and all(isinstance(t, ast.Name) for t in node.targets):
            for target in node.targets:
                found[target.id] = ast.get_source_segment(text, node.value)
    return found


def perturbed(text: str) -> tuple:
    """(params for param_splices, notes): the perturbed run's values, each different from the file's own."""
    own = module_values(text)
    params, notes = {}, []
    for name, choices in PERTURBED.items():
        if name not in own:
            notes.append(f"the file sets no module-level {name}, so the perturbed run keeps its own value")
            continue
        params[name] = next((c for c in choices if _literal(own[name]) != c), choices[-1])
    return params, notes


def param_splices(text: str, params: dict) -> list:
    """Splices replacing each module-level assignment of a parameter in ``params`` by the new value."""
    lines = text.splitlines()
    splices = []
    for node in ast.parse(text).body:
        if not (isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name)):
            continue
        name = node.targets[0].id
        if name in params:
            old = ast.get_source_segment(text, node.value) or ""
            indent = lines[node.lineno - 1][:node.col_offset]
            splices.append((node.lineno - 1, node.end_lineno, [f"{indent}{name} = {_like(old, params[name])}\n"]))
    return splices


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
    return tuple(float(v) for v in value) if isinstance(value, (list, tuple)) else float(value)


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
