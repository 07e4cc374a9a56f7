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

``low_rank``: ``TailTerm``s added to the periodic convolution (``tail_terms``: a viscoelastic
film's long relaxation tails, whose periodic images are summed exactly).
"""
from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .fft import get_rfft
from .grid import Grid

__all__ = ["FourierOperator", "TailTerm", "tail_terms"]

Symbol = Callable[[tuple, np.ndarray], np.ndarray]


class FourierOperator:
    """A Fourier multiplier ``symbol(direction, kmag)`` on ``grid``.

    ``symbol`` must accept broadcastable arrays: ``direction`` a tuple of ``grid.ndim`` arrays
    of unit-vector components, ``kmag`` >= 0 (k = 0 included: the symbol decides its value
    there).  ``constant`` is added to the symbol everywhere.
    """

    def __init__(self, grid: Grid, symbol: Symbol, constant: complex = 0.0, low_rank=()):
        self.grid = grid
        self.symbol_function = symbol
        self.constant = constant
        self.low_rank = tuple(low_rank)  # TailTerms: the operator adds t.field(f)
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
        out = get_rfft(self.grid.shape).apply(field, self.symbol)
        for t in self.low_rank:
            out += t.field(np.ravel(field), slice(None)).reshape(out.shape)
        return out

    def apply_symbol(self, field: np.ndarray, symbol: np.ndarray) -> np.ndarray:
        """Another symbol on the same grid (e.g. ``preconditioner(k_c)``) applied to ``field``."""
        return get_rfft(self.grid.shape).apply(field, symbol)

    def preconditioner(self, k_cut: float) -> np.ndarray:
        """Symbol of the approximate inverse: 1/S(k) for |k| >= k_cut, 1/S(k_cut n) below
        (cached per cut-off)."""
        P = self._preconditioners.get(k_cut)
        if P is None:
            k = self.grid.kmag
            if self.grid.ndim == 1:
                P = self._line_preconditioner(k, float(k_cut))
            else:
                low = k < k_cut
                inv = np.zeros(self.grid.kshape, dtype=complex)
                hi = ~low
                inv[hi] = 1.0 / self.symbol[hi]
                # the symbol at |k| = k_cut in every direction: |k| as one broadcast value (the
                # film's transfer functions once, not once per mode)
                kc = np.full((1,) * self.grid.ndim, float(k_cut))
                clipped = np.broadcast_to(self._evaluate(kc), self.grid.kshape)
                inv[low] = 1.0 / clipped[low]
                P = inv
            if len(self._preconditioners) > 32:  # bounded: cut-offs follow the contact width
                self._preconditioners.clear()
            self._preconditioners[k_cut] = P
        return P

    def _line_preconditioner(self, k: np.ndarray, k_cut: float) -> np.ndarray:
        """``preconditioner`` of a line grid, the same numbers: there the direction is +1 at
        every mode (``Grid.direction``) and |k| increases, so the symbol at |k| = k_cut is one
        value, evaluated once instead of over the half spectrum (a viscoelastic film's complex
        modulus and products there: ~1.5 ms of a cold paper-scene solve's 13), the modes
        below k_cut are the first ones, and 1/S above is the operator's one inverse symbol."""
        m = int(k.searchsorted(k_cut))  # the modes k < k_cut
        # 1/S at every mode, once per operator (a solve asks for a cut-off per contact size)
        full = getattr(self, "_inverse", None)
        if full is None:
            with np.errstate(divide="ignore", invalid="ignore"):  # (S(0) = 0: below any cut)
                full = self._inverse = 1.0 / self.symbol
        inv = full.copy()
        clipped = np.asarray(self.symbol_function((np.ones(1),), np.full(1, k_cut)))
        if self.constant:
            clipped = clipped + self.constant
        inv[:m] = 1.0 / clipped
        return inv

    def __add__(self, c) -> FourierOperator:
        """The operator S + c (c a real or complex constant)."""
        return FourierOperator(self.grid, self.symbol_function, self.constant + c, self.low_rank)

    __radd__ = __add__


class TailTerm:
    """One relaxation tail's periodic images, summed (``tail_terms``): the correction to add to
    the periodic convolution of a field, a(x) (b . p)(y) on a line (rank one) or a(x) [g *_y
    (b . p)](y) on a surface (rank one along x, a convolution along y of symbol g)."""

    def __init__(self, a: np.ndarray, b: np.ndarray, g: np.ndarray | None = None,
                 shape: tuple = ()):
        self.a, self.b, self.g, self.shape = a, b, g, shape

    def field(self, values: np.ndarray, sel) -> np.ndarray:
        """The correction (flat, whole grid) for the field holding ``values`` at the flat
        positions ``sel`` and 0 elsewhere."""
        if self.g is None:
            return self.a * float(self.b[sel] @ values)
        nx, ny = self.shape
        f = np.zeros(nx * ny)
        f[sel] = values
        m = self.b @ f.reshape(nx, ny)
        c = np.fft.irfft(self.g * np.fft.rfft(m), ny)
        return np.multiply.outer(self.a, c).ravel()

    def at(self, values: np.ndarray, sel) -> np.ndarray:
        """``field`` gathered at ``sel``."""
        if self.g is None:
            return self.a[sel] * float(self.b[sel] @ values)
        return self.field(values, sel)[sel]


def tail_terms(shape: tuple, lengths: tuple, poles) -> tuple:
    """The corrections that turn a grid's periodic convolution along x into the isolated
    (aperiodic) one for kernels with long one-sided exponential tails ``poles`` ((l, B):
    K(s_x, s_y) = exp(s_x/l)/|l| F_y^-1[B(k_y)](s_y) for s_x/l < 0, ``Film.tail_poles``), as
    ``TailTerm``s for ``FourierOperator``.

    The periodic sum along x of that tail differs from it, for every s = x - x' in (-L, L)
    (both points on one period, L the period along x), by q exp(s/l) / (|l| (1 - q)) times
    the y-kernel, q = exp(-L/|l|): one exponential in s, i.e. exp(x/l) exp(-x'/l), rank one
    along x.  The other parts of the kernel decay at the film's elastic rate (the period's
    margin).  So u_isolated = u_periodic + a(x) [g *_y (b . p)] with a = exp((x - x_m)/l -
    L/(2|l|)), b = dx exp(-(x - x_m)/l - L/(2|l|)) on the nodes (x_m the period's middle:
    both exponents <= 0, no overflow) and g = -B(k_y) / (|l| (1 - q)) (on a line the
    constant -B(0)/(|l| (1 - q)), folded into a).  Along y the grid's own periodic
    convolution (the y-kernel decays at the elastic rate or faster)."""
    if not poles or len(shape) > 2:
        return ()
    n, L = shape[0], lengths[0]
    dx = L / n
    s = (np.arange(n) - n // 2) * dx
    out = []
    for length, B in poles:
        al = abs(length)
        half = 0.5 * L / al
        scale = -1.0 / (al * -math.expm1(-2.0 * half))
        a = np.exp(s / length - half)
        b = dx * np.exp(-s / length - half)
        if len(shape) == 1:
            out.append(TailTerm(scale * float(B(np.zeros(1))[0]) * a, b))
        else:
            ny, Ly = shape[1], lengths[1]
            ky = 2.0 * math.pi * np.fft.rfftfreq(ny, Ly / ny)
            out.append(TailTerm(a, b, scale * B(ky), shape))
    return tuple(out)
