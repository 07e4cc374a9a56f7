"""The film's surface compliance on an open (non-periodic) box: contacts much smaller than h.

A periodic grid must hold the contact plus the film's decay margin (~15 h at tol 1e-3) with
cells sized from the contact: a sphere with a/h = 0.01 would need ~10^4 points per axis.  Here
the contact is solved on a box a little larger than the contact, with the convolution made
non-periodic by zero padding (circulant embedding on a grid of twice the box per axis: every
pair of nodes inside the box is at an offset that does not wrap), and the film's kernel written
in real space as

    K(x) = alpha / (2 pi r) - mu beta x / (2 pi r^2) + K_even(r) + mu (x / r) K_odd(r),

where alpha / |k| and i mu n_x beta / |k| are the half-space limits of the symbol
H(k) = [F0 + i mu n_x F1] / (2|k|) (alpha = F0(inf) / 2 = 1/2 and beta = F1(inf) / 2 = 0 at
nu = 1/2; alpha = 1 - nu, beta = -(1 - 2 nu)/2 below), integrated exactly over each cell
(Love's formula; the odd term's closed form), and K_even, K_odd the kernels of the remainders
[F0 - F0(inf)] / (2|k|) and i n_x [F1 - F1(inf)] / (2|k|), which decay exponentially in |k| h:
smooth on the scale of h, sampled at the nodes (Hankel transforms by Gauss-Legendre quadrature,
tabulated in r):

    K_even(r) = (1/2pi) int_0^inf [F0(k) - F0(inf)] / 2 J0(k r) dk,
    K_odd(r)  = -(1/2pi) int_0^inf [F1(k) - F1(inf)] / 2 J1(k r) dk.

(Fourier convention of the package: w(x) = sum_j K(x - x_j) p_j cell, K = (2 pi)^-2 int H e^{ik.x}
d^2k.)  The padded operator's symbol is the discrete Fourier transform of these cell
coefficients; nodes outside the box are excluded from the contact (infinite height).  Lengths in
h, the core's units (``Film``'s symbols).
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.special import j0, j1

from ..physics.film import Film
from .fft import get_rfft
from .grid import Grid
from .operators import FourierOperator

__all__ = ["OpenOperator", "open_compliance_operator", "half_space_limits", "open_grid",
           "box_of"]

_K_MAX = 60.0      # [1/h]: the remainders decay as exp(-2 k h) (e^-120 there)
_PANELS = 80       # Gauss-Legendre panels of 16 nodes over [0, _K_MAX] (r up to ~4 h)
_ORDER = 16
_TABLE = 2049      # r-table points for the smooth kernels (smooth on the scale of h)


def half_space_limits(film: Film) -> tuple:
    """(F0(inf), F1(inf)): the symbol's half-space limits, |k| H -> [F0 + i mu n_x F1] / 2."""
    F0, F1 = film._F0_F1(np.array([200.0 / film.thickness]))
    return float(F0[0]), float(F1[0])


@lru_cache(maxsize=16)
def _smooth_tables(film: Film, rmax: float):
    """(r, K_even(r), K_odd(r)) on [0, rmax] (lengths in the film's unit)."""
    F0i, F1i = half_space_limits(film)
    x, w = np.polynomial.legendre.leggauss(_ORDER)
    edges = np.linspace(0.0, _K_MAX / film.thickness, _PANELS + 1)
    half = 0.5 * np.diff(edges)
    k = (edges[:-1, None] + half[:, None] * (x[None, :] + 1.0)).ravel()
    wk = (half[:, None] * w[None, :]).ravel()
    F0, F1 = film._F0_F1(k)
    g0 = wk * 0.5 * (np.asarray(F0, dtype=float) - F0i)
    g1 = wk * 0.5 * (np.asarray(F1, dtype=float) - F1i)
    r = np.linspace(0.0, rmax, _TABLE)
    ke = np.empty_like(r)
    ko = np.empty_like(r)
    for s in range(0, r.size, 256):  # blocks: bounded memory
        kr = np.outer(r[s:s + 256], k)
        ke[s:s + 256] = j0(kr) @ g0
        ko[s:s + 256] = -(j1(kr) @ g1)
    return r, ke / (2 * math.pi), ko / (2 * math.pi)


def _love(x1, x2, y1, y2):
    """Integral of 1/sqrt(x^2 + y^2) over the rectangle [x1, x2] x [y1, y2]."""
    def F(x, y):
        # x asinh(y/|x|) + y asinh(x/|y|) (= x ln(y + r) + y ln(x + r) up to constants)
        a = np.where(x != 0, x * np.arcsinh(np.divide(y, np.abs(x), where=x != 0,
                                                      out=np.zeros_like(x))), 0.0)
        b = np.where(y != 0, y * np.arcsinh(np.divide(x, np.abs(y), where=y != 0,
                                                      out=np.zeros_like(y))), 0.0)
        return a + b
    return F(x2, y2) - F(x1, y2) - F(x2, y1) + F(x1, y1)


def _odd(x1, x2, y1, y2):
    """Integral of x / (x^2 + y^2) over the rectangle [x1, x2] x [y1, y2]."""
    def G(x, y):
        r2 = x * x + y * y
        with np.errstate(divide="ignore", invalid="ignore"):
            a = np.where(r2 > 0, 0.5 * y * np.log(np.where(r2 > 0, r2, 1.0)), 0.0)
            b = np.where(x != 0, x * np.arctan(np.divide(y, x, where=x != 0,
                                                         out=np.zeros_like(x))), 0.0)
        return a - y + b
    return G(x2, y2) - G(x1, y2) - G(x2, y1) + G(x1, y1)


def _coefficients(shape, spacing, mu: float, film: Film) -> np.ndarray:
    """The cell coefficients C[offset] (w_i = sum_j C[i - j] p_j) on the padded grid of
    ``shape`` (twice the box per axis), offsets in numpy's FFT order."""
    (nx, ny), (dx, dy) = shape, spacing
    ox = np.fft.fftfreq(nx, 1.0 / nx) * dx  # offsets -nx/2 dx ... (nx/2 - 1) dx
    oy = np.fft.fftfreq(ny, 1.0 / ny) * dy
    X, Y = np.meshgrid(ox, oy, indexing="ij")
    F0i, F1i = half_space_limits(film)
    C = (0.5 * F0i / (2 * math.pi)) * _love(X - dx / 2, X + dx / 2, Y - dy / 2, Y + dy / 2)
    if mu != 0.0 and F1i != 0.0:
        C -= mu * (0.5 * F1i / (2 * math.pi)) * _odd(X - dx / 2, X + dx / 2, Y - dy / 2,
                                                     Y + dy / 2)
    R = np.hypot(X, Y)
    r, ke, ko = _smooth_tables(film, 2.0 ** math.ceil(math.log2(float(R.max()) * 1.001 + 1e-9)))
    C += np.interp(R, r, ke) * (dx * dy)
    if mu != 0.0:
        with np.errstate(invalid="ignore", divide="ignore"):
            cos = np.where(R > 0, X / np.where(R > 0, R, 1.0), 0.0)
        C += mu * cos * np.interp(R, r, ko) * (dx * dy)
    return C


class OpenOperator(FourierOperator):
    """The film's compliance for an isolated contact inside the central box of a padded grid
    (``open_grid``): ``symbol`` is the DFT of the cell coefficients; the preconditioner's
    clipped part uses the film's continuous symbol (as ``FourierOperator``)."""

    def __init__(self, grid: Grid, mu: float, film: Film, constant: complex = 0.0,
                 symbol: np.ndarray | None = None):
        super().__init__(grid, film.compliance_symbol(mu), constant)
        self.mu, self.film = mu, film
        if symbol is None:
            C = _coefficients(grid.shape, grid.spacing, mu, film)
            symbol = get_rfft(grid.shape).forward(C)
            if mu == 0.0:
                symbol = symbol.real.astype(complex)
        self._base = symbol
        self._symbol = symbol + constant if constant else symbol

    def __add__(self, c) -> OpenOperator:
        return OpenOperator(self.grid, self.mu, self.film, self.constant + c, self._base)

    __radd__ = __add__


@lru_cache(maxsize=8)
def open_compliance_operator(shape: tuple, lengths: tuple, mu: float, film: Film = Film()
                             ) -> OpenOperator:
    """``OpenOperator`` on the padded grid of ``shape`` over ``lengths`` (cached)."""
    return OpenOperator(Grid(shape, lengths), float(mu), film)


def open_grid(box_shape, box_lengths, center) -> Grid:
    """The padded grid (twice the box's points and lengths per axis) centred on ``center``."""
    return Grid.centered(tuple(2 * n for n in box_shape), tuple(2.0 * L for L in box_lengths),
                         center)


def box_of(grid: Grid):
    """Slices of the padded grid's nodes inside its box (the central half per axis)."""
    return tuple(slice(n // 4, n // 4 + n // 2) for n in grid.shape)
