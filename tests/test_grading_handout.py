"""The handout: made from the solution, no solution line in it or in its answers file, hints kept, runs
headless and sits still; its --check (and the solution's) runs the grader's checks against those answers."""
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import venv_with_our_dependencies, ROOT, SOLUTION
from rigid.errors import UserError
from rigid.grading import answers
from rigid.grading.handout import make_handout, solution_lines


@pytest.fixture(scope="module")
def handout(tmp_path_factory):
    # Into folders that do not exist yet, as the README writes it in a fresh clone.
    out = tmp_path_factory.mktemp("handout") / "handout" / "deeper" / "rigid_body_dynamic.py"
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


def test_answers_file_holds_numbers_only_and_matches_the_repositorys(handout):
    data = handout.with_name(answers.FILE_NAME)
    raw = data.read_bytes()
    assert not any(line.encode() in raw for line in solution_lines(SOLUTION.read_text()))
    with np.load(data, allow_pickle=False) as fresh, np.load(ROOT / answers.FILE_NAME) as kept:
        assert all(np.issubdtype(fresh[key].dtype, np.number) for key in fresh.files)
        assert sorted(fresh.files) == sorted(kept.files) and any(k.startswith("direct/6/") for k in fresh.files)
        stale = [k for k in fresh.files if not np.allclose(fresh[k], kept[k], rtol=1e-9, atol=1e-12)]
    assert not stale, (f"{answers.FILE_NAME} beside the solution is out of date for {stale}: "
                       f"python scripts/make_handout.py --answers-only")


def check(path, cwd):
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONIOENCODING="utf-8")
    return subprocess.run([sys.executable, str(path), "--check"], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)


def test_self_check_of_the_solution_with_the_repositorys_answers():
    proc = check(SOLUTION, ROOT)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert sum(line.startswith("✓ TODO") and "simulation agrees" in line for line in proc.stdout.splitlines()) == 7


def test_self_check_without_current_answers_is_one_line(handout, tmp_path):
    shutil.copy(handout, tmp_path / "rigid_body_dynamic.py")
    proc = check(tmp_path / "rigid_body_dynamic.py", tmp_path)
    assert proc.returncode == 2 and proc.stderr.startswith(f"error: no answers file {answers.FILE_NAME}")
    with np.load(handout.with_name(answers.FILE_NAME)) as data:
        values = {k: data[k] for k in data.files}
    values[answers.FINGERPRINT] = values[answers.FINGERPRINT][::-1].copy()  # made for other inputs
    np.savez(tmp_path / answers.FILE_NAME, **values)
    with pytest.raises(UserError, match="made for other inputs"):
        answers.load(tmp_path / answers.FILE_NAME)
    with pytest.raises(UserError, match="not a readable answers file"):
        (tmp_path / "junk.npz").write_bytes(b"junk")
        answers.load(tmp_path / "junk.npz")


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


def test_make_handout_creates_the_missing_folder(handout):
    assert handout.parent.name == "deeper" and handout.is_file() and handout.with_name(answers.FILE_NAME).is_file()


def test_bundle_runs_check_in_a_fresh_venv(handout, tmp_path):
    """make_handout.py --bundle: unzipped in an empty folder, with a fresh venv (its packages from the
    system's site-packages, none of this repository), the handout's --check runs and fails every TODO, and
    the solution put in its place passes all seven with the bundle's own rigid/. The bundle's handout and
    answers are make_handout.py OUT.py's (the same bytes, the same numbers): this --check is theirs too."""
    import zipfile

    out = tmp_path / "a3.zip"
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "make_handout.py"), "--bundle", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    with zipfile.ZipFile(out) as z:
        names = z.namelist()
        z.extractall(tmp_path / "student")
    assert "a3/rigid_body_dynamic.py" in names and f"a3/{answers.FILE_NAME}" in names
    assert "a3/requirements.txt" in names and "a3/assets/sphere.obj" in names
    assert not any(n.startswith(("a3/rigid/grading/original/", "a3/rigid/bench/")) for n in names)
    python = venv_with_our_dependencies(tmp_path / "venv")
    folder = tmp_path / "student" / "a3"
    env = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": str(tmp_path), "TI_SKIP_VERSION_CHECK": "ON"}
    where = subprocess.run([str(python), "-c", "import rigid; print(rigid.__file__)"], cwd=folder, env=env,
                           capture_output=True, text=True, timeout=60)
    assert where.stdout.strip().startswith(str(folder)), where.stdout + where.stderr  # the bundle's rigid/
    assert (folder / "rigid_body_dynamic.py").read_bytes() == handout.read_bytes()
    with np.load(folder / answers.FILE_NAME) as bundled, np.load(handout.with_name(answers.FILE_NAME)) as beside:
        assert sorted(bundled.files) == sorted(beside.files)
        assert all(np.array_equal(bundled[key], beside[key]) for key in beside.files)
    check = subprocess.run([str(python), "rigid_body_dynamic.py", "--check"], cwd=folder,
                           env=dict(env, PYTHONIOENCODING="utf-8"), capture_output=True, text=True, timeout=300)
    lines = check.stdout.splitlines()
    assert check.returncode == 1, check.stderr
    todo_lines = [line for line in lines if line.startswith(("✓", "✗"))]
    assert [line[:9] for line in todo_lines] == [f"✗ TODO {k}:" for k in range(1, 8)]
    assert all("not done" in line and "placeholder" in line for line in todo_lines)
    assert "0 of 7 TODOs pass" in lines[-1]
    shutil.copy(SOLUTION, folder / "rigid_body_dynamic.py")
    solved = subprocess.run([str(python), "rigid_body_dynamic.py", "--check"], cwd=folder, env=env,
                            capture_output=True, text=True, timeout=300)
    assert solved.returncode == 0 and "All 7 TODOs pass" in solved.stdout, solved.stdout + solved.stderr
