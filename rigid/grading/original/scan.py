"""Statements of a Python file read line by line, for a file that may not parse.

``continuation_lines(text)``: the lines that continue a statement begun above
them (inside brackets, a triple-quoted string, after a backslash). It recovers
from an unclosed bracket, so a syntax error in one TODO does not swallow the
rest of the file. ``indent_of(line)``: its indentation in columns (a tab = 4).
"""


def indent_of(line: str) -> int:
    return len(line.expandtabs(4)) - len(line.expandtabs(4).lstrip())


def continuation_lines(text: str) -> set:
    """Indices of lines that continue a statement (open brackets, a string over lines, a backslash).

    It recovers from an unclosed bracket (a syntax error in one TODO): a line no more indented than
    the line that opened the bracket, and not starting with a closing one, starts a new statement.
    """
    cont, depth, opener, quote = set(), 0, 0, None
    lines = text.splitlines()
    for i, line in enumerate(lines):
        stripped = line.strip()
        if quote is None and depth and stripped and indent_of(line) <= opener and stripped[0] not in ")]}":
            depth = 0
        if quote is not None or depth or (i and lines[i - 1].rstrip().endswith("\\")):
            cont.add(i)
        elif stripped:
            opener = indent_of(line)
        depth, quote = _scan(line, depth, quote)
    return cont


def _scan(line: str, depth: int, quote):
    """Bracket depth and open triple quote after ``line`` (strings and comments skipped)."""
    j = 0
    while j < len(line):
        if quote is not None:
            end = line.find(quote, j)
            if end < 0:
                return depth, quote
            j, quote = end + len(quote), None
            continue
        c = line[j]
        if c == "#":
            break
        if c in "'\"":
            triple = line[j:j + 3]
            if triple in ('"""', "'''"):
                quote, j = triple, j + 3
                continue
            end = j + 1
            while end < len(line) and line[end] != c:
                end += 2 if line[end] == "\\" else 1
            j = end + 1
            continue
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth = max(0, depth - 1)
        j += 1
    return depth, quote
