"""Walk the bad-input table of docs/bad-input.md: each row gives one line on stderr and exit code 2."""
import re
import shlex

import pytest

from conftest import ROOT, run_cli


def table_rows():
    text = (ROOT / "docs" / "bad-input.md").read_text()
    table = text.split("<!-- bad-input-table")[1].split("<!-- end bad-input-table")[0]
    rows = re.findall(r"^\| ([^|]+) \| `([^`]+)` \| `([^`]+)` \|$", table, re.M)
    assert len(rows) >= 20, "docs/bad-input.md's table lost its rows"
    return rows


@pytest.mark.parametrize("problem, args, message", table_rows(), ids=[r[0] for r in table_rows()])
def test_bad_input_row(problem, args, message, capsys, monkeypatch):
    from rigid.cli import main

    monkeypatch.chdir(ROOT)
    try:
        code = main(["--headless", *shlex.split(args)])
    except SystemExit as stop:  # argparse's own errors exit from inside main
        code = stop.code
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert err.startswith(message), err
    assert len(err.splitlines()) == 1, err


def test_real_process_exit_code_and_no_traceback(tmp_path):
    proc = run_cli("--headless", "--mesh", "tests/data/line.obj", "--export", tmp_path / "t.npz")
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and proc.stderr.strip().startswith("error: all 4 particles")
    assert not (tmp_path / "t.npz").exists()
