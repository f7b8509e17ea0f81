"""The student's lines of a TODO region that stay when the grader puts its reference lines there.

A region holds the TODO's own work and sometimes a line the rest of the file needs: a student's
``is_in_contact = False`` under ``# TODO 2``, read by the given collision code after it; TODO 6's
``w = body_angular_velocity[None]`` written under ``# TODO 5``. Swapping the whole region out would
make the file fail (a name not defined) where the student's own file runs. ``kept(...)`` returns the
region's top-level simple assignments of locals (``name = ...``, ``a, b = ...``) that code after the region in the
same kernel reads, with the assignments they read in turn, split into those before the region's
first other statement and those after it (the replacement goes between, so each keeps its order).
The TODO's result itself is never kept: augmented assignments, writes of fields, the local the TODO
hands on (``inertia``, ``body_force``, ``body_torque``) and the loop variable are not simple locals here.
"""
import re

from .scan import indent_of

SIMPLE = re.compile(r"^\s*(?P<names>[A-Za-z_]\w*(\s*,\s*[A-Za-z_]\w*)*)\s*(:[^=]+)?=(?!=)(?P<value>.*)$", re.DOTALL)
IDENT = re.compile(r"(?<![.\w])[A-Za-z_]\w*")


def _statements(region, lines, cont) -> list:
    """[(first, end, text)] of the region's statements at its own level (with their nested lines)."""
    out = []
    for j in range(region.start, region.end):
        text = lines[j].strip()
        if not text or text.startswith("#"):
            continue
        if j not in cont and indent_of(lines[j]) <= region.level:
            out.append([j, j + 1, lines[j]])
        elif out:
            out[-1][1] = j + 1
            out[-1][2] += "\n" + lines[j]
    return [tuple(s) for s in out]


def _code(text: str) -> str:
    return "\n".join(line.split("#")[0] for line in text.splitlines())


def kept(region, lines, cont) -> tuple:
    """([lines kept before the replacement], [lines kept after it]), each line ending in a newline."""
    statements = _statements(region, lines, cont)
    after = set(IDENT.findall(_code("\n".join(lines[region.end:region.kernel_lines[1]]))))
    off_limits = {region.shared, region.loop_var}
    needed, keep = set(after), set()
    for i in range(len(statements) - 1, -1, -1):
        m = SIMPLE.match(statements[i][2])  # never a compound statement: "for ...:" or "if ...:" do not match
        names = set(re.split(r"\s*,\s*", m["names"].strip())) if m else set()
        if names & needed and not names & off_limits:
            keep.add(i)
            needed |= set(IDENT.findall(_code(m["value"])))
    if not keep:
        return [], []
    first_other = next((i for i in range(len(statements)) if i not in keep), len(statements))
    before, later = [], []
    for i in sorted(keep):
        first, end, _ = statements[i]
        (before if i < first_other else later).extend(line + "\n" for line in lines[first:end])
    return before, later
