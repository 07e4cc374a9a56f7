"""Wavenumber integrals of the paper's Abel formulation (kernels M_ij, Z_1..Z_6, a-posteriori).

Every kernel is an integral over k in [0, inf) of a transfer function (F0 - 1, F1: decay like
k^2 exp(-2k); A, B, C: like k exp(-k)) times Bessel / trigonometric factors that oscillate with
frequency up to |x| + |t|.  They are evaluated with a fixed, vectorised composite Gauss-Legendre
rule in k (panels no wider than a fraction of the oscillation period, truncated where the
exponential factor is below 1e-17 of its peak), so that a whole kernel matrix is one matrix
product.  Accuracy against adaptive scipy.integrate.quad: ~1e-13 absolute (tests/test_abel.py).

Kernels (dimensionless, lengths in h):

    M_ij(x, t) = (-1)^j x^{1-j} t^i Int k (F_|i-j|(k) - delta_ij) J_i(kt) J_j(kx) dk
    Z1 = Int A cos(kx) J0(kt),  Z2 = Int B cos(kx) J1(kt),  Z3 = Int B sin(kx) J0(kt),
    Z4 = Int A sin(kx) J1(kt),  Z5 = Int C cos(kx) J0(kt),  Z6 = Int C sin(kx) J1(kt)

A-posteriori kernels (functions of t only) for x0 and 1/alpha:

    K_F1J0(t)    = Int F1 J0(kt) dk
    K_F0m1J1(t)  = Int (F0 - 1) J1(kt) dk      [Int F0 J1(kt) dk = 1/t + K_F0m1J1(t)]
    L_rem(t)     = Int (F0 - 1 + exp(-2k)) / (2k) J0(kt) dk
                   [Int F0/(2k) J0(kt) dk = L_rem(t) + asinh(2/t)/2: the log singularity at t = 0
                    is split off analytically, Int (1 - e^{-2k}) J0(kt)/k dk = asinh(2/t)]
    K_F1J1_2k(t) = Int F1/(2k) J1(kt) dk
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.special import j0, j1

from ..physics.transfer import F0_minus_1, transfer_functions

__all__ = [
    "KMAX_M", "KMAX_Z", "k_rule", "m_kernels", "z_kernels", "aposteriori_kernels",
    "legendre_log_weights", "gauss_legendre",
]

KMAX_M = 26.0  # k^3 exp(-2k) < 1e-17 beyond
KMAX_Z = 46.0  # k exp(-k) < 1e-17 beyond
_PANEL_POINTS = 20


@lru_cache(maxsize=64)
def _leggauss(n: int):
    s, w = np.polynomial.legendre.leggauss(n)
    s.setflags(write=False)
    w.setflags(write=False)
    return s, w


def gauss_legendre(n: int, lo: float = -1.0, hi: float = 1.0):
    """n-point Gauss-Legendre nodes and weights on [lo, hi]."""
    s, w = _leggauss(int(n))
    half = 0.5 * (hi - lo)
    return lo + half * (s + 1.0), half * w


def k_rule(kmax: float, omega: float, points: int = _PANEL_POINTS, max_width: float = 1.0):
    """Composite Gauss-Legendre rule on [0, kmax] for integrands oscillating at frequency omega.

    Panels are at most ``max_width`` wide and at most one period 2 pi / omega wide (20 points per
    period: Gauss-Legendre resolves that to machine precision).
    """
    width = min(max_width, 2.0 * np.pi / max(float(omega), 1e-300))
    n_panels = int(np.ceil(kmax / width))
    edges = np.linspace(0.0, kmax, n_panels + 1)
    s, w = _leggauss(int(points))
    half = 0.5 * np.diff(edges)
    k = (edges[:-1, None] + half[:, None] * (s[None, :] + 1.0)).ravel()
    wk = (half[:, None] * w[None, :]).ravel()
    return k, wk


def _rule(rule, kmax, *lengths):
    if rule is not None:
        return rule
    omega = sum(float(np.max(np.abs(v))) if np.size(v) else 0.0 for v in lengths)
    return k_rule(kmax, omega)


def m_kernels(x, t, rule=None):
    """(M00, M01, M10, M11) at all pairs (x_i, t_j); each of shape (len(x), len(t))."""
    x = np.atleast_1d(np.asarray(x, float))
    t = np.atleast_1d(np.asarray(t, float))
    k, wk = _rule(rule, KMAX_M, x, t)
    _, F1_, _, _, _ = transfer_functions(k)
    F0m1 = F0_minus_1(k)
    kt = np.outer(k, t)
    J0t, J1t = j0(kt), j1(kt)
    if x.shape == t.shape and np.array_equal(x, t):  # the Nystrom matrix: x = t
        J0x, J1x = J0t, J1t
    else:
        kx = np.outer(k, x)
        J0x, J1x = j0(kx), j1(kx)
    g00 = (wk * k * F0m1)[:, None]
    g01 = (wk * k * F1_)[:, None]
    M00 = x[:, None] * ((J0x * g00).T @ J0t)
    M11 = -t[None, :] * ((J1x * g00).T @ J1t)
    M10 = (x[:, None] * t[None, :]) * ((J0x * g01).T @ J1t)
    M01 = -((J1x * g01).T @ J0t)
    return M00, M01, M10, M11


def z_kernels(x, t, rule=None):
    """Z1..Z6 at all pairs (x_i, t_j): array of shape (6, len(x), len(t))."""
    x = np.atleast_1d(np.asarray(x, float))
    t = np.atleast_1d(np.asarray(t, float))
    k, wk = _rule(rule, KMAX_Z, x, t)
    _, _, A_, B_, C_ = transfer_functions(k)
    kx, kt = np.outer(x, k), np.outer(k, t)
    cx, sx = np.cos(kx), np.sin(kx)
    J0t, J1t = j0(kt), j1(kt)
    out = np.empty((6, x.size, t.size))
    out[0] = (cx * (wk * A_)) @ J0t
    out[1] = (cx * (wk * B_)) @ J1t
    out[2] = (sx * (wk * B_)) @ J0t
    out[3] = (sx * (wk * A_)) @ J1t
    out[4] = (cx * (wk * C_)) @ J0t
    out[5] = (sx * (wk * C_)) @ J1t
    return out


def aposteriori_kernels(t, rule=None):
    """The t-only kernels of the x0 and 1/alpha equations (see module docstring)."""
    t = np.atleast_1d(np.asarray(t, float))
    k, wk = _rule(rule, KMAX_M, t)
    _, F1_, _, _, _ = transfer_functions(k)
    F0m1 = F0_minus_1(k)
    kt = np.outer(t, k)
    J0t, J1t = j0(kt), j1(kt)
    return {
        "K_F1J0": J0t @ (wk * F1_),
        "K_F0m1J1": J1t @ (wk * F0m1),
        "L_rem": J0t @ (wk * (F0m1 + np.exp(-2.0 * k)) / (2.0 * k)),
        "K_F1J1_2k": J1t @ (wk * F1_ / (2.0 * k)),
    }


@lru_cache(maxsize=64)
def legendre_log_weights(n: int):
    """Product-integration weights on the n Gauss-Legendre nodes s_j of [-1, 1]:

        Int_{-1}^{1} f(s) log((1 + s)/2) ds  ~=  sum_j W_j f(s_j)

    exact for polynomials f of degree < n (spectral for analytic f).  Uses
    Int P_0 log((1+s)/2) = -2 and Int P_m log((1+s)/2) = 2 (-1)^(m+1) / (m (m+1)) for m >= 1.
    """
    s, w = _leggauss(int(n))
    m = np.arange(n)
    Im = np.empty(n)
    Im[0] = -2.0
    mm = m[1:].astype(float)
    Im[1:] = 2.0 * (-1.0) ** (mm + 1) / (mm * (mm + 1.0))
    P = np.polynomial.legendre.legvander(s, n - 1)  # P[j, m] = P_m(s_j)
    # Legendre coefficients of f from node values: c_m = (2m+1)/2 sum_j w_j P_m(s_j) f_j
    W = (P * w[:, None]) @ ((2.0 * m + 1.0) / 2.0 * Im)
    W.setflags(write=False)
    return W
