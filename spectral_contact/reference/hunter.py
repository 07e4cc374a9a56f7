"""Hunter's problem in closed form: a rigid cylinder sliding (rolling, frictionless) at steady
speed V on a standard-linear-solid incompressible half-space (issue 23).

Source.  Hunter, S. C., "The rolling contact of a rigid cylinder with a viscoelastic half
space", J. Appl. Mech. 28 (1961) 611-617, solved this problem by reduction to a Riemann-Hilbert
problem.  His formulas were not found in the sources searched here (web pages, documentation
and code corpora); the solution below was DERIVED for this package, along the route the paper
is known for (first-order ODE on the contact + the elastic finite Hilbert problem), and is
independent of the spectral solver and of ``reference.sls_halfspace`` (the x-space collocation
of the same problem, against which it is checked in ``tests/test_hunter.py``).

Units and model as ``reference.sls_halfspace``: lengths L, the indenter f = x^2 (displacements
in L^2/2R), stresses G_inf L/2R, loads G_inf L^2/2R; relaxed compliance symbol 1/(2|k|); one
Prony term with r = E_inf/E_0, l = V tau, l_r = V tau_r = l / r (V > 0: the indenter moves
toward +x).  The sinking s = K * p has the symbol R(k)/(2|k|), R = (1 - i k l)/(1 - i k l_r),
so with D = d/dx and s_e the relaxed elastic sinking of the same pressure,

    (1 - l_r D) s = (1 - l D) s_e          everywhere,                       (i)
    s = d - x^2                            on the contact (b1, b2).          (ii)

Derivation.
1.  (i)-(ii) on the contact: (1 - l D) s_e = d - x^2 + 2 l_r x, whose solutions have
    s_e' = -2x + 2(l_r - l) + C exp((x - b2)/l), C a free constant.
2.  The elastic finite Hilbert problem s_e'(x) = -(1/2 pi) PV Int p(s)/(x - s) ds on
    (b1, b2) = (c - a, c + a), x = c + a xi: with the Chebyshev expansion
    exp(beta xi) = I_0(beta) + 2 sum_{n>=1} I_n(beta) T_n(xi), beta = a/l, and
    PV Int T_n(t) / (sqrt(1 - t^2) (t - xi)) dt = pi U_{n-1}(xi), the solution bounded at both
    ends (the glassy response is elastic: square-root edges) is

        p = sqrt(1 - xi^2) [4a - 4 C sum_{n>=1} e^{-beta} I_n(beta) U_{n-1}(xi)],

    solvable iff C e^{-beta} I_0(beta) = 2 (c - (l_r - l))                      (1)
    with the load   P = 2 pi a^2 - 2 pi a C e^{-beta} I_1(beta)                   (2)
    and the centroid  x_bar = c - pi a^2 C e^{-beta} I_2(beta) / P.
3.  (i) alone leaves s = d - x^2 + A exp(x / l_r) on the contact; (ii) needs A = 0, i.e. the
    sinking at the leading edge, which remembers the material's path ahead of the contact
    (s(x) = Int_0^inf e^{-u} [(1 - l D) s_e](x + l_r u) du), equals d - b2^2.  With s_e on the
    contact from step 1 and s_e' beyond the leading edge from the Cauchy transform
    Int sqrt(1 - t^2) U_m(t)/(eta - t) dt = pi rho^(m+1), rho = eta - sqrt(eta^2 - 1):
    s_e'(c + a eta) = -2 a rho + 2 C sum_{n>=1} e^{-beta} I_n(beta) rho^n for eta > 1, this is

        2 (l_r - l)(b2 + l) + C l + (l_r - l) J = 0,                              (3)
        J = Int_0^inf e^{-u} s_e'(b2 + l_r u) du   (one quadrature: u = t^2, smooth in t).

For a given a, (1) and (3) are linear in (c, C); (2) then sets a (one transcendental equation,
bracketed between the glassy and relaxed Hertz half-widths).  The ends b2 = c + a and
b1 = c - a are thus set by the two transcendental conditions (2) and (3).  Checks (tests): the
elastic limits (l -> 0 and l -> inf: Hertz with E_inf and E_0), p >= 0, continuity of s_e' at
the leading edge, and the x-space collocation within its O(dx) error.

mu_def.  Int p df/dx / P with f = x^2/(2R) is x_bar / R: in the package's core units (lengths
in h) mu_def = (h/R) x_bar.

Where it applies to a bonded film of thickness h.  Hunter's half-space is the film's limit when
both the contact and the relaxation tail are thin compared with the film: a << h AND l_r =
V tau_r << h.  The film's kernel differs from the half-space's by a smooth part, constant +
O(s^2/h^2) at distances s << h: the constant goes into d, the rest changes a by O((a/h)^2) and,
through the tail's memory over l_r, the offset and mu_def by O((l_r/h)^2).  Measured
(studies/README, viscoelastic; tests/test_hunter.py), film against this closed form at a_H/h
= 0.01, 0.003, 0.001 with l_r = 14 a_H (the same a and l_r on thicker films): mu_def off by
1.1e-2, 9.0e-4, 2.4e-5 at l_r/h = 0.14, 0.042, 0.014 (0.56, 0.51, 0.12 (l_r/h)^2): the film
converges to Hunter as h grows.  So Hunter holds within 0.5 % on a, x_c and mu_def for a/h <=
0.01 and l_r <= ~0.1 h (0.5 % interpolated at l_r = 0.096 h), within 1e-3 for l_r <= 0.04 h;
beyond, the difference is the film's finite thickness, not Hunter's regime.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import ive

__all__ = ["hunter_contact"]


def _bessel(beta: float) -> np.ndarray:
    """e^{-beta} I_n(beta), n = 0 ... N, N enough that the rest is below 1e-17 of I_0."""
    n_max = int(beta + 12.0 * math.sqrt(beta + 1.0) + 30.0)
    return ive(np.arange(n_max + 1), beta)


def _solve_for_a(a: float, r: float, lr: float):
    """(c, C, bessel) from conditions (1) and (3) at half-width a."""
    ll = r * lr
    beta = a / ll
    b = _bessel(beta)
    lam = a / lr  # eta = 1 + u lr / a = 1 + u / lam

    def rho(t):
        u = t * t
        eta = 1.0 + u / lam
        return 1.0 / (eta + math.sqrt(max(eta * eta - 1.0, 0.0)))  # eta - sqrt(eta^2 - 1)

    n = np.arange(1, b.size)

    def series(t):
        return float(np.dot(b[1:], rho(t) ** n))

    # J = -2 a M + 2 C T, M = Int e^-u rho du, T = Int e^-u S(rho) du (u = t^2, du = 2 t dt)
    # the integrands vary on t ~ sqrt(lam) (rho from 1 to 0) and, near rho = 1, on
    # t ~ sqrt(lam) / beta (the series' terms up to n ~ beta): breakpoints there
    pts = sorted({min(max(v, 1e-12), 8.0) for v in (math.sqrt(lam) / max(beta, 1.0),
                                                   math.sqrt(lam), 3.0 * math.sqrt(lam))})
    kw = {"epsabs": 1e-15, "epsrel": 1e-12, "limit": 400, "points": pts}
    M = quad(lambda t: 2.0 * t * math.exp(-t * t) * rho(t), 0.0, 9.0, **kw)[0]
    T = quad(lambda t: 2.0 * t * math.exp(-t * t) * series(t), 0.0, 9.0, **kw)[0]
    # (1): C = 2 (c - dl) / b0, dl = lr - l.  (3): 2 dl (c + a + l) + C l + dl (-2 a M + 2 C T) = 0
    dl = lr - ll
    k = 2.0 / b[0]  # C = k c - k dl
    # linear in c: 2 dl c + (l + 2 dl T) (k c - k dl) + 2 dl (a + l) - 2 dl a M = 0
    A = 2.0 * dl + (ll + 2.0 * dl * T) * k
    B = -(ll + 2.0 * dl * T) * k * dl + 2.0 * dl * (a + ll) - 2.0 * dl * a * M
    c = -B / A
    C = k * (c - dl)
    return c, C, b


def _load(a, C, b):
    return 2.0 * math.pi * a * a - 2.0 * math.pi * a * C * b[1]


def hunter_contact(P: float, r: float, lr: float, n_profile: int = 401) -> dict:
    """Steady frictionless sliding of f = x^2 toward +x on the SLS half-space, closed form.

    P : load (core units, > 0); r = E_inf/E_0 in (0, 1); lr = l_r = V tau_r (> 0, lengths).
    Returns dict: a (half-width), c (contact centre in the apex frame: the package's x_c),
    edges (b1, b2), centroid (x_bar: mu_def = (h/R) centroid), C, x and p (the pressure on
    n_profile points of the contact), p_min_interior (min of p / p_max inside the contact,
    >= 0 for a valid solution)."""
    if not (P > 0.0 and 0.0 < r < 1.0 and lr > 0.0):
        raise ValueError("hunter_contact: needs P > 0, 0 < r < 1, lr > 0")

    def resid(a):
        c, C, b = _solve_for_a(a, r, lr)
        return _load(a, C, b) - P

    a_relaxed = math.sqrt(P / (2.0 * math.pi))
    a_glassy = a_relaxed * math.sqrt(r)
    a = brentq(resid, 0.98 * a_glassy, 1.02 * a_relaxed, xtol=1e-15 * a_relaxed, rtol=1e-15,
               maxiter=200)
    c, C, b = _solve_for_a(a, r, lr)
    centroid = c - math.pi * a * a * C * b[2] / P
    xi = np.cos(np.linspace(math.pi, 0.0, n_profile))
    theta = np.arccos(np.clip(xi, -1.0, 1.0))
    s = np.sin(theta)
    nn = np.arange(1, b.size)
    with np.errstate(invalid="ignore", divide="ignore"):
        U = np.where(s[:, None] > 1e-12, np.sin(np.outer(theta, nn)) / s[:, None],
                     np.where(xi[:, None] > 0, nn[None, :], nn[None, :] * (-1.0) ** (nn[None, :] - 1)))
    p = np.sqrt(np.maximum(1.0 - xi * xi, 0.0)) * (4.0 * a - 4.0 * C * (U @ b[1:]))
    inner = np.abs(xi) < 1.0
    return {"a": a, "c": c, "edges": (c - a, c + a), "centroid": centroid, "C": C,
            "x": c + a * xi, "p": p,
            "p_min_interior": float(np.min(p[inner]) / np.max(p))}
