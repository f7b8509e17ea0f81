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
    return path


@contextlib.contextmanager
def atomic_output(path):
    """Yield a temporary path beside ``path``; on success rename it to ``path``."""
    path = Path(path)
    tmp = path.with_name(f".{path.stem}.partial{path.suffix}")
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
