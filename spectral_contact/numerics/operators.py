"""Fourier multipliers on a periodic grid: a grid plus a symbol, applied through the plan cache.

``FourierOperator(grid, symbol)`` applies ``u = irfft(S(k) rfft(f))``: a periodic convolution,
e.g. the film's surface compliance (physics.film).  The symbol is a function of the wavevector
given as its direction n = k/|k| (a tuple of arrays, ``grid.direction``) and its magnitude |k|,
so that the operator can also build

* ``preconditioner(k_c)``: the inverse symbol restricted to |k| >= k_c, continued below k_c by
  its value at |k| = k_c in the same direction (the inverse of an order -1 operator that a
  contact of width W cannot resolve below k_c ~ pi/W: it turns the contact operator into an
  order-0 one, so GMRES needs about as many iterations at every grid size);
* ``op + c``: the symbol S + c (a local term: e.g. a linear interface compliance).
"""
from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .fft import get_rfft
from .grid import Grid

__all__ = ["FourierOperator"]

Symbol = Callable[[tuple, np.ndarray], np.ndarray]


class FourierOperator:
    """A Fourier multiplier ``symbol(direction, kmag)`` on ``grid``.

    ``symbol`` must accept broadcastable arrays: ``direction`` a tuple of ``grid.ndim`` arrays
    of unit-vector components, ``kmag`` >= 0 (k = 0 included: the symbol decides its value
    there).  ``constant`` is added to the symbol everywhere.
    """

    def __init__(self, grid: Grid, symbol: Symbol, constant: complex = 0.0):
        self.grid = grid
        self.symbol_function = symbol
        self.constant = constant
        self._preconditioners: dict[float, np.ndarray] = {}

    def _evaluate(self, kmag: np.ndarray) -> np.ndarray:
        s = np.asarray(self.grid.alias_average(lambda n: self.symbol_function(n, kmag)))
        return s + self.constant if self.constant else s

    @property
    def symbol(self) -> np.ndarray:
        """The symbol on the grid's half spectrum (shape ``grid.kshape``)."""
        s = getattr(self, "_symbol", None)
        if s is None:
            s = self._symbol = np.broadcast_to(self._evaluate(self.grid.kmag), self.grid.kshape).copy()
        return s

    def apply(self, field: np.ndarray) -> np.ndarray:
        """The operator applied to a real field of shape ``grid.shape`` (one FFT pair)."""
        return get_rfft(self.grid.shape).apply(field, self.symbol)

    def apply_symbol(self, field: np.ndarray, symbol: np.ndarray) -> np.ndarray:
        """Another symbol on the same grid (e.g. ``preconditioner(k_c)``) applied to ``field``."""
        return get_rfft(self.grid.shape).apply(field, symbol)

    def preconditioner(self, k_cut: float) -> np.ndarray:
        """Symbol of the approximate inverse: 1/S(k) for |k| >= k_cut, 1/S(k_cut n) below
        (cached per cut-off)."""
        P = self._preconditioners.get(k_cut)
        if P is None:
            k = self.grid.kmag
            low = k < k_cut
            inv = np.zeros(self.grid.kshape, dtype=complex)
            hi = ~low
            inv[hi] = 1.0 / self.symbol[hi]
            # the symbol at |k| = k_cut in every direction: |k| as one broadcast value (the
            # film's transfer functions once, not once per mode)
            kc = np.full((1,) * self.grid.ndim, float(k_cut))
            clipped = np.broadcast_to(self._evaluate(kc), self.grid.kshape)
            inv[low] = 1.0 / clipped[low]
            if len(self._preconditioners) > 32:  # bounded: cut-offs follow the contact width
                self._preconditioners.clear()
            P = self._preconditioners[k_cut] = inv
        return P

    def __add__(self, c) -> FourierOperator:
        """The operator S + c (c a real or complex constant)."""
        return FourierOperator(self.grid, self.symbol_function, self.constant + c)

    __radd__ = __add__
