"""The handout: made from the solution, no solution line in it, hints kept, runs headless and sits still."""
import os
import subprocess
import sys

import pytest

from conftest import ROOT, SOLUTION
from rigid.errors import UserError
from rigid.grading.handout import make_handout, solution_lines


@pytest.fixture(scope="module")
def handout(tmp_path_factory):
    out = tmp_path_factory.mktemp("handout") / "rigid_body_dynamic.py"
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "make_handout.py"), str(out)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    return out


def test_no_solution_line_and_every_hint_kept(handout):
    solution, text = SOLUTION.read_text(), handout.read_text()
    shown = {line.strip() for line in text.splitlines()}
    code = solution_lines(solution)
    assert len(code) >= 12  # the 7 TODOs hold at least this many code lines
    assert not code & shown
    hints = [line for line in solution.splitlines() if line.strip().startswith("# Hint")]
    assert len(hints) >= 7 and all(h in text.splitlines() for h in hints)
    for k in range(1, 8):
        assert f"# TODO {k}:" in text and f"# END TODO {k}" in text
    # Outside the TODO blocks nothing changes.
    outside = lambda t: [ln for ln in t.splitlines() if not ln.startswith("    ")]  # noqa: E731
    assert outside(text) == outside(solution)


def test_runs_headless_and_sits_still(handout):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, str(handout), "--headless", "--frames", "20"],
                          cwd=handout.parent, env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "x = [0.0, 0.0, 0.0]" in proc.stdout  # no gravity force, no motion: TODOs 2, 5 are placeholders
    assert "singular" in proc.stderr  # TODO 1's zero inertia is reported, not a crash


def test_bad_markers_are_one_line_errors():
    solution = SOLUTION.read_text()
    with pytest.raises(UserError, match="TODO 4 starts inside TODO 3"):
        make_handout(solution.replace("# END TODO 3", "# the end"))
    with pytest.raises(UserError, match="TODO 7 has no"):
        make_handout(solution.replace("# END TODO 7", "# the end"))
    with pytest.raises(UserError, match="no '# TODO 6:'"):
        make_handout(solution.replace("# TODO 6:", "# TO DO 6:").replace("# END TODO 6", ""))
