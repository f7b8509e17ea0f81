"""Which handout a submission was written for: this project's, or the course's original one.

"project": the 7 TODO units as functions (``def particle_inertia(...)`` ...),
or ``# END TODO`` markers. "original": a module-level script with kernel
``substep()`` and the handout's global fields (``body_cm_position``). Anything
else is graded as "project", whose messages then say which function is missing.
"""
import re

from ...engine.units import UNIT_NAMES

FORMATS = ("project", "original")


def detect(text: str) -> str:
    if any(re.search(rf"^\s*def\s+{name}\s*\(", text, re.MULTILINE) for name in UNIT_NAMES):
        return "project"
    if re.search(r"#\s*END\s+TODO", text, re.IGNORECASE):
        return "project"
    if re.search(r"^\s*def\s+substep\s*\(", text, re.MULTILINE) and "body_cm_position" in text:
        return "original"
    return "project"
