"""An independent reference for issue 23: a rigid cylinder sliding (rolling, frictionless) at
steady speed on a standard-linear-solid incompressible half-space, solved by dense collocation
in x-space (no FFT, no film, no periodic grid).

Hunter (J. Appl. Mech. 28, 611-617, 1961) solved this problem in closed form; we did not find
his formulas in the sources at hand and use this numerical solution of the same problem instead
(stated as such in tests and studies).

Model (the package's core units: lengths L, displacements L^2/2R, stresses G_inf L/2R, so that
the indenter is f = x^2 and the relaxed half-space compliance is 1/(2|k|)).  One Prony term
E_1, tau: the symbol G_inf/G*(-k V) = (1 - i k l)/(1 - i k l_r), l = V tau, l_r = V tau_r,
tau_r = tau E_0/E_inf (``physics.viscoelastic``), i.e. in x-space

    w(x) = Int K(x - s) p(s) ds,
    K(x) = -(1/2 pi) [ r ln|x| + (1 - r) Int_0^inf exp(-t) ln|x + l_r t| dt ],   r = E_inf/E_0,

(the relaxing part of the kernel smeared behind the load over l_r).  With y = x/l_r the inner
integral is ln l_r + I(y), I(y) = ln|y| - e^y Ei(-y) (derived by parts: d/dy[e^{-y} ln|y| -
Ei(-y)] = -e^{-y} ln|y|), whose antiderivatives are J(y) = y ln|y| - y + ln|y| - e^y Ei(-y) and
J2(y) = y^2/2 ln|y| - 3 y^2/4 + y ln|y| - y + ln|y| - e^y Ei(-y).

Discretisation: the pressure is piecewise linear (hat functions on a uniform grid of spacing
dx), collocated at the nodes; the influence of a hat is the second difference of the kernel's
second antiderivative over dx (exact).  The contact (p >= 0, gap >= 0, p gap = 0, Int p = P) is
found by a primal-dual active-set iteration on the dense system.  Edges: midway between the
outermost active node and its inactive neighbour (error <= dx/2).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.special import expi

__all__ = ["sls_halfspace_contact"]


def _eEi(y):
    """e^y Ei(-y), by the asymptotic series for |y| > 40 (no overflow)."""
    y = np.asarray(y, dtype=float)
    out = np.empty_like(y)
    big = np.abs(y) > 40.0
    small = ~big
    with np.errstate(over="ignore"):
        out[small] = np.exp(y[small]) * expi(-y[small])
    z = -y[big]
    s = np.zeros_like(z)
    term = np.ones_like(z)
    for n in range(12):
        s += term
        term = term * (n + 1) / z
    out[big] = s / z
    return out


def _G2_log(x):
    """Second antiderivative of ln|x| (0 at x = 0)."""
    x = np.asarray(x, dtype=float)
    ax = np.where(x == 0.0, 1.0, np.abs(x))
    return np.where(x == 0.0, 0.0, 0.5 * x * x * np.log(ax) - 0.75 * x * x)


def _G2_tail(x, lr):
    """Second antiderivative of ln(l_r) + I(x/l_r) in x: ln(l_r) x^2/2 + l_r^2 J2(x/l_r)."""
    y = np.asarray(x, dtype=float) / lr
    ay = np.where(y == 0.0, 1.0, np.abs(y))
    ln = np.log(ay)
    J2 = 0.5 * y * y * ln - 0.75 * y * y + y * ln - y + ln - _eEi(y)
    J2 = np.where(y == 0.0, -np.euler_gamma, J2)  # ln|y| - e^y Ei(-y) -> -gamma
    return 0.5 * math.log(lr) * np.asarray(x) ** 2 + lr * lr * J2


def _hat_influence(n, dx, r, lr):
    """m[j] = Int hat(u) K(j dx - u) du for j = -(n-1) ... n-1 (hat of half-width dx at 0)."""
    j = np.arange(-(n - 1), n) * dx

    def second_difference(G):
        return (G(j + dx) - 2.0 * G(j) + G(j - dx)) / dx

    m = r * second_difference(_G2_log)
    if r < 1.0:
        m = m + (1.0 - r) * second_difference(lambda x: _G2_tail(x, lr))
    return -m / (2.0 * math.pi)


def sls_halfspace_contact(P: float, r: float, lr: float, n: int = 1200, window=None,
                          max_outer: int = 100) -> dict:
    """Steady frictionless sliding of the indenter f = x^2 toward +x on the SLS half-space.

    P : load (core units); r = E_inf/E_0 in (0, 1]; lr = l_r = V tau_r (core lengths), > 0.
    n : nodes; window : (x_lo, x_hi) (default +-1.3 relaxed Hertz half-widths sqrt(P/2pi)).
    Returns dict with x, p, d, edges (lo, hi), a (half-width), c (contact centre, apex frame:
    the package's x_c = -x0), centroid (of p), mu_factor (= centroid: mu_def = (h/R) centroid in
    the package's units), outer (active-set steps)."""
    aH = math.sqrt(P / (2.0 * math.pi))
    lo, hi = window or (-1.3 * aH, 1.3 * aH)
    x = np.linspace(lo, hi, n)
    dx = x[1] - x[0]
    m = _hat_influence(n, dx, r, lr)
    idx = np.arange(n)
    M = m[(idx[:, None] - idx[None, :]) + (n - 1)]
    f = x * x
    active = np.abs(x) < 0.5 * aH
    d = 0.0
    p = np.zeros(n)
    outer = 0
    for outer in range(1, max_outer + 1):  # noqa: B007 (reported)
        A = np.flatnonzero(active)
        k = A.size
        S = np.zeros((k + 1, k + 1))
        S[:k, :k] = M[np.ix_(A, A)]
        S[:k, k] = -1.0
        S[k, :k] = dx  # hats: Int p = dx sum p_j (p = 0 at the window's ends)
        rhs = np.concatenate([-f[A], [P]])
        sol = np.linalg.solve(S, rhs)
        p = np.zeros(n)
        p[A] = sol[:k]
        d = sol[k]
        gap = f - d + M @ p
        new = (p > 0.0) | (~active & (gap < 0.0))
        new &= ~(active & (p <= 0.0))
        if np.array_equal(new, active):
            break
        active = new
    else:
        raise RuntimeError("sls_halfspace_contact: active set did not settle")
    A = np.flatnonzero(active)
    if A[0] == 0 or A[-1] == n - 1:
        raise RuntimeError("sls_halfspace_contact: the contact reaches the window's end")
    e_lo, e_hi = x[A[0]] - 0.5 * dx, x[A[-1]] + 0.5 * dx
    centroid = float(np.sum(p * x) / np.sum(p))
    return {"x": x, "p": p, "d": d, "edges": (e_lo, e_hi), "a": 0.5 * (e_hi - e_lo),
            "c": 0.5 * (e_hi + e_lo), "centroid": centroid, "outer": outer, "dx": dx}
