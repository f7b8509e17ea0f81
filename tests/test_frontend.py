"""rigid/engine/frontend.py: its quick stand-ins answer as Taichi's and textwrap's do.

QuickWrapper against textwrap on every line of the engine's and Taichi's Python sources and
the caret rows Taichi draws under them, and on edge cases (tabs, Unicode, control characters,
lines longer than the width, spaces only).

In a fresh process (this worker has the patch in place already): Taichi's own ``_inside_class``
and the quick one are asked about the same frames (decorators in a class body, in a function,
at module level, on a continued line); then a process that imports the engine before Taichi
must never reach ``inspect.getframeinfo`` (Taichi's slow test, once per decorator: ~90 times
while ``import taichi`` decorates its own functions, without the finder).
"""
import random
import subprocess
import sys
import textwrap
from pathlib import Path

from conftest import ROOT

from rigid.engine.frontend import QuickWrapper

SAME_ANSWERS = r'''
import sys
import taichi as ti
from taichi.lang import kernel_impl
taichi_test = kernel_impl._inside_class
from rigid.engine import frontend
frontend._patch_class_test(kernel_impl)
quick_test = kernel_impl._inside_class
assert quick_test is not taichi_test
answers = []

def ask():  # as a decorator does: frame 3, seen from inside the test, is the one that decorates
    answers.append((taichi_test(level_of_class_stackframe=3), quick_test(level_of_class_stackframe=3)))

def deco(f):
    ask()
    return f

class A:
    @deco
    def method(self):
        pass

    x = (deco)(lambda: 0)

def outer():
    @deco
    def inner():
        pass

outer()

@deco
def plain():
    pass

class B: y = deco(1)

def data_oriented(cls):
    ask()
    return cls

@data_oriented
class C:
    pass

@ti.data_oriented
class D:
    z = deco(2)

assert [t for t, _ in answers] == [False, False, False, False, True, True, False], answers  # Taichi's
assert all(t == q for t, q in answers), answers
print("same", len(answers))
'''

NO_SLOW_TEST = r'''
import inspect
calls = []
slow = inspect.getframeinfo
inspect.getframeinfo = lambda *a, **k: (calls.append(1), slow(*a, **k))[1]
import rigid.engine  # imports Taichi through the finder
import taichi
assert "taichi.lang.kernel_impl" in __import__("sys").modules
print("getframeinfo", len(calls))
'''


def _run(code, tmp_path, name):
    path = tmp_path / f"{name}.py"  # a file: Taichi's test reads the decorating line from the source
    path.write_text(code)
    proc = subprocess.run([sys.executable, str(path)], cwd=ROOT, capture_output=True, text=True, timeout=300,
                          env={**__import__("os").environ, "PYTHONPATH": str(ROOT)})
    assert proc.returncode == 0, proc.stderr[-3000:]
    return proc.stdout


def test_quick_method_test_answers_as_taichis_and_runs_before_taichis_own_decorators(tmp_path):
    assert "same 7" in _run(SAME_ANSWERS, tmp_path, "same_answers")
    assert "getframeinfo 0" in _run(NO_SLOW_TEST, tmp_path, "no_slow_test")


def test_quick_wrapper_wraps_as_textwrap():
    import taichi

    lines = [line for folder in (ROOT / "rigid", Path(taichi.__file__).parent)
             for path in sorted(folder.rglob("*.py")) for line in path.read_text(encoding="utf-8").splitlines()]
    rng = random.Random(0)
    carets = [" " * rng.randrange(40) + "^" * rng.randrange(60) + " " * rng.randrange(30) for _ in range(2000)]
    edge = ["", " ", " " * 81, "a", "  a  ", "x" * 80, "x" * 81, "a " * 40, " " * 79 + "a", "\tindented", "a\tb",
            "caf\u00e9", "\u3000a", "a\x1fb", "a\nb", "-" * 85, "a-b " * 30, "  \u00a0 "]
    assert len(lines) > 50000
    for width in (80, 10):
        quick, plain = QuickWrapper(width=width), textwrap.TextWrapper(width=width)
        for text in [*lines, *carets, *edge]:
            assert quick.wrap(text) == plain.wrap(text), (width, text)
