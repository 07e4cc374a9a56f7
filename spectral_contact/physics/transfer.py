"""Transfer functions of the bonded incompressible film (the paper's Eqs. f0, f1, ak, bk, ck).

All functions take the dimensionless wavenumber k (in units of 1/h) and are even in k: they are
evaluated at |k|.  Written with exp(-2|k|) so they neither overflow at large k (the textbook forms
overflow past k ~ 350) nor cancel near k = 0 (sinh 2k - 2k is summed as a series there).

    D  = cosh 2k + 1 + 2k^2
    F0 = (sinh 2k - 2k) / D      -> 1 as k -> inf,   ~ 2k^3/3 as k -> 0
    F1 = 2k^2 / D                -> 0,               ~ k^2
    A  = 2(cosh k + k sinh k)/D  -> 0,               -> 1
    B  = 2k cosh k / D           -> 0,               ~ k
    C  = 2(cosh k - k sinh k)/D  -> 0,               -> 1

F0, F1 give the surface compliance; A, B, C carry surface tractions to the rigid base (z = 0).
"""
from __future__ import annotations

import numpy as np

__all__ = ["transfer_functions", "F0", "F0_minus_1", "F2", "tanh_over"]

_SERIES_MAX = 1.0  # |2k| below which sinh(2k) - 2k is summed as a series


def _sinh_minus_x(x: np.ndarray) -> np.ndarray:
    """sinh(x) - x without cancellation (x >= 0)."""
    out = np.empty_like(x)
    small = x < _SERIES_MAX
    xs = x[small]
    x2 = xs * xs
    term = xs**3 / 6.0
    acc = term.copy()
    for n in range(1, 12):  # x < 1: 11 terms reach 1e-17 relative
        term = term * x2 / ((2 * n + 2) * (2 * n + 3))
        acc += term
    out[small] = acc
    xl = x[~small]
    out[~small] = np.sinh(xl) - xl  # only used for x >= 1 here, where exp(-x) is finite
    return out


def _scaled(k):
    """k = |k| as float array, e2 = exp(-2k), and Dp = 2 exp(-2k) D (never overflows)."""
    # beyond 1e100 every exponential has underflowed: clip so that k * exp(-k) stays 0, not nan
    k = np.minimum(np.abs(np.asarray(k, dtype=float)), 1e100)
    e2 = np.exp(-2.0 * k)
    Dp = 1.0 + e2 * e2 + 2.0 * e2 * (1.0 + 2.0 * k * k)
    return k, e2, Dp


def _F0_scaled_numerator(k, e2):
    """2 exp(-2k) (sinh 2k - 2k)."""
    num = np.empty_like(k)
    small = 2.0 * k < _SERIES_MAX
    num[small] = 2.0 * e2[small] * _sinh_minus_x(2.0 * k[small])
    kl, el = k[~small], e2[~small]
    num[~small] = 1.0 - el * el - 4.0 * kl * el
    return num


def transfer_functions(k):
    """Return (F0, F1, A, B, C) at wavenumbers k (array-like, units 1/h)."""
    k, e2, Dp = _scaled(k)
    e1 = np.exp(-k)
    F0_ = _F0_scaled_numerator(k, e2) / Dp
    F1_ = 4.0 * k * k * e2 / Dp
    A_ = 2.0 * e1 * ((1.0 + k) + (1.0 - k) * e2) / Dp
    B_ = 2.0 * k * e1 * (1.0 + e2) / Dp
    C_ = 2.0 * e1 * ((1.0 - k) + (1.0 + k) * e2) / Dp
    return F0_, F1_, A_, B_, C_


def F0(k):
    k, e2, Dp = _scaled(k)
    return _F0_scaled_numerator(k, e2) / Dp


def F0_minus_1(k):
    """F0(k) - 1 without cancellation at large k (decays like -2(1 + 2k + 2k^2) exp(-2k))."""
    k, e2, Dp = _scaled(k)
    return -2.0 * e2 * (e2 + 1.0 + 2.0 * k + 2.0 * k * k) / Dp


def F2(k):
    """F2 = (sinh 2k + 2k) / D: the tangential-tangential surface compliance of the sagittal
    problem (physics3d.md): -> 1 as k -> inf, ~ 2k as k -> 0."""
    k, e2, Dp = _scaled(k)
    return (1.0 - e2 * e2 + 4.0 * k * e2) / Dp


def tanh_over(k):
    """tanh(k) / k, with its limit 1 at k = 0 (the anti-plane compliance times 1/h)."""
    k = np.abs(np.asarray(k, dtype=float))
    e2 = np.exp(-2.0 * k)
    safe = np.where(k > 0, k, 1.0)
    return np.where(k > 1e-8, (1.0 - e2) / ((1.0 + e2) * safe), 1.0 - k * k / 3.0)
