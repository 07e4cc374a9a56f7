"""Exceptions raised by spectral_contact."""
from __future__ import annotations


class SpectralContactError(Exception):
    """Base class of the package's errors."""


_MARK = "\x1f"  # brackets an option's Python name in a message (``named``)


def named(option: str) -> str:
    """``option`` (a Python parameter name) marked in a message, so that the message can name it
    as the caller typed it: ``str(InputError)`` says ``poisson``, and the command line, through
    ``InputError.as_typed``, ``--poisson``."""
    return f"{_MARK}{option}{_MARK}"


class InputError(SpectralContactError, ValueError):
    """A parameter is outside its accepted range. The message names the parameter and the range.

    Options named with ``named(...)`` in the message read as Python names in ``str(exc)``;
    ``exc.as_typed(name_of)`` renames them (the command line: ``--poisson``)."""

    def __init__(self, message="", *args):
        self.template = str(message)
        self.options = tuple(self.template.split(_MARK)[1::2])
        super().__init__(self.template.replace(_MARK, ""), *args)

    def __reduce__(self):  # pickled (dask workers) with its marks
        return (type(self), (self.template,))

    def as_typed(self, name_of) -> str:
        """The message with each marked option named ``name_of(option)``."""
        parts = self.template.split(_MARK)
        return "".join(name_of(p) if i % 2 else p for i, p in enumerate(parts))


class ConvergenceError(SpectralContactError, RuntimeError):
    """An iterative solver did not reach its tolerance.

    Attributes
    ----------
    residuals : list[float]
        The residual history (dimensionless, relative).
    iterations : int
        Iterations performed before giving up.
    """

    def __init__(self, message: str, residuals=(), iterations: int = 0):
        super().__init__(message)
        self.residuals = list(residuals)
        self.iterations = int(iterations)
