"""Exceptions raised by spectral_contact."""
from __future__ import annotations


class SpectralContactError(Exception):
    """Base class of the package's errors."""


class InputError(SpectralContactError, ValueError):
    """A parameter is outside its accepted range. The message names the parameter and the range."""


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
