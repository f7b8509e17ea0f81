"""The house rules, checked on the source: dependencies point one way, files stay small.

Layers (README, "Layout"): the base modules (config, errors, runtime) <- bodies <- engine <- run
<- view; science, grading, bench and report sit above them; the CLI and the Python API on top. Nothing in rigid/
imports scripts/.
"""
import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
RIGID = ROOT / "rigid"
BASE = {"config", "errors", "runtime"}
# What each group may import from rigid (besides itself).
ALLOWED = {
    "errors": set(),
    "config": {"errors"},
    "runtime": {"errors", "config"},
    "bodies": {"errors", "config"},
    "engine": BASE | {"bodies"},
    "run": BASE | {"bodies", "engine"},
    "view": BASE | {"bodies", "engine", "run"},
    "science": BASE | {"bodies", "engine", "run"},
    "grading": BASE | {"bodies", "engine", "run"},
    "bench": BASE | {"bodies", "engine", "run", "view", "science", "grading"},
    "report": BASE | {"bodies", "engine", "run", "view", "science", "bench"},
    "sweeps": BASE | {"bodies", "engine", "run", "view"},  # many runs: workers simulate (and record)
    "cli": BASE | {"bodies", "engine", "run", "view", "sweeps"},
    "api": BASE | {"bodies", "engine", "run", "view", "sweeps"},  # the Python API: build, step, read, export, show (view, lazily)
    "__main__": {"cli"},
    "diff": BASE | {"bodies", "engine"},  # gradients and fitting (rigid.gradient, rigid.fit)
    "__init__": {"api", "diff"},  # loaded on first use of rigid.Simulator etc. (PEP 562)
}
MAX_LINES = 300


def group_of(path: Path) -> str:
    parts = path.relative_to(RIGID).with_suffix("").parts
    return parts[0]


def rigid_imports(path: Path, root: Path = RIGID):
    """(line, imported group) for every import of a rigid module in the file."""
    package = ["rigid", *path.relative_to(root).parts[:-1]]
    for node in ast.walk(ast.parse(path.read_text())):
        names = []
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - node.level + 1]
                module = base + (node.module.split(".") if node.module else [])
                names = [module + [a.name] for a in node.names] if node.module is None else [module]
            elif node.module:
                names = [node.module.split(".")]
        elif isinstance(node, ast.Import):
            names = [a.name.split(".") for a in node.names]
        for name in names:
            if name[0] in ("scripts",) or name[0].startswith(("bench_", "report_", "make_")):
                yield node.lineno, "scripts"
            elif name[0] == "rigid" and len(name) >= 2:
                yield node.lineno, name[1]


SOURCES = sorted(RIGID.rglob("*.py"))


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_dependencies_point_one_way(path):
    group = group_of(path)
    assert group in ALLOWED, f"{path}: a new top-level module or package; add it to the layout"
    for line, imported in rigid_imports(path):
        if imported == group:
            continue
        assert imported in ALLOWED[group], (f"{path.relative_to(ROOT)}:{line} imports rigid.{imported}, "
                                            f"which {group} may not (allowed: {sorted(ALLOWED[group])})")


def test_the_rule_catches_a_violation(tmp_path):
    """The checker itself: an engine module importing the view is reported."""
    fake = tmp_path / "rigid" / "engine" / "probe.py"
    fake.parent.mkdir(parents=True)
    fake.write_text("from ..view.render import SceneRenderer\nfrom . import model\nimport bench_table\n")
    found = list(rigid_imports(fake, tmp_path / "rigid"))
    assert found == [(1, "view"), (2, "engine"), (3, "scripts")]
    assert "view" not in ALLOWED["engine"]


def test_every_subpackage_says_what_it_holds():
    for init in RIGID.glob("*/__init__.py"):
        doc = ast.get_docstring(ast.parse(init.read_text()))
        assert doc and "import" in doc, f"{init}: say what lives here and what it may import"


def test_no_top_level_module_belongs_to_a_group():
    top = {p.stem for p in RIGID.glob("*.py")}
    assert top == {"__init__", "__main__", "api", "cli", "config", "errors", "runtime"}


@pytest.mark.parametrize("folder", ["rigid", "scripts"])
def test_files_stay_small(folder):
    big = {str(p.relative_to(ROOT)): n for p in (ROOT / folder).rglob("*.py")
           if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert not big, f"files over {MAX_LINES} lines: {big}"


def test_scripts_are_thin():
    fat = {p.name: n for p in (ROOT / "scripts").glob("*.py") if (n := len(p.read_text().splitlines())) >= 100}
    assert not fat, f"scripts should parse arguments and call the package: {fat}"
