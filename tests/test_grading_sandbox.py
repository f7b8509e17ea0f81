"""Hostile submissions in the grader's bubblewrap box (rigid/grading/box.py), as the TA's grade.py runs them.

One batch (--jobs 2, --require-sandbox) of two files, each the right solution, so each must score full
marks whatever else it does: a sibling whose file holds a secret, and a hostile file graded beside it that
tries everything at once: it reads the sibling's file and writes the stolen text into the TA's home and
into the grades' folder, opens a TCP connection to a server this test listens on, runs ``os.system`` to
write a file beside the test, forks until refused, and leaves a ``sleep`` behind. Every attempt must fail
(nothing written, nothing read, no connection, no process left) and be noted in its feedback (seven kinds
of note, within the child's limit of eight: rigid.grading.attempts.LIMIT). CI runs the suite as root:
there the child drops to a uid of its own. Without bwrap: the loud warning once, and --require-sandbox
refuses with one line.
"""
import json
import os
import socket
import subprocess
import sys
import threading
import uuid
from pathlib import Path

import pytest

from conftest import ROOT, SOLUTION

from rigid.grading.box import find_box

BOX, WHY = find_box()  # bwrap installed and able to start a box here (scripts/setup.sh installs it)
needs_bwrap = pytest.mark.skipif(BOX is None, reason=f"no sandbox: {WHY}")
SECRET = "SECRET-" + uuid.uuid4().hex[:8]
SLEEP = 987654 + os.getpid() % 1000  # the argument of the sleep left behind, to find it in ps


def hostile_code(sibling: Path, home_target: Path, out_target: Path, port: int, marker: Path) -> str:
    return SOLUTION.read_text() + f"""

import pathlib as _p
_stolen = ""
try:
    _stolen = _p.Path({str(sibling)!r}).read_text()
except Exception:
    pass
print("STOLEN:" + _stolen)
for _target in ({str(home_target)!r}, {str(out_target)!r}):
    try:
        _p.Path(_target).write_text("pwned " + _stolen)
    except Exception:
        pass

import os as _os, socket as _socket, signal as _signal
try:
    _socket.create_connection(("127.0.0.1", {port}), timeout=2).sendall(b"hello")
except Exception:
    pass
_os.system("echo pwned > {marker}")
_kids = []
try:
    for _ in range(2000):
        _pid = _os.fork()
        if _pid == 0:
            _signal.pause()
        _kids.append(_pid)
except OSError:
    pass
print("FORKS:", len(_kids))
for _pid in _kids:
    _os.kill(_pid, _signal.SIGKILL)
    _os.waitpid(_pid, 0)
if _os.fork() == 0:
    _os.execv("/bin/sleep", ["sleep", "{SLEEP}"])
"""


@pytest.fixture(scope="module")
def hostile(tmp_path_factory):
    base = tmp_path_factory.mktemp("hostile")
    subs, out = base / "subs", base / "out"
    subs.mkdir()
    out.mkdir()
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()
    server.settimeout(0.5)
    reached = []

    def accept():
        while not reached and server.fileno() >= 0:
            try:
                reached.append(server.accept())
            except OSError:
                continue

    threading.Thread(target=accept, daemon=True).start()
    targets = dict(home=Path.home() / f"grader_pwned_{uuid.uuid4().hex[:8]}.txt", out=out / "pwned.txt",
                   marker=base / "os_system_marker.txt")
    (subs / "sibling.py").write_text(SOLUTION.read_text() + f"\n# {SECRET}\n")
    (subs / "hostile.py").write_text(hostile_code(subs / "sibling.py", targets["home"], targets["out"],
                                                  server.getsockname()[1], targets["marker"]))
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "grade.py"), str(subs), "--jobs", "2",
                           "--require-sandbox", "--json", str(out / "grades.json")],
                          capture_output=True, text=True, timeout=600)
    server.close()
    assert proc.returncode == 0, proc.stderr
    results = {Path(r["submission"]).stem: r for r in json.loads((out / "grades.json").read_text())}
    left = []  # the command lines of the processes still running
    for cmdline in Path("/proc").glob("[0-9]*/cmdline"):
        try:
            left.append(cmdline.read_bytes().replace(b"\0", b" ").decode(errors="replace"))
        except OSError:
            pass
    return dict(results=results, targets=targets, reached=reached, out=out, stderr=proc.stderr, ps=left)


@needs_bwrap
def test_every_file_scores_full_marks_and_the_sibling_is_untouched(hostile):
    assert {n: r["total"] for n, r in hostile["results"].items()} == {"sibling": 90, "hostile": 90}
    assert hostile["results"]["sibling"]["notes"] == []
    assert "NOT contained" not in hostile["stderr"]


@needs_bwrap
def test_files_outside_the_box_can_be_neither_read_nor_written(hostile):
    r = hostile["results"]["hostile"]
    assert "STOLEN:\n" in r["output"] and SECRET not in r["output"]
    assert not hostile["targets"]["home"].exists() and not hostile["targets"]["out"].exists()
    assert sorted(p.name for p in hostile["out"].iterdir()) == ["grades.json", "grades.summary.txt"]
    notes = "\n".join(r["notes"])
    assert f"tried to read {hostile['results']['sibling']['submission']}" in notes
    assert f"tried to write {hostile['targets']['home']}" in notes and f"tried to write {hostile['targets']['out']}" in notes


@needs_bwrap
def test_no_network_no_command_outside_a_bounded_number_of_processes_none_left(hostile):
    r = hostile["results"]["hostile"]
    assert hostile["reached"] == [] and not hostile["targets"]["marker"].exists()
    forks = int(r["output"].split("FORKS:")[1].split()[0])
    assert 0 < forks < 256  # the box's process limit (rigid.grading.child.PROCESSES), Taichi's threads included
    assert not any(f"sleep {SLEEP}" in line for line in hostile["ps"])  # what it left behind died with its box
    notes = "\n".join(r["notes"])
    for words in ("network connection to 127.0.0.1", "os.system: 'echo pwned", "forked a process",
                  f"started a program: '/bin/sleep' "[:30]):
        assert words in notes, (words, notes)


def test_without_bwrap_a_loud_warning_and_require_sandbox_refuses(tmp_path):
    empty = tmp_path / "empty.py"
    empty.write_text("\n\n")
    env = dict(os.environ, PATH=str(tmp_path))  # no bwrap on it
    command = [sys.executable, str(ROOT / "scripts" / "grade.py"), str(empty)]
    refused = subprocess.run(command + ["--require-sandbox"], capture_output=True, text=True, env=env, timeout=120)
    assert refused.returncode != 0 and refused.stderr.count("\n") == 1 and "Traceback" not in refused.stderr
    assert refused.stderr.startswith("error: --require-sandbox: bubblewrap (bwrap) is not installed")
    graded = subprocess.run(command, capture_output=True, text=True, env=env, timeout=300)
    assert graded.returncode == 0, graded.stderr
    assert graded.stderr.count("WARNING: submissions are NOT contained") == 1
    assert "TODOs 1-7: not graded — the file is empty" in graded.stdout  # item 5: an empty file, not graded, listed
    assert f"Not graded at all: 1\n  {empty}: the file is empty" in graded.stdout


@needs_bwrap
def test_a_box_that_cannot_start_is_the_graders_trouble_not_the_students(tmp_path):
    from rigid.grading.sandbox import Limits, run_child

    box = tmp_path / "box"
    box.mkdir()
    with pytest.raises(RuntimeError, match="bwrap could not start the box: .*nowhere"):
        run_child(["--todos", "1"], box, tmp_path / "events.jsonl", Limits(), BOX, [tmp_path / "nowhere"])
