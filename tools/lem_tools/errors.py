"""The error every command reports as `PROG: error: MESSAGE`, exit 1."""


class ToolError(Exception):
    """A problem with the user's input or files, told in one sentence."""
