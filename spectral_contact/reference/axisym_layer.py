"""Frictionless rigid sphere on the bonded incompressible film: an axisymmetric reference.

An independent check of the 3D FFT solver (issue 10), as the Abel method is in 2D: the contact
of a sphere on the film reduced to a second-kind Fredholm equation on [0, a] (the classical
treatment of an indented layer: Sneddon's representation, Lebedev & Ufliand 1958), solved by
Gauss-Legendre Nystrom to the requested tolerance (default 1e-10; ~1e-13 reachable for
a <= 10 h) and cross-checked on a 2D periodic grid (tests).

Units (the package's dimensionless core, as in 2D but with a total force)
-------------------------------------------------------------------------
* lengths (r, a) in h, the film thickness;
* heights and displacements (indentation d, sinking w) in h^2/(2R): the sphere's height above its
  apex is f(r) = r^2 (paraboloid approximation of the sphere of radius R);
* stresses (p, sigma_zz) in G h/(2R) = E h/(6R), G = E/3 (incompressible film);
* force P = 6 R F / (E h^3) (F in N), i.e. F = P * G h^3/(2R).
Convert: a_m = a h, d_m = d h^2/(2R), p_Pa = p E h/(6R).
Signs: p >= 0 in compression (sigma_zz(r, h) = -p); the base stress sigma_zz(r, 0) < 0 in
compression, Int sigma_zz(r, 0) dA = -P.

The surface sinking w = -u_z (2D transforms, numpy's sign; physics3d.md)

    w^(k) = F0(|k|) / (2|k|) p^(k),     F0 = (sinh 2k - 2k) / (cosh 2k + 1 + 2k^2),

and the base stress sigma_zz^(k, 0) = -A(|k|) p^(k).  For an axisymmetric p the 2D transform is
p^(k) = 2 pi P~(k), P~(k) = Int_0^inf p(r) J0(kr) r dr (Hankel), and f(r) = Int_0^inf f~ J0(kr) k dk.

Formulation
-----------
Write the Hankel transform of the pressure through an auxiliary function g on [0, a]:

    P~(k) = Int_0^a g(t) cos(kt) dt,                                                        (1)

i.e. (Int_0^inf cos(kt) J0(kr) dk = 1/sqrt(r^2 - t^2) for t < r, 0 for t > r; Sonine's
Int_0^t r J0(kr)/sqrt(t^2 - r^2) dr = sin(kt)/k)

    p(r) = g(a)/sqrt(a^2 - r^2) - Int_r^a g'(t)/sqrt(t^2 - r^2) dt     (r < a),  0 beyond a.

The sinking is w(r) = (1/2) Int_0^inf F0(k) P~(k) J0(kr) dk.  Split F0 = 1 + (F0 - 1): the
half-space part is (1/2) Int_0^r g(t)/sqrt(r^2 - t^2) dt.  The contact condition
w(r) = d - r^2 (r < a) is an Abel equation; inverting it (J0(kr) <-> (2/pi) cos kt,
1 <-> 2/pi, r^2 <-> 4 t^2/pi, from Int_0^r cos(kt)/sqrt(r^2 - t^2) dt = (pi/2) J0(kr)) gives the
second-kind Fredholm equation

    g(t) + Int_0^a K(t, s) g(s) ds = (4/pi) (d - 2 t^2),        0 <= t <= a,                (2)
    K(t, s) = (2/pi) Int_0^inf (F0(k) - 1) cos(kt) cos(ks) dk
            = (1/pi) Int_0^inf (F0 - 1) [cos k(t - s) + cos k(t + s)] dk,

a smooth kernel (F0 - 1 ~ -4 k^2 exp(-2k)): analytic in a strip |Im t|, |Im s| < ~1.  With it

    load            P = 2 pi P~(0) = 2 pi Int_0^a g(t) dt,                                   (3)
    smooth edge     g(a) = 0     (p bounded at r = a; p ~ sqrt(a - r) there),                (4)

(4) fixes d for given a (g is linear in d: g = d g1 + g2, d = -g2(a)/g1(a)) and (3) gives P(a),
increasing; a(P) is found by Brent's method on log a.  Then, with G(t) = g'(t)/t (even, analytic)

    G(t) = -16/pi + (2/pi) Int_0^inf (F0 - 1) k^2 [sin(kt)/(kt)] P~(k) dk,
    p(r) = -Int_0^sqrt(a^2 - r^2) G(sqrt(r^2 + s^2)) ds  =  sqrt(a^2 - r^2) Q(r^2),
    Q(x) = -Int_0^1 G(sqrt(x + (a^2 - x) v^2)) dv      (analytic in x on [0, a^2]),
    p_max = p(0) = -Int_0^a G(t) dt,
    sigma_zz(r, 0) = -Int_0^inf A(k) P~(k) J0(kr) k dk.

Hertz limit (F0 = 1, K = 0): g = (4/pi)(d - 2t^2), g(a) = 0 gives d = 2 a^2, g = (8/pi)(a^2 - t^2),
P = 32 a^3/3, p(r) = (16 a/pi) sqrt(1 - r^2/a^2) -- the incompressible half-space (E* = 4E/3:
a^3 = 3FR/(4E*), p0 = 3F/(2 pi a^2), delta = a^2/R, in these units).  As a -> 0 the layer
enters first through the constant K(0, 0) = (2/pi) kappa0, kappa0 = Int_0^inf (F0 - 1) dk
= -1.7702...: it shifts g by a constant, so a(P) and p are Hertz's up to O(a^3) relative
(at fixed a, P/P_Hertz - 1 = -(2 kappa2/(3 pi)) a^3 = 0.81298 a^3, kappa2 = Int (F0 - 1) k^2 dk
= -3.8311: 8.1e-7 at a = 0.01 h, 1.0e-4 at 0.05 h; at fixed P, a/a_Hertz - 1 is -1/3 of
that), but the indentation is d = 2 a^2 + kappa0 P/(4 pi) + O(a^5): the rigid base stops the
far field, a relative correction 4 kappa0 a/(3 pi) = -0.75 a/h (-3.8 % at a = 0.05 h!) which
a comparison with Hertz's d must include.  The base stress under a small contact is the point load's,
sigma_zz(0, 0) = -(P/2pi)[Int A k dk - (a^2/10) Int A k^3 dk] + O(a^4).
Thin-film limit (a >> h, F0 ~ 2k^3/3, w = -(1/3) lap p): p = (3/16)(a^2 - r^2)^2, d = a^2/2,
P = pi a^6/16, approached slowly: the contact radius trails (16P/pi)^(1/6) by a nearly constant
~1.4 h (1.31 h at a = 3, 1.38 at 5, 1.45 at 20); at a = 5 d and p_max still exceed the thin-film
values by 44 % and x3.1 (p_max at 20 h: +34 %).  There the base stress follows the gradient
expansion of A(k) = 1 - k^2/2 + 7k^4/8: sigma_zz(r, 0) ~ -(p + lap p/2 + 7 lap^2 p/8) (tested).

Reference values (tol 1e-12; lengths in h, d in h^2/2R, stresses in G h/2R):

     a/h            P                  d                p_max          -sigma_zz(0, 0)
    0.05  1.333468350112e-03  4.812763180394e-03  2.546737161591e-01  9.972181529936e-04
     0.1  1.067522007011e-02  1.851549152318e-02  5.097055322441e-01  7.912331463843e-03
     0.3  2.936808819070e-01  1.430040138597e-01  1.558867054956e+00  1.985960316310e-01
       1  1.504533519337e+01  1.118830971126e+00  7.613388412093e+00  4.896170509943e+00
       3  1.255650657153e+03  7.334612287769e+00  8.775271703912e+01  7.645178081482e+01
       5  1.326173733370e+04  1.795623452859e+01  3.649436922266e+02  3.377093403018e+02

Numerics
--------
Nystrom on n Gauss-Legendre nodes of [0, a]; every k-integral by composite Gauss-Legendre on
[0, 26] (kernel, G; F0 - 1 < 1e-19 beyond) or [0, 46] (base stress; A k < 1e-17 beyond) with
panels no wider than a fraction of the oscillation period (numerics.abel_kernels.k_rule).
P~(k) for the base stress is computed from the Nystrom interpolant of g (eq. 2 evaluated at
off-node t) on a finer Gauss rule, so that it stays accurate at k a >> n.  The node count grows
until two levels (n, n + n/2) agree on a, d and p_max to ``tol``; ``error_estimate`` is that
difference (the finer level is returned: spectral convergence makes it a bound).

Convergence at fixed a: max relative change of (d, p_max, P) against n = 200 nodes
(``convergence_table``; the floor ~1e-15..1e-13 is round-off, growing with the condition
number, ~ 0.2 a^2.2: 4 at a = 1, 23 at 3, 67 at 5, 2e3 at 20):

        a       n=8     n=12     n=16     n=24     n=32     n=48     n=64     n=96
     0.05   2.0e-15  1.8e-15  1.5e-15  2.0e-15  2.0e-15  2.6e-15  1.3e-15  8.1e-16
      0.3   1.5e-15  1.3e-15  1.5e-15  2.3e-15  2.1e-15  2.8e-15  1.5e-15  1.1e-15
        1   1.9e-12  1.6e-15  1.4e-15  1.6e-15  1.7e-15  2.2e-15  1.0e-15  9.3e-16
        3   1.3e-06  1.8e-09  2.8e-14  4.2e-14  4.3e-14  6.7e-14  2.9e-14  1.6e-14
        5   4.7e-03  1.6e-05  4.6e-08  3.0e-13  1.7e-13  2.7e-13  1.1e-13  5.7e-14
       10   1.1e+00  5.5e-01  2.6e-02  7.9e-05  2.0e-07  1.5e-12  7.1e-13  3.4e-13
       20   2.7e+00  7.6e+00  9.7e-01  1.6e+01  1.9e-01  5.3e-04  1.3e-06  6.6e-12

Geometric convergence, about 5 a/h + 8 nodes for 1e-12: the solver starts at max(16, 8 + 4a)
and multiplies by 1.5.  At fixed P (``sphere_on_layer``, tol 1e-10) the returned a, d, p_max
agree with a level of twice the nodes to 6e-16 (a = 0.01 ... 1), 3e-14 (3, 5), 4e-13 (10),
1.3e-11 (20), the error estimate being of the same size; well under a second up to a = 10
(measured on a loaded machine: indicative only).

Independent checks (tests/test_axisym_layer.py): Hertz and the kappa0 correction as a -> 0
(deviations scale as a^3), the point-load base stress (a^4); Int p dA = P (adaptive quad);
Int sigma_zz(r, 0) dA = -P; the forward sinking formula (``surface_sinking``: half-space Abel
integral + layer Hankel integral, no inversion) returns d - r^2 in the contact to 1e-13 and an
opening gap outside; the pressure put on a 2D
periodic grid and pushed through physics.film.Film's 2D compliance and base transfer gives
w = d - r^2 in the contact (to the grid's accuracy, converging as dx^2.5 once the sqrt edge is
handled in closed form: 7e-6 d at 512^2 for a = 1), a gap >= 0 outside, and the same base
stress (to 7e-7 of its peak at 512^2, edge split; 6e-5 brute force); the thin-film limit is
approached as a/h grows.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.polynomial import chebyshev
from scipy.optimize import brentq
from scipy.special import j0

from ..errors import ConvergenceError, InputError
from ..numerics.abel_kernels import KMAX_M, KMAX_Z, gauss_legendre, k_rule
from ..physics.transfer import F0_minus_1, transfer_functions

__all__ = ["AxisymContact", "sphere_on_layer", "sphere_with_radius", "hertz_sphere",
           "thin_film_sphere", "KAPPA0", "convergence_table", "unit_scales"]

N_MIN = 16
_DIRECT_MAX = 512   # base_sigma_zz: above this many points, a piecewise Chebyshev interpolant
_PANEL_DEG = 40
N_MAX = 640
_A_MIN, _A_MAX = 1e-4, 40.0


def _kappa0() -> float:
    k, wk = k_rule(KMAX_M, 0.0)
    return float(wk @ F0_minus_1(k))


KAPPA0 = _kappa0()
"""Int_0^inf (F0(k) - 1) dk: the leading layer correction of the indentation,
d = 2 a^2 + KAPPA0 P/(4 pi) + ... as a -> 0."""


def unit_scales(young: float, radius: float, thickness: float) -> dict:
    """SI value of one dimensionless unit, for a film of Young modulus ``young`` [Pa] and
    thickness ``thickness`` [m] under a sphere of radius ``radius`` [m]: length h [m],
    height/displacement h^2/(2R) [m], stress E h/(6R) [Pa], force E h^3/(6R) [N]."""
    E, R, h = float(young), float(radius), float(thickness)
    return {"length": h, "displacement": h * h / (2.0 * R), "stress": E * h / (6.0 * R),
            "force": E * h**3 / (6.0 * R)}


def hertz_sphere(P: float) -> dict:
    """Incompressible half-space (E* = 4E/3) in these units: a = (3P/32)^(1/3), d = 2a^2,
    p_max = 16 a/pi, p(r) = p_max sqrt(1 - r^2/a^2)."""
    a = (3.0 * P / 32.0) ** (1.0 / 3.0)
    return {"a": a, "indentation": 2.0 * a * a, "max_pressure": 16.0 * a / math.pi}


def thin_film_sphere(P: float) -> dict:
    """Lubrication limit (a >> h: w = -(1/3) lap p, p = p' = 0 at r = a):
    p = (3/16)(a^2 - r^2)^2, a = (16 P/pi)^(1/6), d = a^2/2, p_max = 3 a^4/16."""
    a = (16.0 * P / math.pi) ** (1.0 / 6.0)
    return {"a": a, "indentation": 0.5 * a * a, "max_pressure": 3.0 * a**4 / 16.0}


# -------------------------------------------------------------------------------------------------
class _Level:
    """The Nystrom solution at fixed contact radius a and node count n."""

    def __init__(self, a: float, n: int):
        self.a, self.n = float(a), int(n)
        self.t, self.w = gauss_legendre(n, 0.0, a)
        self.k, self.wk = k_rule(KMAX_M, 2.0 * a)
        self.fk = F0_minus_1(self.k)                      # F0 - 1 on the k rule
        C = np.cos(np.outer(self.k, self.t))              # (nk, n)
        K = (2.0 / math.pi) * (C.T * (self.wk * self.fk)) @ C  # K(t_i, t_j)
        A = np.eye(n) + K * self.w[None, :]
        rhs = np.stack([np.full(n, 4.0 / math.pi), -8.0 / math.pi * self.t**2], axis=1)
        self._A = A
        G = np.linalg.solve(A, rhs)                       # g1 (d = 1, no t^2), g2 (t^2 part)
        # g(a) by Nystrom interpolation: g(a) = rhs(a) - Int K(a, s) g(s) ds
        Ka = (2.0 / math.pi) * (np.cos(self.k * a) * self.wk * self.fk) @ C  # K(a, t_j)
        ga = np.array([4.0 / math.pi, -8.0 / math.pi * a * a]) - Ka @ (self.w[:, None] * G)
        self.d = float(-ga[1] / ga[0])
        self.g = self.d * G[:, 0] + G[:, 1]
        self.P = 2.0 * math.pi * float(self.w @ self.g)
        self.Pk = C @ (self.w * self.g)                   # P~(k) on the kernel's k rule
        self._G_cheb = None

    @property
    def cond(self) -> float:
        """2-norm condition number of the Nystrom matrix I + K W."""
        return float(np.linalg.cond(self._A))

    def g_at(self, t):
        """g at any t in [0, a] (the Nystrom interpolant, eq. 2)."""
        t = np.asarray(t, float)
        corr = (2.0 / math.pi) * np.cos(np.multiply.outer(t, self.k)) @ (self.wk * self.fk * self.Pk)
        return 4.0 / math.pi * (self.d - 2.0 * t * t) - corr

    def G(self, t):
        """g'(t)/t (derivative of the Nystrom interpolant), any shape."""
        t = np.asarray(t, float)
        sinc = np.sinc(np.multiply.outer(t, self.k) / math.pi)
        return -16.0 / math.pi + (2.0 / math.pi) * sinc @ (self.wk * self.fk * self.k**2 * self.Pk)

    def G_fast(self):
        """A Chebyshev interpolant of G on [0, a] (degree n + 32: G is as smooth as g)."""
        if self._G_cheb is None:
            self._G_cheb = chebyshev.Chebyshev.interpolate(self.G, self.n + 32,
                                                           domain=[0.0, self.a])
        return self._G_cheb

    def max_pressure(self) -> float:
        v, wv = gauss_legendre(self.n + 16, 0.0, 1.0)
        return -self.a * float(wv @ self.G(self.a * v))


def _level_for_load(P: float, n: int, a_guess: float | None = None):
    """Root of P(a) = P at fixed n (Brent on log a); returns (level, evaluations)."""
    calls = [0]

    def f(loga):
        calls[0] += 1
        return math.log(_Level(math.exp(loga), n).P / P)

    if a_guess is None:
        a_guess = min(hertz_sphere(P)["a"], thin_film_sphere(P)["a"])
    lo, hi = math.log(a_guess) - 0.1, math.log(a_guess) + 0.1
    flo, fhi = f(lo), f(hi)
    while flo > 0.0:
        lo -= 0.5
        flo = f(lo)
    while fhi < 0.0:
        hi += 0.5
        fhi = f(hi)
    loga = brentq(f, lo, hi, xtol=1e-15, rtol=1e-15, maxiter=200)
    return _Level(math.exp(loga), n), calls[0] + 1


def _n_start(a: float) -> int:
    return max(N_MIN, int(math.ceil(8.0 + 4.0 * a)))


# -------------------------------------------------------------------------------------------------
@dataclass(eq=False)
class AxisymContact:
    """A frictionless sphere on the film (dimensionless; see the module docstring for units).

    a : contact radius (in h);  indentation : d, apex sinking (in h^2/2R);  load : P;
    max_pressure : p(0) (in G h/2R);  nodes : Nystrom nodes of the returned level;
    iterations : solves of the Nystrom system (all levels, root finding included);
    error_estimate : relative difference of (a, d, p_max, P) between the last two levels;
    condition_number : 2-norm condition number of the Nystrom matrix (~0.2 (a/h)^2.2);
    t, g : Gauss nodes on [0, a] and the auxiliary function g(t) (eq. 1).

    Methods: ``pressure(r)``, ``base_sigma_zz(r)``, ``surface_sinking(r)`` (w = -u_z, any r;
    the gap outside is w - d + r^2), ``pressure_hankel(k)`` (P~(k); the 2D transform is
    2 pi P~(|k|)), all vectorised over arrays of r >= 0 (or k >= 0).
    """

    load: float
    a: float
    indentation: float
    max_pressure: float
    nodes: int
    iterations: int
    error_estimate: float
    condition_number: float
    t: np.ndarray = field(repr=False)
    g: np.ndarray = field(repr=False)
    _level: _Level = field(repr=False, default=None)
    _Q: chebyshev.Chebyshev = field(repr=False, default=None)

    @classmethod
    def _from_level(cls, lev: _Level, iterations: int, error_estimate: float) -> AxisymContact:
        return cls(load=lev.P, a=lev.a, indentation=lev.d, max_pressure=lev.max_pressure(),
                   nodes=lev.n, iterations=iterations, error_estimate=error_estimate,
                   condition_number=lev.cond, t=lev.t.copy(), g=lev.g.copy(), _level=lev)

    def to_si(self, young: float, radius: float, thickness: float) -> dict:
        """The scalars in SI for a film of Young modulus ``young`` [Pa], thickness ``thickness``
        [m] under a sphere of radius ``radius`` [m] (keys as in the 3D solver's JSON)."""
        u = unit_scales(young, radius, thickness)
        return {"force_N": self.load * u["force"], "contact_radius_m": self.a * u["length"],
                "indentation_m": self.indentation * u["displacement"],
                "max_pressure_Pa": self.max_pressure * u["stress"],
                "base_sigma_zz_center_Pa": float(self.base_sigma_zz(np.array([0.0]))[0])
                * u["stress"],
                "error_estimate": self.error_estimate}

    # --- pressure ---------------------------------------------------------------------------
    def _q(self, x, exact: bool = False):
        """Q(x) = p / sqrt(a^2 - r^2) at x = r^2, by Gauss quadrature in v of G (the Chebyshev
        interpolant of G, or with ``exact`` its k-integral at every point: slow)."""
        a2 = self.a * self.a
        v, wv = gauss_legendre(self.nodes + 24, 0.0, 1.0)
        x = np.asarray(x, float)
        t = np.sqrt(x[..., None] + (a2 - x[..., None]) * v**2)
        G = self._level.G if exact else self._level.G_fast()
        return -(G(t) @ wv)

    def pressure_exact(self, r) -> np.ndarray:
        """p(r) by direct quadrature at each r (slow; ``pressure`` interpolates it)."""
        r = np.abs(np.asarray(r, float))
        inside = r < self.a
        out = np.zeros(r.shape)
        out[inside] = np.sqrt(self.a**2 - r[inside] ** 2) * self._q(r[inside] ** 2, exact=True)
        return out

    def pressure(self, r) -> np.ndarray:
        """p(r) >= 0 (in G h/2R), 0 for r >= a; a Chebyshev interpolant of Q(r^2) (degree
        nodes + 24, spectrally accurate: agrees with ``pressure_exact`` to ~1e-13 p_max)."""
        if self._Q is None:
            self._Q = chebyshev.Chebyshev.interpolate(self._q, self.nodes + 24,
                                                      domain=[0.0, self.a**2])
        r = np.abs(np.asarray(r, float))
        inside = r < self.a
        out = np.zeros(r.shape)
        out[inside] = np.sqrt(self.a**2 - r[inside] ** 2) * self._Q(r[inside] ** 2)
        return out

    def pressure_integral(self) -> float:
        """Int p dA = 2 pi Int_0^a u^2 Q(a^2 - u^2) du (u = sqrt(a^2 - r^2)): should equal P."""
        u, wu = gauss_legendre(self.nodes + 24, 0.0, self.a)
        return 2.0 * math.pi * float(wu @ (u * u * self._q(self.a**2 - u * u)))

    # --- transforms and base stress ----------------------------------------------------------
    def pressure_hankel(self, k) -> np.ndarray:
        """P~(k) = Int_0^inf p(r) J0(kr) r dr = Int_0^a g(t) cos(kt) dt (from the Nystrom
        interpolant of g on a Gauss rule fine enough for k a; P~(0) = P/(2 pi))."""
        k = np.abs(np.asarray(k, float))
        kmax = float(np.max(k)) if k.size else 0.0
        m = self.nodes + int(math.ceil(0.6 * kmax * self.a)) + 32
        tf, wf = gauss_legendre(m, 0.0, self.a)
        gw = wf * self._level.g_at(tf)
        return np.cos(np.multiply.outer(k, tf)) @ gw

    def surface_sinking(self, r) -> np.ndarray:
        """w(r) = -u_z(r, h), the surface's sinking (in h^2/2R), at any r >= 0:

            w(r) = (1/2) Int_0^min(r, a) g(t)/sqrt(r^2 - t^2) dt + (1/2) Int (F0 - 1) P~ J0(kr) dk
                 = (1/2) Int_0^arcsin(min(1, a/r)) g(r sin th) dth + ...

        (the half-space part from Int cos(kt) J0(kr) dk = 1/sqrt(r^2 - t^2), t < r).  Inside the
        contact it must return d - r^2 (the Abel inversion undone numerically: tested); outside,
        the gap is w - d + r^2 >= 0."""
        r = np.abs(np.asarray(r, float))
        lev = self._level
        th, wth = gauss_legendre(self.nodes + 24, 0.0, 1.0)
        top = np.arcsin(np.minimum(1.0, self.a / np.maximum(r, 1e-300)))
        t = r[..., None] * np.sin(top[..., None] * th)
        hs = 0.5 * top * (lev.g_at(t) @ wth)
        k, wk = k_rule(KMAX_M, (float(np.max(r)) if r.size else 0.0) + self.a)
        layer = 0.5 * (j0(np.multiply.outer(r, k)) @ (wk * F0_minus_1(k) * self.pressure_hankel(k)))
        return hs + layer

    def base_sigma_zz(self, r) -> np.ndarray:
        """sigma_zz(r, 0) at the rigid base (in G h/2R; < 0 in compression):
        -Int_0^inf A(k) P~(k) J0(kr) k dk.  Up to _DIRECT_MAX points: direct quadrature at each
        r (about 70 (max r + a) Bessel evaluations per point); beyond (e.g. a whole 2D grid):
        a piecewise Chebyshev interpolant on panels of width h up to max r (degree 40 per
        panel; sigma_zz is analytic in r: agrees with the direct sum to ~1e-13 of its peak)."""
        r = np.abs(np.asarray(r, float))
        if r.size <= _DIRECT_MAX:
            return self._base_sigma_zz_direct(r)
        r_max = float(np.max(r))
        edges = np.linspace(0.0, r_max, int(math.ceil(r_max)) + 1)
        nodes = np.cos(np.pi * (np.arange(_PANEL_DEG + 1) + 0.5) / (_PANEL_DEG + 1))  # [-1, 1]
        mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * np.diff(edges)
        values = self._base_sigma_zz_direct((mid[:, None] + half[:, None] * nodes).ravel())
        values = values.reshape(len(mid), -1)
        coef = np.polynomial.chebyshev.chebfit(nodes, values.T, _PANEL_DEG)  # (deg+1, panels)
        i = np.clip(np.searchsorted(edges, r, side="right") - 1, 0, len(mid) - 1)
        x = (r - mid[i]) / half[i]
        # Clenshaw on every point with its own panel's coefficients
        b1 = np.zeros(r.shape)
        b2 = np.zeros(r.shape)
        for j in range(_PANEL_DEG, 0, -1):
            b1, b2 = 2.0 * x * b1 - b2 + coef[j][i], b1
        return x * b1 - b2 + coef[0][i]

    def _base_sigma_zz_direct(self, r: np.ndarray) -> np.ndarray:
        k, wk = k_rule(KMAX_Z, (float(np.max(r)) if r.size else 0.0) + self.a)
        _, _, A, _, _ = transfer_functions(k)
        weight = wk * A * k * self.pressure_hankel(k)
        return -(j0(np.multiply.outer(r, k)) @ weight)


# -------------------------------------------------------------------------------------------------
def _check(P, tol):
    try:
        P = float(P)
        tol = float(tol)
    except (TypeError, ValueError):
        raise InputError("P and tol must be numbers") from None
    if not (math.isfinite(tol) and 1e-14 <= tol < 0.1):
        raise InputError(f"tol must be in [1e-14, 0.1); got {tol}")
    return P, tol


def _relative_change(x: _Level, y: _Level) -> float:
    px, py = x.max_pressure(), y.max_pressure()
    return max(abs(x.a - y.a) / y.a, abs(x.d - y.d) / abs(y.d), abs(px - py) / abs(py),
               abs(x.P - y.P) / y.P)


def sphere_on_layer(P: float, tol: float = 1e-10) -> AxisymContact:
    """The frictionless sphere pressed with dimensionless force P on the film.

    P = 6 R F/(E h^3) (F the force in N, R the sphere's radius, h the film's thickness, E its
    Young modulus; see ``unit_scales``), finite and > 0, such that the contact radius is in
    [1e-4, 40] h (checked on min(Hertz, thin-film) estimates, which bound a from above:
    roughly 1e-11 < P < 4e8).  ``tol``: relative accuracy of a, d, p_max, in [1e-14, 0.1).
    Raises InputError on bad input, ConvergenceError when N_MAX nodes do not reach ``tol``.
    """
    P, tol = _check(P, tol)
    if not (math.isfinite(P) and P > 0.0):
        raise InputError(f"P must be a finite number > 0; got {P}")
    a_est = min(hertz_sphere(P)["a"], thin_film_sphere(P)["a"])
    if not (_A_MIN <= a_est <= _A_MAX):
        raise InputError(f"P = {P} gives a contact radius outside [{_A_MIN}, {_A_MAX}] h "
                         f"(estimate {a_est:.3g} h)")
    n = _n_start(a_est)
    prev, calls = None, 0
    while n <= N_MAX:
        lev, c = _level_for_load(P, n, prev.a if prev is not None else None)
        calls += c
        if prev is not None:
            err = _relative_change(prev, lev)
            if err <= tol:
                return AxisymContact._from_level(lev, calls, err)
        prev = lev
        n = max(_n_start(lev.a), n + n // 2)
    raise ConvergenceError(f"axisymmetric layer reference: no convergence to tol = {tol} with "
                           f"{N_MAX} nodes (P = {P})", iterations=calls)


def sphere_with_radius(a: float, tol: float = 1e-10) -> AxisymContact:
    """The same at prescribed contact radius a (in h, [1e-4, 60]): no root finding."""
    a, tol = _check(a, tol)
    if not (math.isfinite(a) and _A_MIN <= a <= _A_MAX):
        raise InputError(f"a must be in [{_A_MIN}, {_A_MAX}] (in h); got {a}")
    n = _n_start(a)
    prev, calls = None, 0
    while n <= N_MAX:
        lev = _Level(a, n)
        calls += 1
        if prev is not None:
            err = _relative_change(prev, lev)
            if err <= tol:
                return AxisymContact._from_level(lev, calls, err)
        prev = lev
        n += n // 2
    raise ConvergenceError(f"axisymmetric layer reference: no convergence to tol = {tol} with "
                           f"{N_MAX} nodes (a = {a})", iterations=calls)


def convergence_table(radii=(0.05, 0.3, 1.0, 3.0, 5.0), nodes=(16, 24, 32, 48, 64, 96),
                      n_ref: int = 192):
    """Relative error max(|da|/a, |dd|/d, |dp_max|/p_max) at fixed a of each node count
    against n_ref (rows: radii).  Used to fill the table of the module docstring."""
    rows = []
    for a in radii:
        ref = _Level(a, n_ref)
        rows.append((a, [_relative_change(_Level(a, n), ref) for n in nodes]))
    return rows
