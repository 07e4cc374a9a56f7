"""The solver interface: methods registered by name, each validating its own options.

In the spirit of ``scipy.integrate.OdeSolver`` / ``METHODS``: ``Method`` subclasses are
registered by name (``register``), constructed with the tolerance and their options (which they
validate, naming the option and its accepted range), and ``solve(scene, model)`` returns a
``ContactResult`` whose ``counters`` hold the same keys for every method:

    transforms         FFT pairs (forward + backward) spent, 0 where none are used
    iterations         outer iterations (active-set, or root finding on the half-width)
    linear_iterations  inner iterations (GMRES matrix-vector products, or Nystrom solves)
"""
from __future__ import annotations

import math
import numbers
from abc import ABC, abstractmethod

from ..errors import InputError, named
from ..physics.scene import Scene, check_tol
from ..result import COUNTER_KEYS

__all__ = ["Method", "METHODS", "register", "check_grid_points", "COUNTER_KEYS"]

METHODS: dict[str, type[Method]] = {}


def register(cls):
    """Class decorator: add a Method subclass to METHODS under ``cls.name``."""
    METHODS[cls.name] = cls
    return cls


def check_grid_points(value, lo: int, hi: int, what: str, even: bool = False,
                      shown: str | None = None) -> int | None:
    """An integer count in [lo, hi] (None passes through).  Whole floats are accepted;
    booleans, strings and fractional or non-finite numbers are refused.  ``shown``: the range
    as the messages say it (default "[lo, hi]")."""
    if value is None:
        return None
    shown = shown or f"[{lo}, {hi}]"
    n_ = named("grid_points")
    ok = isinstance(value, numbers.Integral) or (
        isinstance(value, numbers.Real) and math.isfinite(value) and float(value).is_integer())
    if isinstance(value, bool) or not ok:
        raise InputError(f"{n_} ({what}) must be an integer in {shown}; got {value!r}")
    n = int(value)
    if not lo <= n <= hi:
        raise InputError(f"{n_} ({what}) must be in {shown}; got {n}")
    if even and n % 2:
        raise InputError(f"{n_} ({what}) must be even (a power of two is fastest); got {n}")
    return n


ONSET_MU_MIN = 1e-6
"""The smallest |mu| onset takes: below it the tangential load mu P is below what the partial
slip iteration resolves (|mu| 1e-200 and below crashed it; 1e-100 ... 1e-8 did not converge)."""


def check_onset_mu(mu) -> float:
    """|mu| >= ONSET_MU_MIN (the tangential load goes up to mu P)."""
    if not abs(mu) >= ONSET_MU_MIN:
        raise InputError(f"{named('mu')} must be != 0 for onset, |mu| >= {ONSET_MU_MIN:g} (the "
                         f"tangential load goes up to mu P); got {mu:g}")
    return mu


class Method(ABC):
    """A numerical method for the contact of one scene.

    Parameters
    ----------
    tol : float
        Relative accuracy target, in [1e-14, 0.1).
    grid_points : int, optional
        The method's resolution (grid points, nodes), fixed instead of chosen from ``tol``.
    domain_length : float, optional
        The period of a periodic method, in film thicknesses (h).
    """

    name: str = ""
    models: tuple[str, ...] = ("exact", "goodman")

    def __init__(self, tol: float = 1e-4, grid_points=None, domain_length=None):
        self.tol = check_tol(tol)
        self.grid_points = grid_points
        self.domain_length = domain_length

    @abstractmethod
    def solve(self, scene: Scene, model: str):
        """Solve ``scene`` with ``model`` (one of ``self.models``); returns a ContactResult."""

    def check_model(self, model: str) -> str:
        if model not in self.models:
            raise InputError(f"model must be one of {', '.join(self.models)} for method "
                             f"{self.name}; got {model!r}")
        return model
