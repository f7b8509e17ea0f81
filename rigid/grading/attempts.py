"""Inside the child: note what a submission tries beyond its own folder (Python's audit hooks).

The sandbox (box.py) is what contains a submission; this only tells the TA what it tried, in
that submission's feedback: reading or writing files outside its folder, a network connection,
a shell command or another program, forking. ``install(events, readable)`` adds the hook just
before the submission's code first runs; each kind of attempt on each target is noted once
(as {"event": "note"}), at most LIMIT notes a process. A hook cannot be removed from Python,
but native code (ctypes) passes it by: what it misses, the sandbox still holds.
"""
import os

from .box import python_roots

LIMIT = 8
WRITE_FLAGS = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_APPEND | os.O_TRUNC
SYSTEM = ("/usr/", "/lib", "/bin/", "/sbin/", "/etc/", "/proc/", "/sys/", "/dev/")  # not /tmp: other boxes live there


def install(events, readable=()) -> None:
    import sys

    box = os.getcwd()
    # the reference's folder: the project format imports the reference (its folder listed, its cache looked up)
    allowed = [box, *map(str, python_roots()), *(os.path.dirname(os.path.abspath(p)) for p in readable)]
    sandboxed = bool(os.environ.get("RIGID_SANDBOXED"))
    seen, busy = set(), [False]

    def note(kind, target, text):
        if (kind, target) in seen or len(seen) >= LIMIT:
            return
        seen.add((kind, target))
        if not sandboxed:
            why = "NOT contained: the grader ran without a sandbox"
        else:
            why = {"read": "the sandbox shows it nothing there", "write": "the sandbox keeps it out",
                   "connect": "the sandbox has no network"}.get(kind, "inside the sandbox: no network, no "
                                                                   "files but its own, ended with the grading")
        events.emit(event="note", message=f"the submission {text} ({why})")

    def inside(path, roots) -> bool:
        return any(path == r or path.startswith(r.rstrip("/") + "/") for r in roots)

    def hook(event, args):
        if busy[0]:
            return
        busy[0] = True
        try:
            _check(event, args)
        except Exception:
            pass  # a note is never worth breaking the grading
        finally:
            busy[0] = False

    def _check(event, args):
        if event == "open":
            path, mode, flags = args
            if not isinstance(path, (str, bytes)):
                return
            path = os.path.normpath(os.path.join(box, os.fsdecode(path)))
            writes = any(c in (mode or "") for c in "wax+") or bool((flags or 0) & WRITE_FLAGS)
            if writes and not inside(path, [box, "/dev/null"]):
                note("write", path, f"tried to write {path}, outside its own folder")
            elif not writes and not inside(path, allowed) and not path.startswith(SYSTEM):
                note("read", path, f"tried to read {path}, outside its own folder")
        elif event == "socket.connect":
            address = args[1]
            target = ":".join(map(str, address)) if isinstance(address, tuple) else str(address)
            note("connect", target, f"tried to open a network connection to {target}")
        elif event == "os.system":
            command = os.fsdecode(args[0])[:120]
            note("system", command, f"ran a shell command with os.system: {command!r}")
        elif event in ("subprocess.Popen", "os.exec", "os.posix_spawn", "os.spawn"):
            program = args[1] if event == "subprocess.Popen" else args[0]
            shown = " ".join(map(os.fsdecode, program))[:120] if isinstance(program, (list, tuple)) else \
                os.fsdecode(program)[:120]
            note("program", shown, f"started a program: {shown!r}")
        elif event == "os.fork":
            note("fork", "", "forked a process (os.fork)")

    sys.addaudithook(hook)
