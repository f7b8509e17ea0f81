"""Which lines of a submission are the handout's given code, and which the student edited.

The course's handout is not part of this project; what is kept is a fingerprint
of each of its given code statements (HASHES: the first 12 hex digits of the SHA-1
of the statement without whitespace, comments, quote style and trailing commas), enough to tell a given
line from an edited one and nothing to read the handout from. ``hashes_of(text)``
makes them from a file in the handout's shape (the test fixture
tests/data/original_handout/unsolved.py; tests/test_grading_original.py checks
that they agree). The 2023 version of the handout differs in two given lines
(the window's title, the box's line width), listed in HASHES_2023.

``edits(text, regions)`` lists the code lines outside the TODO regions that are
not given lines: what the student changed in the given code (friction in the
wall branches, ``substeps = int(1 / 120 // dt)``, ``ti.init(debug=False)``, a
smaller window). The grader keeps them in every version it compares, so they
cost nothing; they are reported as a note. Assignments of the handout's
parameters (``particle_mass = 0.5``, ``file_path = "bunny.obj"``) and of bonus
parameters (BONUS: ``air_drag = 0.02``) are the student's choice and not listed.
"""
import hashlib
import re

from .scan import continuation_lines

PARAMETERS = ("particle_mass", "initial_velocity", "initial_angular_velocity", "gravity", "collision_stiffness",
              "velocity_damping_stiffness", "friction_stiffness", "dt", "file_path", "vertices_np, faces_np")
HASHES = frozenset({
    "0022b28cb137", "017fa3139744", "03c2abbaa056", "0911dbc63412", "0a1c14080465", "0b7913f39f0c", "0e23e01a28d5",
    "10d953770153", "126ac245176c", "142d29f95e15", "14ea6af5542b", "1e708e525ec8", "2064df83fb38", "211b4998f71e",
    "2155048fcb59", "217f93267ae9", "24bf038c8233", "2b8972d1dfd2", "2bf9431b500f", "3114117e0a18", "34008e34d2cc",
    "36829c399ec2", "377b57b4fa9e", "37f1509dc031", "38eb629b1439", "396da81f3c5f", "3fa89bfdd51b", "406cc0046a28",
    "4174bbcada98", "4915158039f3", "4c3385a6ed51", "4ce59595715c", "4f889a2125d3", "52d348346520", "5327a6a5002a",
    "5590088223c3", "5793f452016e", "5834457ea51f", "59e2a393543d", "5b2b8de28ee5", "5e10702f47fd", "5e83f04fa1d9",
    "5fb0e9d1521a", "617df1cf1357", "64682be6f288", "64da1d7c26f3", "64fb6e3e5641", "6880422a3c0c", "69e3dfbea2f6",
    "6a2a979289e3", "6c60f8e47f8e", "6cea8a69e616", "7410be0a19f3", "74f06e68df00", "758d63c87b2b", "76bc083e3d14",
    "77314db3072e", "77330bd41f65", "7836ada968e0", "806d987b53ad", "82c83fe5d631", "84ea2bb0b562", "86ddd0e10cd2",
    "8e4c21e5e74d", "8ef0bae7d5f3", "90e2ddbe4801", "97363bf121a6", "998859fbbdac", "9a2320d7cbd7", "9afc9b5b2ee7",
    "9c7d0616f5b5", "9e600ea55eda", "a4086f23d2de", "a483093b4491", "a5b2a1d15aff", "a803d4bdbe17", "a9581065b226",
    "a963308b9b48", "abf48e32d7cd", "b1b264585d2a", "b421af91cdec", "bbbc1a02cc3c", "bd8272fbe507", "bf0a6ed56c13",
    "c259e9c1c183", "c3cf50197d44", "c59ae414de48", "d306c15bf198", "d37c0ea22ac8", "d409e710ce96", "d5405b002383",
    "d75d0b089cb2", "d82a754e04db", "d85e56f0fe46", "d984f0f4d494", "daea245a4970", "db1055af37f8", "dfb6af2af97a",
    "e2436c310ad9", "e5851a673d31", "e5dd88f02f4a", "e7c57a2346a5", "eaac00f7f96a", "eee0bbba4ff9", "f29d8e34f966",
    "f501f18df786", "f72683ce1b9c", "f7d6cfd7d5d7", "fe49b19eabad",
})
HASHES_2023 = frozenset({
    "8e6ef0beb9c0", "abe385261a7d",
})


def normalise(line: str) -> str:
    """The code of a line without its comment, whitespace and quote style."""
    out, quote = [], None
    for c in line:
        if quote:
            if c == quote:
                quote = None
        elif c in "'\"":
            quote = c
        elif c == "#":
            break
        out.append("'" if c == '"' else c)
    return re.sub(r"\s+", "", "".join(out))


def fingerprint(line: str) -> str:
    """12 hex digits of the SHA-1 of a statement (its lines joined) without whitespace, comments, quote
    style and trailing commas (so a black-formatted file's given code reads as given)."""
    code = re.sub(r",([)\]}])", r"\1", "".join(normalise(part) for part in line.splitlines()))
    return hashlib.sha1(code.encode()).hexdigest()[:12]


def statements(text: str) -> list:
    """(1-based first line, index of that line, the statement's lines joined) of every code statement."""
    lines = text.splitlines()
    cont = continuation_lines(text)
    out = []
    for i, line in enumerate(lines):
        if i in cont and out:
            out[-1][2] += "\n" + line
        elif normalise(line):
            out.append([i + 1, i, line])
    return [tuple(s) for s in out]


def code_lines(text: str, regions: dict) -> list:
    """(1-based line number, statement) of the code statements outside the TODO regions."""
    inside = {j for r in regions.values() for j in range(r.start, r.end)}
    return [(n, statement) for n, i, statement in statements(text) if i not in inside]


def hashes_of(text: str, regions: dict) -> frozenset:
    """The fingerprints of a file's given statements, parameters left out (HASHES, from the fixture)."""
    return frozenset(fingerprint(line) for _, line in code_lines(text, regions) if not _is_parameter(line))


BONUS = re.compile(r"damp|fric|drag|viscos|restitution|resist", re.IGNORECASE)  # names of bonus parameters


def _is_parameter(line: str) -> bool:
    text = line.strip()
    if line[:1].isspace():
        return False
    m = re.match(r"^([A-Za-z_]\w*)\s*=(?!=)", text)
    return bool(m and BONUS.search(m[1])) or any(re.match(rf"^{re.escape(name)}\s*=(?!=)", text)
                                                 for name in PARAMETERS)


def edits(text: str, regions: dict) -> tuple:
    """([(line number, line) of edited or added given code], number of the handout's given lines not found)."""
    known = HASHES | HASHES_2023
    lines = code_lines(text, regions)
    found = {fingerprint(statement) for _, _, statement in statements(text)}
    changed = [(n, line.strip().splitlines()[0]) for n, line in lines
               if fingerprint(line) not in known and not _is_parameter(line)]
    missing = len({h for h in HASHES if h not in found})
    return changed, missing


KERNEL = re.compile(r"^\s*@ti\.(kernel|func)\b")
PHYSICS = re.compile(r"^\s*(substeps|dt|gravity|particle_mass|\w*stiffness\w*)\s*=(?!=)")


def physics_lines(text: str) -> set:
    """1-based numbers of the lines that take part in the simulation: those of @ti.kernel and @ti.func
    functions (until the next line at the decorator's indentation or less), and the module-level
    assignments of the time step, substeps, mass, gravity and stiffnesses."""
    lines, out, level = text.splitlines(), set(), None
    for n, line in enumerate(lines, 1):
        code = line.split("#")[0]
        depth = len(line) - len(line.lstrip())
        if level is not None and code.strip() and depth <= level and not line.lstrip().startswith(("def", "@")):
            level = None
        if KERNEL.match(line):
            level = depth
        if level is not None or PHYSICS.match(line):
            out.add(n)
    return out


def note(text: str, regions: dict, limit: int = 6) -> str:
    """One note on the edits of the given code, or '' when there are none (or the file is not the handout's).
    Edits in the simulation (physics_lines) come first: a sign flipped in the given wall code must not
    hide behind a window's new size."""
    changed, missing = edits(text, regions)
    if not changed and not missing:
        return ""
    if len(HASHES) and missing > len(HASHES) // 2:
        return (f"the code outside the TODOs differs from the handout's in most lines ({missing} of its "
                f"{len(HASHES)} given lines not found); it is kept as it is in every version the grader compares")
    physics = physics_lines(text)
    parts = []
    for label, group in (("in the simulation (they change the physics)", [c for c in changed if c[0] in physics]),
                         ("elsewhere", [c for c in changed if c[0] not in physics])):
        if group:
            left = max(limit - sum(len(p[1]) for p in parts), 1 if not parts else 0)
            shown = "; ".join(f"line {n}: {line[:100]}" for n, line in group[:left])
            more = f"{'; ' if shown else ''}and {len(group) - left} more" if len(group) > left else ""
            parts.append((label, group, f"{label}: {shown}{more}"))
    shown = "; ".join(p[2] for p in parts) if parts else "none added"
    gone = f"; {missing} given line{'s' if missing > 1 else ''} of the handout removed or rewritten" if missing else ""
    return (f"edits of the given code (they cost nothing: the grader runs them in every version it compares): "
            f"{shown}{gone}")
