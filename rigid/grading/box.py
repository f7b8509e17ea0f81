"""The box a grading child runs in: bubblewrap (``bwrap``), when the machine has it.

``find_box()`` returns a ``Box`` when ``bwrap`` is on PATH and can start a sandbox here (a
container may forbid the namespaces it needs), else None with the reason. ``Box.command(...)``
wraps the child's command so that it sees:

- the system (/usr, the /bin and /lib links, a few files of /etc: never /etc/shadow), Python's
  installation and site-packages, and this package's ``rigid/`` and ``assets/``, all read-only;
- its own box (the submission's folder, writable), the events file it reports to, and the
  reference files it grades against (read-only); /tmp is an empty tmpfs of its own;
- no network (its own network namespace: no interface but a down loopback), its own PID, IPC
  and UTS namespaces, so a process it leaves behind dies with it (bwrap's PID 1 is the child).

Nothing else of the machine is there: not the other submissions, not the TA's home, not the
grades. As root, bwrap keeps capabilities, and a root process can read any file it can see and
is exempt from RLIMIT_NPROC: so the child is told (RIGID_CHILD_UID) to drop to an unprivileged
uid of its own before it loads anything (child.apply_limits), and its box is chown'ed to it.
As a user, bwrap makes a user namespace, where the process limit counts this box's processes only.
"""
import itertools
import os
import shutil
import site
import subprocess
import sys
import threading
from dataclasses import dataclass
from pathlib import Path

from ..config import REPO_ROOT

ETC = ("ld.so.cache", "ld.so.conf", "ld.so.conf.d", "localtime", "passwd", "group", "nsswitch.conf",
       "alternatives", "hosts", "resolv.conf")  # what the dynamic loader, Python and Taichi may read
# uids of children when the grader is root: far above users', systemd's (61184-65519) and the usual
# subordinate ranges of containers (100000 up); 64 a grader process (its pid picks them), one a child alive
FIRST_UID = 1_900_000_000
_uids = itertools.count()
_lock = threading.Lock()


@dataclass
class Box:
    bwrap: str
    root: bool  # the grader runs as root: no user namespace, the child drops to its own uid

    def base(self) -> list:
        """bwrap and the options every child gets: namespaces, the system read-only, an empty /tmp."""
        args = [self.bwrap, "--die-with-parent", "--unshare-pid", "--unshare-net", "--unshare-ipc",
                "--unshare-uts", "--unshare-cgroup-try", "--as-pid-1", "--proc", "/proc", "--dev", "/dev",
                "--tmpfs", "/tmp"]
        if self.root:
            args += ["--cap-drop", "ALL", "--cap-add", "CAP_SETUID", "--cap-add", "CAP_SETGID"]
        else:
            args += ["--unshare-user"]
        return args + _system()

    def command(self, command: list, box: Path, writable: list, readable: list) -> tuple:
        """(the wrapped command, extra environment) for ``command`` run with cwd ``box``."""
        args, env = self.base(), {}
        args += _folders([*map(Path, readable), *map(Path, writable), Path(box)], python_roots())
        if self.root:
            with _lock:
                uid = FIRST_UID + 64 * (os.getpid() % 10000) + next(_uids) % 64
            _chown_tree(Path(box), uid)
            for path in writable:
                os.chown(path, uid, uid)
            env["RIGID_CHILD_UID"] = str(uid)
        for path in readable:
            args += ["--ro-bind", str(path), str(path)]
        for path in writable:
            args += ["--bind", str(path), str(path)]
        args += ["--bind", str(box), str(box), "--chdir", str(box), "--"]
        return args + command, env


def _system() -> list:
    """Read-only binds of the system and of Python, as this process sees them."""
    args = []
    for top in ("usr", "bin", "sbin", "lib", "lib32", "lib64", "libx32"):
        path = Path("/") / top
        if path.is_symlink():
            args += ["--symlink", os.readlink(path), str(path)]
        elif path.is_dir():
            args += ["--ro-bind", str(path), str(path)]
    for name in ETC:
        args += ["--ro-bind-try", f"/etc/{name}", f"/etc/{name}"]
    args += ["--ro-bind-try", "/sys/devices/system/cpu", "/sys/devices/system/cpu"]  # the CPU count
    args += _folders(python_roots(), [])
    for path in python_roots():
        args += ["--ro-bind", str(path), str(path)]
    return args


def _folders(bound: list, done: list) -> list:
    """``--dir`` for the folders above the bound paths, traversable by the child's uid (bwrap would copy
    the host's modes: a 0700 temporary folder or /root would lock it out), listing nothing of the host.
    Folders made for (above) or inside the paths ``done``, already bound, are left alone."""
    made = {str(a) for p in done for a in Path(p).parents}
    out = []
    for path in bound:
        for parent in reversed(Path(path).parents):
            text = str(parent)
            if text in ("/", "/tmp") or text.startswith(("/usr", "/proc", "/dev")) or text in out \
                    or text in made or any(_within(parent, Path(d)) for d in done):
                continue
            out.append(text)
    return [arg for text in out for arg in ("--perms", "0711", "--dir", text)]


def python_roots() -> list:
    """Python's installation, its site-packages (the user's too, where Python reads it) and this package's
    code and meshes (real paths and the paths as named, so a venv's links resolve inside the box)."""
    named = [Path(sys.prefix), Path(sys.base_prefix), *map(Path, site.getsitepackages()),
             REPO_ROOT / "rigid", REPO_ROOT / "assets"]
    if site.ENABLE_USER_SITE and site.getusersitepackages() in sys.path:  # taichi from pip install --user
        named.append(Path(site.getusersitepackages()))
    out = []
    for path in named:
        for p in (path.absolute(), path.resolve()):
            if p.exists() and not str(p).startswith(("/usr/", "/bin/", "/lib")) and p not in out:
                out.append(p)
    return [p for p in out if not any(q != p and _within(p, q) for q in out)]  # nested ones come with their root


def _within(path: Path, top: Path) -> bool:
    return path == top or top in path.parents


def _chown_tree(top: Path, uid: int) -> None:
    os.chown(top, uid, uid)
    for folder, dirs, files in os.walk(top):
        for name in dirs + files:
            os.chown(os.path.join(folder, name), uid, uid, follow_symlinks=False)


def find_box() -> tuple:
    """(Box or None, why there is none)."""
    bwrap = shutil.which("bwrap")
    if bwrap is None:
        return None, "bubblewrap (bwrap) is not installed"
    box = Box(bwrap, os.geteuid() == 0)
    probe = box.base() + ["--", "/bin/true"]
    try:
        proc = subprocess.run(probe, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired) as err:
        return None, f"bwrap cannot start here ({err})"
    if proc.returncode:
        why = (proc.stderr.strip().splitlines() or [f"exit code {proc.returncode}"])[-1]
        return None, f"bwrap cannot start a sandbox here ({why})"
    return box, ""
