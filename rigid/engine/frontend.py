"""Taichi's Python frontend, made cheaper: decorating is quick, and AST positions are formatted once.

Each ``@ti.func`` and ``@ti.kernel`` asks whether it decorates a method (``_inside_class``) by
reading the source line of a caller's frame with ``inspect.getframeinfo``, which looks the
frame's module up with ``inspect.getmodule``: a scan of every module in ``sys.modules``, for
each of the engine's ~200 decorators (measured: importing the engine 0.11 s, 0.035 s without
the scans; more in a process holding more modules, as a test worker or the grader's child,
which imports each version of a graded file).
``install()`` reads the same line with ``linecache`` instead (the frame's file and line number,
as getframeinfo does) and matches it against Taichi's own patterns: the same answer.

Every process builds the kernels' IR from their Python source, even when the machine code then
comes from the offline cache (Taichi 1.7 keys the cache by that IR), and each inlined call of a
``ti.func`` reads its source again: ``inspect.getsourcelines`` (a tokenizer pass over the file),
then ``textwrap.fill`` line by line and ``textwrap.dedent``: ~30 % of building the IR (a
command-line run's largest part, ~0.7 s). ``install()`` keeps each function's source lines
(weakly, by the function object: a new version of a graded file is a new module) and the
results of the two textwrap calls (pure functions of their arguments), so each is done once.

While Taichi 1.7 turns a kernel's Python AST into its IR it formats a debug string for every
node it visits (the file, the line and a row of carets under the node, wrapped at 80 columns by
``textwrap``), to show should compiling fail. The engine's stages are ``ti.func``s inlined many
times over (every kernel, every RK4 stage), so building the lone body's kernels formats ~30,000
of these strings for ~2,800 distinct nodes: ~0.7 s of the ~3 s a first run of a Simulator
spends before its kernels are loaded from Taichi's offline cache. The grader pays it once per
graded file, the suite once per process.

``install()`` wraps Taichi's ``get_pos_info`` in a memo keyed by everything the string is made
from (file, function name, offsets, the node's type and span, the source lines it covers), so
the strings, and every message built from them, are exactly Taichi's; the distinct ones are
wrapped by ``QuickWrapper``, which writes down textwrap's answer for a line that fits (nearly
all of them) instead of chunking it (~0.1 s of every process). Where Taichi's internals differ
from 1.7's it leaves them alone.
"""
from __future__ import annotations

import textwrap

_installed = False


def install() -> None:
    global _installed
    if _installed:
        return
    _installed = True
    _quick_class_test()
    _sources_once()
    try:
        from taichi.lang.ast import ast_transformer_utils
        from taichi.lang.ast.ast_transformer_utils import ASTTransformerContext

        ast_transformer_utils.TextWrapper  # noqa: B018 (get_pos_info wraps each line at 80 columns)
        ast_transformer_utils.TextWrapper = QuickWrapper

        original = ASTTransformerContext.get_pos_info
    except (ImportError, AttributeError):
        return
    memo: dict = {}

    def get_pos_info(self, node):
        try:
            body = getattr(node, "body", None)
            first_body_line = body[0].lineno if isinstance(body, list) and body and hasattr(body[0], "lineno") else 0
            key = (self.file, self.func.func.__name__, self.lineno_offset, self.indent, type(node).__name__,
                   node.lineno, node.col_offset, node.end_lineno, node.end_col_offset, first_body_line,
                   tuple(self.src[node.lineno - 1:node.end_lineno]))
        except Exception:  # not the context or node Taichi 1.7 passes: no memo
            return original(self, node)
        text = memo.get(key)
        if text is None:
            text = memo[key] = original(self, node)
        return text

    ASTTransformerContext.get_pos_info = get_pos_info


class QuickWrapper(textwrap.TextWrapper):
    """``TextWrapper.wrap`` with its answer for a line that fits written down, not computed.

    With the default options, a text of printable ASCII (so its only whitespace is spaces)
    no longer than the width is one line with its trailing spaces dropped, or no line at all
    when it is only spaces; the node strings are nearly all such lines. A longer text goes to
    textwrap once (its answer is kept: every node of a source line wraps that line), and
    other options always, so the answer is always textwrap's (tests/test_frontend.py)."""

    _longer: dict = {}  # (options, text) -> textwrap's lines, for texts longer than the width

    def wrap(self, text):
        if self.initial_indent or self.subsequent_indent or not self.drop_whitespace or \
                self.max_lines is not None:
            return super().wrap(text)
        if len(text) <= self.width and text.isascii() and text.isprintable():
            return [text.rstrip(" ")] if text.strip(" ") else []
        key = (self.width, self.expand_tabs, self.tabsize, self.replace_whitespace, self.fix_sentence_endings,
               self.break_long_words, self.break_on_hyphens, text)
        lines = self._longer.get(key)
        if lines is None:
            if len(self._longer) > 100_000:
                self._longer.clear()
            lines = self._longer[key] = super().wrap(text)
        return list(lines)


def _quick_class_test() -> None:
    """Taichi's ``_inside_class(level)`` with the caller's line read by linecache (see above).

    Taichi's own modules decorate ~200 functions while ``import taichi`` runs (taichi.math, the
    algorithms, ...), each with the slow test, so when Taichi is not imported yet the quick one
    goes in as soon as ``taichi.lang.kernel_impl`` has run, before those decorators do (~0.05 s
    of every process's start)."""
    import sys

    if "taichi.lang.kernel_impl" in sys.modules:
        _patch_class_test(sys.modules["taichi.lang.kernel_impl"])
        return
    finder = _PatchAfterImport("taichi.lang.kernel_impl", _patch_class_test)
    sys.meta_path.insert(0, finder)
    try:
        from taichi.lang import kernel_impl  # noqa: F401 (imports Taichi; the finder patches it)
    except ImportError:
        return
    finally:
        if finder in sys.meta_path:
            sys.meta_path.remove(finder)


class _PatchAfterImport:
    """A meta-path finder for one module: found as usual, then ``patch(module)`` once it has run."""

    def __init__(self, name, patch):
        self.name, self.patch = name, patch

    def find_spec(self, name, path=None, target=None):
        if name != self.name:
            return None
        import importlib.machinery
        import sys

        sys.meta_path.remove(self)  # once
        spec = importlib.machinery.PathFinder.find_spec(name, path)
        if spec is None or not hasattr(spec.loader, "exec_module"):
            return spec
        loader, patch = spec.loader, self.patch

        class Patching:  # the module's own loader, then the patch
            def create_module(self, spec):
                return loader.create_module(spec)

            def exec_module(self, module):
                loader.exec_module(module)
                patch(module)

            def __getattr__(self, attr):  # get_source, get_filename, ...: the module's own loader's
                return getattr(loader, attr)

        spec.loader = Patching()
        return spec


def _patch_class_test(kernel_impl) -> None:
    import linecache
    import sys

    try:
        patterns = kernel_impl._KERNEL_CLASS_STACKFRAME_STMT_RES
        kernel_impl._inside_class  # noqa: B018 (present in Taichi 1.7)
    except AttributeError:
        return

    def _inside_class(level_of_class_stackframe):
        try:
            frame = sys._getframe(level_of_class_stackframe)  # called where Taichi's is: the same frame
            line = linecache.getline(frame.f_code.co_filename, frame.f_lineno, frame.f_globals).strip()
            return any(pattern.match(line) for pattern in patterns)
        except Exception:  # as Taichi's: any failure means "not a method"
            return False

    kernel_impl._inside_class = _inside_class


def _sources_once() -> None:
    """Taichi's source reading for the frontend, each result computed once (see above)."""
    import functools
    import types
    import weakref

    try:
        from taichi.lang import kernel_impl

        read_lines, read_file = kernel_impl.getsourcelines, kernel_impl.getsourcefile
        kernel_impl.textwrap  # noqa: B018 (Taichi 1.7 calls textwrap.fill and .dedent in _get_tree_and_ctx)
    except (ImportError, AttributeError):
        return
    lines_of, file_of = weakref.WeakKeyDictionary(), weakref.WeakKeyDictionary()

    def getsourcelines(obj):
        try:
            found = lines_of.get(obj)
        except TypeError:  # not weakly referable: Taichi's own
            return read_lines(obj)
        if found is None:
            found = read_lines(obj)
            lines_of[obj] = (list(found[0]), found[1])
        return list(found[0]), found[1]

    def getsourcefile(obj):
        try:
            found = file_of.get(obj)
        except TypeError:
            return read_file(obj)
        if found is None:
            found = file_of[obj] = read_file(obj)
        return found

    kernel_impl.getsourcelines, kernel_impl.getsourcefile = getsourcelines, getsourcefile
    kernel_impl.textwrap = types.SimpleNamespace(fill=functools.lru_cache(maxsize=None)(textwrap.fill),
                                                 dedent=functools.lru_cache(maxsize=None)(textwrap.dedent))
