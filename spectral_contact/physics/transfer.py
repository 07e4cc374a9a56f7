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

from functools import lru_cache

import numpy as np

__all__ = ["transfer_functions", "compliance_functions", "F0", "F0_minus_1", "F2", "tanh_over",
           "compressible_transfer_functions", "compressible_decay_rate",
           "compressible_tangential_function"]

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


def compliance_functions(k):
    """(F0, F1) of ``transfer_functions``, the same operations without the base transfers A,
    B, C (the surface compliance needs only these: a symbol on a grid, or at one |k| for each
    preconditioner's cut-off)."""
    k, e2, Dp = _scaled(k)
    return _F0_scaled_numerator(k, e2) / Dp, 4.0 * k * k * e2 / Dp


def F0(k):
    k, e2, Dp = _scaled(k)
    return _F0_scaled_numerator(k, e2) / Dp


def F0_minus_1(k):
    """F0(k) - 1 without cancellation at large k (decays like -2(1 + 2k + 2k^2) exp(-2k))."""
    k, e2, Dp = _scaled(k)
    return -2.0 * e2 * (e2 + 1.0 + 2.0 * k + 2.0 * k * k) / Dp


# --- the compressible film (0 <= nu < 1/2; physics3d.md) -------------------------------------
def compressible_transfer_functions(k, nu: float):
    """(F0, F1, A, B, Bp, C) of the bonded film of Poisson ratio ``nu`` (0 <= nu < 1/2) at
    wavenumbers k (units 1/h), in the normalisation of the incompressible ones:

        kappa = 3 - 4 nu,  D = kappa cosh 2k + 2k^2 + (1 + kappa^2)/2,
        F0 = 2(1 - nu)(kappa sinh 2k - 2k) / D           surface sinking per pressure x 2|k|/G
        F1 = 2 [k^2 - (1 - 2nu) kappa sinh^2 k] / D       its coupling to the shear, x 2|k|/G
        A  = 4(1 - nu)[2(1 - nu) cosh k + k sinh k] / D   base sigma_zz per surface sigma_zz
        B  = 4(1 - nu)[k cosh k + (1 - 2nu) sinh k] / D    base sigma_zz per i sgn(k) surface shear
        Bp = 4(1 - nu)[k cosh k - (1 - 2nu) sinh k] / D    base shear per i sgn(k) surface sigma_zz
        C  = 4(1 - nu)[2(1 - nu) cosh k - k sinh k] / D   base shear per surface shear

    At nu = 1/2 they are (F0, F1, A, B, B, C) of ``transfer_functions`` (which the film uses
    there: this form is for nu < 1/2).  Limits: F0 ~ (1 - 2nu) k / (1 - nu) as k -> 0 (a
    compressible film sinks under a uniform pressure), F0 -> 2(1 - nu) and
    F1 -> -(1 - 2nu) as k -> inf (the compressible half-space and its Dundurs coupling).
    Written with exp(-2k) like the incompressible ones (no overflow, no cancellation at k -> 0:
    kappa sinh 2k - 2k = (kappa - 1) sinh 2k + (sinh 2k - 2k))."""
    k = np.minimum(np.abs(np.asarray(k, dtype=float)), 1e100)
    nu = float(nu)
    kap = 3.0 - 4.0 * nu
    e1 = np.exp(-k)
    e2 = e1 * e1
    one_m_e2 = -np.expm1(-2.0 * k)          # 1 - exp(-2k)
    one_m_e4 = -np.expm1(-4.0 * k)          # 1 - exp(-4k)
    Dp = kap * (1.0 + e2 * e2) + (4.0 * k * k + 1.0 + kap * kap) * e2   # 2 exp(-2k) D
    F0_ = 2.0 * (1.0 - nu) * ((kap - 1.0) * one_m_e4 + _F0_scaled_numerator(k, e2)) / Dp
    F1_ = (4.0 * k * k * e2 - (1.0 - 2.0 * nu) * kap * one_m_e2 * one_m_e2) / Dp
    c = 4.0 * (1.0 - nu) * e1 / Dp
    cosh_ = 1.0 + e2                         # 2 exp(-k) cosh k
    sinh_ = one_m_e2                         # 2 exp(-k) sinh k
    A_ = c * (2.0 * (1.0 - nu) * cosh_ + k * sinh_)
    B_ = c * (k * cosh_ + (1.0 - 2.0 * nu) * sinh_)
    Bp_ = c * (k * cosh_ - (1.0 - 2.0 * nu) * sinh_)
    C_ = c * (2.0 * (1.0 - nu) * cosh_ - k * sinh_)
    return F0_, F1_, A_, B_, Bp_, C_


@lru_cache(maxsize=64)
def compressible_decay_rate(nu: float) -> float:
    """Slowest decay rate (in 1/h) of the kernels of a film of Poisson ratio ``nu``: the zero
    k = i y of D nearest the real axis, kappa cos 2y - 2y^2 + (1 + kappa^2)/2 = 0, unique on
    (0, pi/2) where the left side decreases from > 0 to (kappa - 1)^2/2 - pi^2/2 < 0 (kappa <= 3).
    (The other zeros of D have larger imaginary parts: checked by a complex Newton scan for
    nu in [0, 1/2].)  0.73909 at nu = 1/2 (cos y = y), 0.91278 at 0.3, 1.18962 at 0."""
    from scipy.optimize import brentq

    kap = 3.0 - 4.0 * float(nu)
    return float(brentq(lambda y: kap * np.cos(2.0 * y) - 2.0 * y * y + 0.5 * (1.0 + kap * kap),
                        0.0, 0.5 * np.pi, xtol=1e-15))


def compressible_tangential_function(k, nu: float):
    """F2 of the film of Poisson ratio ``nu``: the surface's tangential displacement along n per
    tangential traction along n is F2 / (2 G |k|) (physics3d.md: u_L^ = [F2 q_L - i F1 p^] /
    (2 G |k|), F1 of ``compressible_transfer_functions``), with

        F2 = 2(1 - nu)(kappa sinh 2k + 2k) / D     ((sinh 2k + 2k)/D at nu = 1/2),

    for the surface displacements of the 3D solver.  Limits: F2 -> 2(1 - nu) as k -> inf (the
    half-space), F2 / (2|k|) -> 1 (i.e. h/G per unit shear: a uniform shear q displaces the
    surface by q h / G) as k -> 0."""
    k = np.minimum(np.abs(np.asarray(k, dtype=float)), 1e100)
    nu = float(nu)
    kap = 3.0 - 4.0 * nu
    e2 = np.exp(-2.0 * k)
    Dp = kap * (1.0 + e2 * e2) + (4.0 * k * k + 1.0 + kap * kap) * e2   # 2 exp(-2k) D
    # 2 exp(-2k)(kappa sinh 2k + 2k) = kappa (1 - exp(-4k)) + 4k exp(-2k): no cancellation
    return 2.0 * (1.0 - nu) * (kap * -np.expm1(-4.0 * k) + 4.0 * k * e2) / Dp


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
