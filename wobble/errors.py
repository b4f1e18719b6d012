"""Exception types raised throughout wobble.

Every error a user can provoke names what was wrong: the parameter (or file and
key/line), the value received, and what is allowed. The command line turns any
:class:`WobbleError` into one line on stderr and exit status 2.
"""

from __future__ import annotations

__all__ = ["WobbleError", "InputError", "FileFormatError", "OutputExistsError", "shown"]


class _Missing:
    """The value of a parameter that was not given at all (shown as ``missing``)."""

    def __repr__(self) -> str:
        return "MISSING"


MISSING = _Missing()


class WobbleError(ValueError):
    """Base class of wobble's own errors (a :class:`ValueError`)."""


def shown(value: object) -> str:
    """A value as an error message shows it: an array Quantity as typed, a long value cut in its middle."""
    text = str(value)
    if isinstance(value, str) and not value.strip():
        return repr(value)  # an empty or blank value as typed: "got ''", not "got ;"
    if getattr(value, "ndim", 0) and hasattr(value, "unit") and hasattr(value, "value"):
        # An array Quantity as a person types it, "(-1, 2, 3) kg m2", not NumPy's "[-1.  2.  3.] kg m2".
        numbers = ", ".join(f"{x:g}" for x in value.value.ravel().tolist()[:20])
        # One value is bracketed as a list, "[1.1] kg m2": "(1.1)" read as a number in parentheses.
        opening, closing = ("[", "]") if value.size == 1 else ("(", ")")
        text = f"{opening}{numbers}{', ...' if value.size > 20 else ''}{closing} {value.unit}"
    # Control characters as escapes: a typed value must not reach the terminal as one (ESC, BEL, a newline).
    text = "".join(ch if ch.isprintable() else repr(ch)[1:-1] for ch in text)
    # A long value keeps its start and its end: for a path, the end is the file's name.
    return text if len(text) <= 200 else text[:97] + "..." + text[-100:]


class InputError(WobbleError):
    """A parameter has a value outside what the computation allows.

    Parameters
    ----------
    parameter : str
        Name of the parameter as the user wrote it (``spin_period``, ``--model``).
    value : object
        The offending value, repeated in the message.
    allowed : str
        What would have been accepted.
    """

    def __init__(self, parameter: str, value: object, allowed: str):
        self.parameter = parameter
        self.value = value
        self.allowed = allowed
        got = "missing" if value is MISSING else f"got {shown(value)}"
        super().__init__(f"{parameter}: {got}; allowed: {allowed}")

    @classmethod
    def missing(cls, parameter: str, allowed: str) -> InputError:
        """A required parameter that was not given: ``"-o/--output: missing; allowed: ..."``."""
        return cls(parameter, MISSING, allowed)


class FileFormatError(WobbleError):
    """A file is missing, unreadable or does not follow its schema.

    Parameters
    ----------
    path : str
        The file.
    where : str or None
        Key (``parameters.k2.value``) or line (``line 12``) where the problem is.
    problem : str
        What is wrong and, where possible, what was expected.
    """

    def __init__(self, path: object, where: str | None, problem: str):
        self.path = str(path)
        self.where = where
        self.problem = problem
        location = f"{self.path}, {where}" if where else self.path
        super().__init__(f"{location}: {problem}")


class OutputExistsError(WobbleError):
    """The output file exists and overwriting was not requested."""

    def __init__(self, path: object):
        self.path = str(path)
        super().__init__(f"{self.path}: file exists; allowed: a new path, or overwrite=True to replace it")
        #: The same for the command line, whose option is --overwrite.
        self.command_line_message = f"{self.path}: file exists; allowed: a new path, or --overwrite to replace it"
