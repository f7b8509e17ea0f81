"""Write a file under a temporary name and rename it into place when complete.

A crash, a Ctrl-C or a blow-up never leaves a half-written file under the
user's name, and never destroys the file that was there before.
"""
from __future__ import annotations

import contextlib
import os
from pathlib import Path

from ..errors import UserError


def check_output_path(path, suffixes: tuple[str, ...] = ()) -> Path:
    """Fail early (one line, exit 2) on an output path that cannot be written."""
    path = Path(path)
    if suffixes and path.suffix.lower() not in suffixes:
        raise UserError(f"output {path}: use a file name ending in {' or '.join(suffixes)}")
    if path.is_dir():
        raise UserError(f"output {path} is a folder; give a file name")
    if not path.parent.is_dir():
        raise UserError(f"output folder {path.parent} does not exist; create it or pick another path")
    if not os.access(path.parent, os.W_OK):
        raise UserError(f"output folder {path.parent} is not writable; pick another path")
    # os.access trusts the permission bits (root passes everything): only creating the file the
    # run will write first (atomic_output's partial name) shows that the folder takes files,
    # e.g. /proc or a read-only mount does not. Made and removed now, before the simulation.
    tmp = partial_path(path)
    try:
        with open(tmp, "ab"):
            pass
        tmp.unlink()
    except OSError as err:
        reason = err.strerror or type(err).__name__
        raise UserError(f"output folder {path.parent} does not take new files (creating {tmp.name} there: "
                        f"{reason}); pick another path") from None
    return path


def partial_path(path: Path) -> Path:
    """The temporary name a complete file is renamed from: hidden, beside it."""
    return path.with_name(f".{path.stem}.partial{path.suffix}")


@contextlib.contextmanager
def atomic_output(path):
    """Yield a temporary path beside ``path``; on success rename it to ``path``."""
    path = Path(path)
    tmp = partial_path(path)
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
