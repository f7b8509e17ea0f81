"""Run one child process under limits and watch it: the parent side of the isolation.

``run_child(args, box, events, limits)`` starts ``python -m rigid.grading.child``
in its own session (process group) with cwd and HOME in ``box``, a small clean
environment, memory/file-size limits (set by the child on itself before
anything else loads) and a time limit *per stage*: the child writes a line
when it starts a stage (import, each TODO's check, each trajectory run), and
the parent kills the whole process group when one stage has used
``limits.stage_seconds`` of CPU time (a busy endless loop), or has waited that
long in wall time while using almost no CPU over the last that many seconds
(an endless ``sleep``, a blocked read). CPU time, not wall time, so that a stage's fate does not depend on how
loaded the machine is: on 2 shared cores a compile that takes 5 CPU seconds
can take 30 s of wall time, and used to run out of a wall-clock limit. stdout and stderr (shared with the submission) are
drained by a thread into a bounded head + tail, so a print flood costs only
CPU time. Returns what happened; interpreting it is grade.py's job.

With a ``box.Box`` (bubblewrap) the child runs inside it: it sees its box, the
system and Python read-only, no network, nothing of the other submissions or
the TA's files (box.py). Without one it runs as the grader's user and can read
or write that user's files and open connections: grade.py says so once, loudly.
Either way a submission can fake its own events (it shares the child's process).
"""
import collections
import json
import select
import os
import signal
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

from ..config import REPO_ROOT

OUTPUT_KEEP = 2000  # characters kept from the start and from the end of the child's output


IDLE_SHARE = 0.02  # a stage using less CPU than this share of its wall time is waiting, not working


@dataclass
class Limits:
    stage_seconds: float = 60.0  # CPU seconds per stage (and wall seconds of a stage that waits)
    memory_mb: int = 4096
    file_mb: int = 64


@dataclass
class ChildRun:
    returncode: int | None
    timed_out: bool
    events: list = field(default_factory=list)
    output: str = ""
    seconds: float = 0.0

    @property
    def done(self) -> bool:
        """Every result was reported ("finish" only flushes Taichi's kernel cache)."""
        return any(e.get("event") == "done" for e in self.events) or self.last_stage.get("phase") == "finish"

    @property
    def last_stage(self) -> dict:
        stages = [e for e in self.events if "phase" in e]
        return stages[-1] if stages else {"phase": "import"}


class _Drain(threading.Thread):
    """Read a pipe to its end, keeping the first and last OUTPUT_KEEP bytes."""

    def __init__(self, pipe):
        super().__init__(daemon=True)
        self.pipe, self.head, self.tail, self.total = pipe, b"", b"", 0

    def run(self):
        for chunk in iter(lambda: self.pipe.read1(65536), b""):
            self.total += len(chunk)
            if len(self.head) < OUTPUT_KEEP:
                self.head += chunk[:OUTPUT_KEEP - len(self.head)]
            self.tail = (self.tail + chunk)[-OUTPUT_KEEP:]

    def text(self) -> str:
        if self.total <= OUTPUT_KEEP:
            return self.head.decode("utf-8", "replace")
        rest = self.tail[-(self.total - OUTPUT_KEEP):]  # the part of the tail not already in head
        skipped = self.total - OUTPUT_KEEP - len(rest)
        gap = f"\n[... {skipped} bytes of output left out ...]\n" if skipped else ""
        return self.head.decode("utf-8", "replace") + gap + rest.decode("utf-8", "replace")


def child_env(box: Path) -> dict:
    """A small clean environment: nothing of the grader's own environment leaks in but PATH and locale."""
    env = {k: v for k, v in os.environ.items() if k in ("PATH", "LANG", "LC_ALL", "LD_LIBRARY_PATH")}
    env.update(HOME=str(box), TMPDIR=str(box), PYTHONPATH=str(REPO_ROOT), PYTHONDONTWRITEBYTECODE="1",
               PYTHONHASHSEED="0", PYTHONUNBUFFERED="1", TI_SKIP_VERSION_CHECK="ON",
               ENABLE_TAICHI_HEADER_PRINT="0", TI_OFFLINE_CACHE_FILE_PATH=str(box / ".taichi-cache"),
               OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    return env


def run_child(args: list, box: Path, events_path: Path, limits: Limits, sandbox=None,
              readable: tuple = ()) -> ChildRun:
    """Run the child with ``args`` (after the module name); kill its process group on a stage timeout.

    ``sandbox``: a box.Box to run it in (``readable``: the files outside the box it reads), or None."""
    # -P (Python 3.11+): the box (cwd) is not put on sys.path, only the repository root is.
    safe_path = ["-P"] if sys.version_info >= (3, 11) else []
    command = [sys.executable, *safe_path, "-m", "rigid.grading.child", "--events", str(events_path),
               "--memory-mb", str(limits.memory_mb), "--file-mb", str(limits.file_mb), *map(str, args)]
    env, pass_fds, info = child_env(box), (), None
    if sandbox is not None:
        Path(events_path).touch()
        info, write_end = os.pipe()  # bwrap writes the child's pid there: its CPU time is the stage's
        wrapped, extra = sandbox.command(command, box, [events_path], readable)
        command = wrapped[:-len(command) - 1] + ["--info-fd", str(write_end), "--"] + command
        env.update(extra, RIGID_SANDBOXED="1")
        pass_fds = (write_end,)
    start = time.monotonic()
    proc = subprocess.Popen(command, cwd=box, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, start_new_session=True, pass_fds=pass_fds)
    pid = proc.pid
    if info is not None:
        os.close(pass_fds[0])
        pid = _child_pid(info) or pid
    drain = _Drain(proc.stdout)
    drain.start()
    reader = _EventReader(events_path)
    stage_wall, stage_cpu, timed_out = start, 0.0, False
    recent = collections.deque()  # (wall, cpu) samples of the last stage_seconds
    while proc.poll() is None:
        now, cpu = time.monotonic(), _cpu_seconds(pid)
        if reader.poll():
            stage_wall, stage_cpu = now, cpu
            recent.clear()
        recent.append((now, cpu))
        while len(recent) > 1 and now - recent[1][0] >= limits.stage_seconds:
            recent.popleft()  # keep the newest sample at least stage_seconds old
        used, waited = cpu - stage_cpu, now - stage_wall
        if cpu < 0:  # no /proc (not Linux): wall time alone
            used = waited
        # Waiting: over the last stage_seconds of wall time, almost no CPU.
        idle = waited > limits.stage_seconds and cpu - recent[0][1] < IDLE_SHARE * (now - recent[0][0])
        if used > limits.stage_seconds or idle:
            timed_out = True
            break
        time.sleep(0.05)
    _kill_group(proc)
    proc.wait()
    drain.join(timeout=5)
    reader.poll()
    if sandbox is not None and not reader.events and not timed_out:
        # the box or Python in it failed before the child wrote a line: the grader's trouble, not the submission's
        last = (drain.text().strip().splitlines() or [f"exit code {proc.returncode}"])[-1]
        raise RuntimeError(f"bwrap could not start the box: {last}")
    code = proc.returncode
    if sandbox is not None and code > 128:  # bwrap reports a child killed by signal N as 128 + N
        code = 128 - code
    return ChildRun(returncode=None if timed_out else code, timed_out=timed_out,
                    events=reader.events, output=drain.text(), seconds=time.monotonic() - start)


def _child_pid(fd: int):
    """The child's pid from bwrap's --info-fd JSON (None if bwrap failed before writing it)."""
    data = b""
    try:
        while select.select([fd], [], [], 30)[0]:
            chunk = os.read(fd, 4096)
            if not chunk:
                break
            data += chunk
    finally:
        os.close(fd)
    try:
        return int(json.loads(data)["child-pid"])
    except (ValueError, KeyError, TypeError):
        return None


def _cpu_seconds(pid: int) -> float:
    """User + system CPU seconds of process ``pid`` (all its threads: Taichi compiles on several),
    from /proc; -1 where there is no /proc."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            fields = f.read().rsplit(b")", 1)[1].split()
    except OSError:
        return -1.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime, stime


def _kill_group(proc) -> None:
    """SIGKILL the child's process group (the child and anything it started), if any is left."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


class _EventReader:
    """Read the child's JSON-lines events as they arrive; poll() says whether a new stage began."""

    def __init__(self, path: Path):
        self.path, self.offset, self.events, self.partial = path, 0, [], b""

    def poll(self) -> bool:
        try:
            with open(self.path, "rb") as f:
                f.seek(self.offset)
                data = f.read()
        except FileNotFoundError:
            return False
        self.offset += len(data)
        lines = (self.partial + data).split(b"\n")
        self.partial = lines.pop()
        new_stage = False
        for line in lines:
            try:
                event = json.loads(line)
            except ValueError:
                continue  # not ours: a submission that wrote into the file; ignored
            if isinstance(event, dict):
                self.events.append(event)
                new_stage |= "phase" in event
        return new_stage
