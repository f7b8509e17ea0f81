"""Import a submission file by path and turn any failure into one line for the student.

Runs only in the child process. The module gets a fresh unique name (Taichi
looks functions' source up through sys.modules), like rigid.engine.units.load_units,
but a missing TODO function is not an error here: it costs only its TODO.
"""
import importlib.util
import sys
import traceback
import uuid
from pathlib import Path

MAIN_HINT = "keep code that runs the simulation under `if __name__ == \"__main__\":`"


def import_submission(path, memory_mb: int):
    """Return (module, None) or (None, message)."""
    path = Path(path).resolve()
    name = f"_submission_{uuid.uuid4().hex[:8]}"
    try:
        spec = importlib.util.spec_from_file_location(name, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
        return module, None
    except SystemExit as err:
        return None, f"the file calls sys.exit() (or exit(), code {err.code}) when imported; {MAIN_HINT}"
    except SyntaxError as err:
        return None, f"the file has a syntax error at line {err.lineno}: {err.msg}"
    except ModuleNotFoundError as err:
        return None, (f"the file imports {err.name!r}, which the grader does not have; "
                      f"use only taichi, numpy and rigid.engine.rotation")
    except MemoryError:
        return None, f"the file ran out of memory when imported (limit {memory_mb} MB)"
    except BaseException as err:  # anything a submission raises at import costs its points, nothing more
        line = _line_in(err, path)
        where = f" at line {line}" if line else ""
        return None, (f"the file raises {type(err).__name__}{where} when imported: "
                      f"{str(err).splitlines()[0][:200] if str(err) else ''}; {MAIN_HINT}")


def _line_in(err: BaseException, path: Path):
    """The last line of ``path`` in the traceback of ``err``, or None."""
    lines = [frame.lineno for frame in traceback.extract_tb(err.__traceback__)
             if Path(frame.filename).resolve() == path]
    return lines[-1] if lines else None
