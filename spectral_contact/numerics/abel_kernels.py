"""Wavenumber integrals of the paper's Abel formulation (kernels M_ij, Z_1..Z_6, a-posteriori).

Every kernel is an integral over k in [0, inf) of a transfer function (F0 - 1, F1: decay like
k^2 exp(-2k); A, B, C: like k exp(-k)) times Bessel / trigonometric factors that oscillate with
frequency up to |x| + |t|.  They are evaluated with a fixed, vectorised composite Gauss-Legendre
rule in k (panels no wider than a fraction of the oscillation period, truncated where the
exponential factor is below 1e-17 of its peak), so that a whole kernel matrix is one matrix
product.  Accuracy against adaptive scipy.integrate.quad: ~1e-13 absolute (tests/test_abel.py).

Speed (issue 13): a rule depends only on kmax and its panel count, so rules and the film's
transfer functions on them are tabulated once (``k_rule``, ``film_on_rule``); J0(kt), J1(kt)
have bandwidth max|t| in k and are evaluated on panels several times wider than the rule's and
interpolated (``bessel_on_rule``); sums over k of cos(kx), sin(kx) factor through the equal
panels (``cos_sin_sums``).  Each agrees with the direct evaluation to ~1e-14
(tests/test_abel_fast.py).

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

import math
from functools import lru_cache

import numpy as np
from scipy.special import j0, j1

from ..physics.transfer import F0_minus_1, transfer_functions

__all__ = [
    "KMAX_M", "KMAX_Z", "KRule", "k_rule", "film_on_rule", "bessel_on_rule", "cos_sin_sums", "m_kernels",
    "z_kernels", "aposteriori_kernels", "legendre_log_weights", "gauss_legendre",
]

KMAX_M = 26.0  # k^3 exp(-2k) < 1e-17 beyond
KMAX_Z = 46.0  # k exp(-k) < 1e-17 beyond
_PANEL_POINTS = 20
_INTERP_POINTS = 30  # Gauss nodes of an interpolation panel (bessel_on_rule) ...
_INTERP_PHASE = 12.0  # ... and the largest phase across one (error < 2e-15 up to 15)


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


class KRule(tuple):
    """A composite Gauss-Legendre rule ``(k, wk)`` (unpacks as that pair) that remembers its
    panels: ``key = (kmax, n_panels, points)``, all that it depends on."""

    key: tuple


@lru_cache(maxsize=64)
def _panel_rule(kmax: float, n_panels: int, points: int) -> KRule:
    edges = np.linspace(0.0, kmax, n_panels + 1)
    s, w = _leggauss(int(points))
    half = 0.5 * np.diff(edges)
    k = (edges[:-1, None] + half[:, None] * (s[None, :] + 1.0)).ravel()
    wk = (half[:, None] * w[None, :]).ravel()
    k.setflags(write=False)
    wk.setflags(write=False)
    rule = KRule((k, wk))
    rule.key = (kmax, n_panels, points)
    return rule


def k_rule(kmax: float, omega: float, points: int = _PANEL_POINTS, max_width: float = 1.0):
    """Composite Gauss-Legendre rule on [0, kmax] for integrands oscillating at frequency omega.

    Panels are at most ``max_width`` wide and at most one period 2 pi / omega wide (20 points per
    period: Gauss-Legendre resolves that to machine precision).  Returns a ``KRule`` (the pair
    (k, wk), read-only arrays), cached: it depends only on kmax and the panel count.
    """
    width = min(max_width, 2.0 * np.pi / max(float(omega), 1e-300))
    n_panels = int(np.ceil(kmax / width))
    return _panel_rule(float(kmax), n_panels, int(points))


def _rule(rule, kmax, *lengths):
    if rule is not None:
        return rule
    omega = sum(float(np.max(np.abs(v))) if np.size(v) else 0.0 for v in lengths)
    return k_rule(kmax, omega)


@lru_cache(maxsize=64)
def _film_on_rule(key: tuple):
    """The film's transfer functions on a cached rule: (F0 - 1, F1, A, B, C), read-only."""
    k = _panel_rule(*key)[0]
    _, F1_, A_, B_, C_ = transfer_functions(k)
    out = (F0_minus_1(k), F1_, A_, B_, C_)
    for v in out:
        v.setflags(write=False)
    return out


def film_on_rule(rule):
    """(F0 - 1, F1, A, B, C) at the rule's nodes (tabulated once per rule: they depend only on
    the film and the rule, not on the contact)."""
    key = getattr(rule, "key", None)
    if key is not None:
        return _film_on_rule(key)
    k = rule[0]
    _, F1_, A_, B_, C_ = transfer_functions(k)
    return F0_minus_1(k), F1_, A_, B_, C_


def _cis(theta):
    """exp(i theta) from cos and sin (numpy's complex exp is several times slower)."""
    out = np.empty(theta.shape, complex)
    out.real = np.cos(theta)
    out.imag = np.sin(theta)
    return out


@lru_cache(maxsize=64)
def _panel_interpolation(points: int, r: int, source: int) -> np.ndarray:
    """Matrix (r * points, source): values at the ``points`` Gauss nodes of each of the r equal
    sub-panels of a panel from the values at the panel's own ``source`` Gauss nodes
    (barycentric Lagrange), read-only."""
    s, _ = _leggauss(source)
    u, _ = _leggauss(points)
    xt = (-1.0 + (2.0 * np.arange(r)[:, None] + u[None, :] + 1.0) / r).ravel()
    bw = np.array([1.0 / np.prod(s[i] - np.delete(s, i)) for i in range(source)])
    d = xt[:, None] - s[None, :]
    hit = d == 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        L = bw[None, :] / d
        L /= L.sum(axis=1, keepdims=True)
    rows = hit.any(axis=1)
    L[rows] = hit[rows].astype(float)  # a target on a node: that node's value
    L.setflags(write=False)
    return L


def bessel_on_rule(t, rule, v0=None, v1=None):
    """J0(k t), J1(k t) at the nodes k of ``rule`` (arrays (nk, nt)), or, given vectors v0, v1
    over t, the sums J0(k t) @ v0 and J1(k t) @ v1 (arrays (nk,)).

    As functions of k they have bandwidth max|t|: where that is small against the panel width,
    they are evaluated at the ``_INTERP_POINTS`` Gauss nodes of panels r times wider (phase of
    exp(i k max|t|) across one <= ``_INTERP_PHASE``) and interpolated to the rule's nodes by
    one fixed matrix (to ~1e-14 of max|J|, round-off: tests/test_abel_fast.py): r * 20 / 30 times
    fewer Bessel evaluations."""
    t = np.atleast_1d(np.asarray(t, float))
    key = getattr(rule, "key", None)
    tmax = float(np.max(np.abs(t), initial=0.0))
    r = 1
    if key is not None and tmax > 0.0:
        kmax, n_panels, points = key
        width = kmax / n_panels
        r = min(n_panels, int(_INTERP_PHASE / (tmax * width)))
    if r * points <= _INTERP_POINTS:  # (r = 1 included): direct evaluation is cheaper
        kt = np.outer(rule[0], t)
        J0, J1 = j0(kt), j1(kt)
        return (J0, J1) if v0 is None else (J0 @ v0, J1 @ v1)
    q = _INTERP_POINTS
    n_src = -(-n_panels // r)
    s, _ = _leggauss(q)
    ks = ((np.arange(n_src) * (r * width))[:, None] + (0.5 * r * width) * (s + 1.0)[None, :]).ravel()
    kt = np.outer(ks, t)
    J0, J1 = j0(kt), j1(kt)
    if v0 is not None:
        J0, J1 = J0 @ v0, J1 @ v1
    L = _panel_interpolation(points, r, q)
    nk = n_panels * points

    def up(A):
        B = np.matmul(L, A.reshape(n_src, q, -1))  # (n_src, r * points, m)
        return B.reshape((n_src * r * points,) + A.shape[1:])[:nk]

    return up(J0), up(J1)


def cos_sin_sums(x, rule, pairs, chunk: int = 1024):
    """``sum_k gc(k) cos(k x) + gs(k) sin(k x)`` at every x, for each (gc, gs) in ``pairs``
    (arrays on the nodes of ``rule``, a ``KRule``); returns a list of arrays shaped like x.

    The panels are equal: node (p, j) is k = p W + u_j (W the panel width, u_j the offset
    within a panel), so exp(i k x) = exp(i p W x) exp(i u_j x) and the sum is a matrix product
    between the two factors; exp(i p W x) is itself exp(i b B W x) exp(i c W x) with
    p = b B + c, B ~ sqrt(panels).  That is ~(points + 2 sqrt(panels)) cosines and sines per x
    instead of panels x points.  Same sums to round-off (phases k x are rounded either way)."""
    x = np.atleast_1d(np.asarray(x, float))
    kmax, n_panels, points = rule.key
    width = kmax / n_panels
    s, _ = _leggauss(points)
    u = 0.5 * width * (s + 1.0)
    npair = len(pairs)
    B = max(1, int(math.ceil(math.sqrt(n_panels))))
    nb = -(-n_panels // B)
    # G[j, (m, p)] = (gc - i gs) of pair m at node (p, j)
    G = np.stack([(np.asarray(gc) - 1j * np.asarray(gs)).reshape(n_panels, points)
                  for gc, gs in pairs]).transpose(2, 0, 1).reshape(points, npair * n_panels)
    out = np.empty((npair, x.size))
    for lo in range(0, x.size, chunk):  # bounded memory
        xc = x[lo:lo + chunk]
        inner = (_cis(np.outer(xc, u)) @ G).reshape(xc.size, npair, n_panels)
        coarse = _cis(np.outer(xc, (B * width) * np.arange(nb)))
        fine = _cis(np.outer(xc, width * np.arange(B)))
        outer = (coarse[:, :, None] * fine[:, None, :]).reshape(xc.size, nb * B)[:, :n_panels]
        out[:, lo:lo + chunk] = np.einsum("xmp,xp->mx", inner, outer).real
    return [o.reshape(x.shape) for o in out]


def m_kernels(x, t, rule=None, bessel=None):
    """(M00, M01, M10, M11) at all pairs (x_i, t_j); each of shape (len(x), len(t)).
    ``bessel``: (J0(k t), J1(k t)) on the rule, if already computed (``bessel_on_rule``)."""
    x = np.atleast_1d(np.asarray(x, float))
    t = np.atleast_1d(np.asarray(t, float))
    rule = _rule(rule, KMAX_M, x, t)
    k, wk = rule
    F0m1, F1_, _, _, _ = film_on_rule(rule)
    J0t, J1t = bessel if bessel is not None else bessel_on_rule(t, rule)
    if x.shape == t.shape and np.array_equal(x, t):  # the Nystrom matrix: x = t
        J0x, J1x = J0t, J1t
    else:
        J0x, J1x = bessel_on_rule(x, rule)
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
    rule = _rule(rule, KMAX_Z, x, t)
    k, wk = rule
    _, _, A_, B_, C_ = film_on_rule(rule)
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


def aposteriori_kernels(t, rule=None, bessel=None):
    """The t-only kernels of the x0 and 1/alpha equations (see module docstring).
    ``bessel``: (J0(k t), J1(k t)) on the rule, if already computed (``bessel_on_rule``)."""
    t = np.atleast_1d(np.asarray(t, float))
    rule = _rule(rule, KMAX_M, t)
    k, wk = rule
    F0m1, F1_, _, _, _ = film_on_rule(rule)
    J0, J1 = bessel if bessel is not None else bessel_on_rule(t, rule)
    J0t, J1t = J0.T, J1.T
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
