"""Import a submission file by path and turn any failure into one line for the student.

Runs only in the child process. The module gets a fresh unique name (Taichi
looks functions' source up through sys.modules), like rigid.engine.units.load_units,
but a missing TODO function is not an error here: it costs only its TODO.

A syntax error between ``# TODO k:`` and ``# END TODO k`` costs TODO k only:
``isolate_syntax_errors`` puts the handout's placeholder in that block (a copy
of the file beside it, same number of lines, so line numbers stay the
student's) and tries again, until the file parses or an error lies outside
every TODO block (that one costs every TODO, as before).
"""
import importlib.util
import sys
import traceback
import uuid
from pathlib import Path

MAIN_HINT = "keep code that runs the simulation under `if __name__ == \"__main__\":`"


def isolate_syntax_errors(path) -> tuple:
    """(path of the file to import, {k: message}) with each TODO block that has a syntax error replaced."""
    import ast
    import re

    from .handout import END, PLACEHOLDERS, START

    path = Path(path)
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines(keepends=True)
    blocks, open_k = {}, None
    for i, line in enumerate(lines):
        start, end = START.match(line), END.match(line)
        if start:
            open_k = int(start["k"])
            blocks[open_k] = [i, None, start["indent"]]
        elif end and open_k is not None and int(end["k"]) == open_k:
            blocks[open_k][1], open_k = i, None
    errors = {}
    while True:
        try:
            ast.parse("".join(lines))
            break
        except SyntaxError as err:
            line = err.lineno or 0
            k = next((k for k, (a, b, _) in blocks.items() if b is not None and a < line - 1 < b and k not in errors
                      and k in PLACEHOLDERS), None)
            if k is None:
                break
            errors[k] = f"TODO {k}: the code between '# TODO {k}:' and '# END TODO {k}' has a syntax error at " \
                        f"line {line}: {err.msg}"
            a, b, indent = blocks[k]
            filler = [f"{indent}{code}\n" for code in PLACEHOLDERS[k]]
            body = filler + [f"{indent}pass\n"] * max(0, b - a - 1 - len(filler))  # keep the line count
            if len(body) > b - a - 1:  # a block shorter than the placeholder: line numbers after it shift
                body = [f"{indent}{'; '.join(PLACEHOLDERS[k])}\n"] + [f"{indent}pass\n"] * (b - a - 2)
            lines[a + 1:b] = body
    if not errors:
        return path, {}
    patched = path.with_name(f"{path.stem}_syntax_isolated{path.suffix}")
    patched.write_text("".join(re.sub(r"\r\n?", "\n", line) for line in lines), encoding="utf-8")
    return patched, errors


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
