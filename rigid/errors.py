"""The one exception type for bad user input.

Anything the user can get wrong (a path, a flag, a TOML key, a mesh) raises
``UserError`` with one line that names the problem and the fix. The CLI prints
that line and exits with code 2, never a traceback.
"""


class UserError(Exception):
    """A problem with the user's input; ``str(err)`` is the one-line message."""

    exit_code = 2
