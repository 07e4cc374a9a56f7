"""The Hertz model (closed form): surface model Hertz, base transfer exact.

"Hertz pressure on the film".  The contact is taken from the incompressible elastic half-space
(plane strain, E* = 4E/3, rigid indenter).  In the paper's units (lengths in h, stresses in
E h/(6R), displacements in h^2/(2R); indenter profile x^2):

    a^2 = P / (2 pi),     p(x) = 4 sqrt(a^2 - x^2)  (|x| < a),     centre 0,    p_max = 4a,

whatever mu: an incompressible half-space under a rigid indenter has Dundurs beta = 0, so the
friction q = mu p does not couple into the normal problem.  That pressure and its Amontons shear
(sigma_zz(x, h) = -p, sigma_xz(x, h) = mu p) are then carried to the rigid base through the
film's exact symbols A, B, C (``physics.film.base_stress_symbols``), using the closed-form
spectrum of the Hertz pressure,

    p^(k) = 4 pi a J1(k a) / k      (p^(0) = 2 pi a^2 = P),

summed on a periodic grid: the base stresses are exact up to the periodic images
(~exp(-0.739 (L - 2a)) = tol/100 by the choice of L) and the truncation of the spectrum at the
grid's Nyquist wavenumber (A, B, C ~ k exp(-k): the grid keeps k_Nyquist >= 40, below 1e-15).

Indentation.  A 2D half-space has no finite indentation (its displacement grows like log|x|), so
the Hertz model has none of its own.  What is reported as ``indentation`` is the film's sinking at
the apex under the Hertz pressure and its friction, w(0) = (H p)(0) with H the film's surface
compliance (physics.film.surface_compliance):

    w(0) = (1/pi) Int_0^inf Re H(k) p^(k) dk = 2a Int_0^inf F0(k) J1(k a) / k^2 dk

(the friction part of H is odd in k and p is even: it does not move the apex).  Evaluated by
composite Gauss-Legendre on [0, 40] plus the closed-form tail beyond (F0 = 1 to 1e-30 there).
It tends to the exact model's indentation as a/h -> 0, and differs from it by O((a/h)^2).

The model error against the exact model (a, centre, peak pressure, indentation and the base-stress
profiles) is measured by ``studies/model_map.py``; ``solvers.auto.model_error_bound`` is the
fitted bound, reported in ``result.info["model_error_bound"]``.
"""
from __future__ import annotations

import math

import numpy as np
from scipy import special

from ..numerics.fft import get_rfft
from ..numerics.grid import Grid
from ..physics.film import base_stress_symbols
from ..physics.transfer import F0

__all__ = ["hertz_half_width", "hertz_pressure", "hertz_pressure_spectrum", "hertz_base_stresses",
           "hertz_film_sinking"]

_K_NYQUIST_MIN = 40.0   # A, B, C ~ 4k exp(-k): below 1e-15 beyond
_POINTS_ACROSS = 128    # grid points across the contact (profile output only)
_K_SPLIT = 40.0         # wavenumber beyond which F0 = 1 to 1e-30 in the sinking integral


def hertz_half_width(P: float) -> float:
    """a = sqrt(P / 2 pi) (in h), for the dimensionless load P."""
    return math.sqrt(max(P, 0.0) / (2.0 * math.pi))


def hertz_pressure(x: np.ndarray, a: float) -> np.ndarray:
    """p(x) = 4 sqrt(a^2 - x^2) in the contact, 0 outside (contact centred on the apex)."""
    x = np.asarray(x, dtype=float)
    return 4.0 * np.sqrt(np.maximum(a * a - x * x, 0.0))


def hertz_pressure_spectrum(k: np.ndarray, a: float) -> np.ndarray:
    """p^(k) = 4 pi a J1(k a)/k, real and even (numpy's convention, contact centred at 0)."""
    k = np.abs(np.asarray(k, dtype=float))
    out = np.full(k.shape, 2.0 * math.pi * a * a)
    nz = k * a > 1e-8
    out[nz] = 4.0 * math.pi * a * special.j1(k[nz] * a) / k[nz]
    small = ~nz
    out[small] *= 1.0 - (k[small] * a) ** 2 / 8.0  # J1(z)/z = (1 - z^2/8 + ...)/2
    return out


def hertz_base_stresses(grid: Grid, a: float, mu: float):
    """sigma_zz(x, 0), sigma_xz(x, 0) on ``grid`` (any origin) under the Hertz pressure of
    half-width ``a`` centred at x = 0 and its Amontons shear mu p (periodic sum of the exact
    spectra; the grid must keep k_Nyquist >~ 40 for full accuracy)."""
    k = grid.k
    ph = hertz_pressure_spectrum(k, a)
    A, iB, C = base_stress_symbols(k)
    szz_s, sxz_s = -ph, mu * ph                      # surface tractions' spectra
    # samples of the periodised field: f_j = (1/L) sum_m f^(k_m) exp(i k_m x_j), x_j = x0 + j dx
    scale = (grid.n / grid.length) * np.exp(1j * k * grid.origin)
    fft = get_rfft(grid.n)
    szz = fft.backward(scale * (A * szz_s + iB * sxz_s))
    sxz = fft.backward(scale * (C * sxz_s + iB * szz_s))
    return szz, sxz


def _gauss_legendre_integral(f, lo: float, hi: float, panel: float, order: int = 24) -> float:
    n_panels = max(1, math.ceil((hi - lo) / panel))
    t, w = np.polynomial.legendre.leggauss(order)
    edges = np.linspace(lo, hi, n_panels + 1)
    half = 0.5 * np.diff(edges)[:, None]
    mid = 0.5 * (edges[1:] + edges[:-1])[:, None]
    x = mid + half * t[None, :]
    return float(np.sum(half * w[None, :] * f(x)))


def _tail_J1_over_t2(x: float) -> float:
    """Int_x^inf J1(t)/t^2 dt = (1/2) [Int_x^inf J0(t)/t dt + J1(x)/x]   (x > 0),
    using J1/t = (J0 + J2)/2, Int_x^inf J2/t dt = J1(x)/x, and
    Int_x^inf J0/t dt = Int_0^x (1 - J0)/t dt - ln(x/2) - gamma."""
    int_1mj0, _ = special.it2j0y0(x)
    e0 = int_1mj0 - math.log(x / 2.0) - np.euler_gamma
    return 0.5 * (e0 + special.j1(x) / x)


def hertz_film_sinking(a: float) -> float:
    """w(0) = 2a Int_0^inf F0(k) J1(k a)/k^2 dk: the film's sinking at the apex under the Hertz
    pressure of half-width a (in h^2/(2R)); ~ the film's indentation for a << h."""
    if a <= 0.0:
        return 0.0
    panel = min(1.0, math.pi / (2.0 * a))  # a few nodes per oscillation of J1(ka)
    head = _gauss_legendre_integral(lambda k: F0(k) * special.j1(k * a) / (k * k),
                                    0.0, _K_SPLIT, panel)
    tail = a * _tail_J1_over_t2(_K_SPLIT * a)  # Int_K^inf J1(ka)/k^2 dk, F0 = 1 there
    return 2.0 * a * (head + tail)


