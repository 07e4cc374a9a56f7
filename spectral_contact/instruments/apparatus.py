"""Apparatus functions of the MEMS sensor (the paper's section "Set-up and Calibration").

The sensor output is U = A G (*) sigma, a 2D convolution over the (x, y) plane of the film's
base with a normalised apparatus function G (unit integral over the plane) and a conversion
constant A.  G is axisymmetric: it is given by its radial profile G(r) [1/m^2].  A field that
does not depend on y (plane strain) sees its line form g(x) = Int G(x, y) dy [1/m], which also
has unit integral, and whose 1D Fourier transform is the 2D transform of G at |k|:

    g^(k) = G^(|k|) = 2 pi Int_0^inf G(r) J0(k r) r dr.

Paper values (used as defaults):

* G_zz: Gaussian of standard deviation 561 um.
* G_xz: Gaussian of standard deviation 688 um "decorated by a rectangular foot of lateral extent
  2.7 mm and amplitude 4.1 % of the maximum amplitude of G_xz".
* A_zz = 19.00 mV/bar, A_xz = 7.95 mV/bar (1 bar = 1e5 Pa).

How the foot is read (``GaussianFoot``)
---------------------------------------
The paper's apparatus functions are plotted as profiles through the sensor centre (G(x, 0)
against x), and the foot is described on that plot.  A "rectangular foot of lateral extent
2.7 mm" is therefore read as a rectangle of full width 2.7 mm on that profile, i.e. a uniform
**disc of diameter 2.7 mm (radius 1.35 mm)** in the plane, centred on the sensor.  Reasons: (i)
"extent" on a profile is its full width, as the Gaussian's width is quoted for the same plot;
(ii) the disc of radius 1.35 mm is comparable with the suspended membrane (radius 1 mm) plus the
post, whereas a radius of 2.7 mm (diameter 5.4 mm) would make the foot carry about a quarter of
the total weight (against ~7 % here), hard to reconcile with "a Gaussian decorated by a foot".
"4.1 % of the maximum amplitude of G_xz" is read literally: the foot height is 4.1 % of
G_xz(0) = Gaussian peak + foot, so foot = 0.041/0.959 x Gaussian peak.  Both readings are
parameters (``foot_radius_m``, ``foot_fraction``) and can be changed.

Its line form is a Gaussian of the same standard deviation plus a half-ellipse
2 f sqrt(b^2 - x^2) (b = foot radius, f = foot height); its transform is
2 pi s^2 g0 exp(-s^2 k^2/2) + 2 pi b f J1(k b)/k.

User-supplied apparatus functions (``TabulatedApparatus``, ``load_apparatus_csv``): a CSV radial
profile with columns ``r_m`` and ``G`` (or ``G_per_m2``, as written by the calibration), read as
piecewise linear in r and zero beyond the last radius, normalised here to unit integral over the
plane (the normalisation is exact for the piecewise-linear profile; its line form is the exact
Abel projection of that profile).
"""
from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np
from scipy.special import j1

from ..errors import InputError
from ..numerics.grid import Grid
from ..physics.scene import check_positive
from ..units import A_XZ_MV_PER_BAR, A_ZZ_MV_PER_BAR, PA_PER_BAR  # noqa: F401 (re-exported)

__all__ = ["ApparatusFunction", "GaussianFoot", "TabulatedApparatus", "load_apparatus_csv",
           "G_ZZ", "G_XZ", "A_ZZ_MV_PER_BAR", "A_XZ_MV_PER_BAR", "PA_PER_BAR",
           "default_apparatus", "check_gain"]



def check_gain(name: str, value) -> float:
    """A conversion constant [mV/bar]: finite and > 0."""
    return check_positive(name, value, "mV/bar")


class ApparatusFunction(ABC):
    """An axisymmetric apparatus function of unit integral over the plane.

    Methods (all SI): ``radial(r)`` [1/m^2], ``line(x)`` [1/m] (y-integrated form),
    ``transform(k)`` (2D Fourier transform at |k| [1/m], dimensionless, 1 at k = 0),
    ``support_radius`` [m] (beyond it G is negligible, < 1e-12 of the peak for Gaussians).
    """

    support_radius: float

    @abstractmethod
    def radial(self, r):
        """G(r) [1/m^2]."""

    @abstractmethod
    def line(self, x):
        """The y-integrated form [1/m]."""

    @abstractmethod
    def transform(self, k):
        """2D Fourier transform at |k| [1/m]."""

    def line_symbol(self, n: int, dx: float) -> np.ndarray:
        """Half-spectrum (rfft layout) of the line form on a periodic grid of n points, step dx,
        such that irfft(symbol * rfft(f)) is g (*) f; symbol[0] = 1 (unit integral)."""
        k = Grid(int(n), int(n) * float(dx)).k
        return np.asarray(self.transform(k), dtype=float)


class GaussianFoot(ApparatusFunction):
    """Gaussian of standard deviation ``sd_m`` plus an optional uniform disc ("foot") of radius
    ``foot_radius_m`` whose height is ``foot_fraction`` times the peak G(0) of the whole
    function; unit integral over the plane.  See the module docstring for the paper's foot."""

    def __init__(self, sd_m: float, foot_radius_m: float = 0.0, foot_fraction: float = 0.0):
        self.sd = float(sd_m)
        self.foot_radius = float(foot_radius_m)
        self.foot_fraction = float(foot_fraction)
        if not (self.sd > 0 and math.isfinite(self.sd)):
            raise InputError(f"apparatus sd must be > 0 m; got {sd_m}")
        if not (0.0 <= self.foot_fraction < 1.0):
            raise InputError(f"foot_fraction must be in [0, 1); got {foot_fraction}")
        if self.foot_radius < 0 or not math.isfinite(self.foot_radius):
            raise InputError(f"foot_radius_m must be >= 0 m; got {foot_radius_m}")
        if self.foot_radius == 0.0:
            self.foot_fraction = 0.0
        # foot height f = phi (g0 + f)  ->  f = phi/(1 - phi) g0 ; unit integral fixes g0
        ratio = self.foot_fraction / (1.0 - self.foot_fraction)
        self.g0 = 1.0 / (2.0 * math.pi * self.sd**2 + ratio * math.pi * self.foot_radius**2)
        self.f = ratio * self.g0
        self.support_radius = max(8.0 * self.sd, self.foot_radius)

    @property
    def foot_weight(self) -> float:
        """Share of the unit integral carried by the foot."""
        return self.f * math.pi * self.foot_radius**2

    def radial(self, r):
        r = np.asarray(r, dtype=float)
        out = self.g0 * np.exp(-0.5 * (r / self.sd) ** 2)
        if self.f:
            out = out + np.where(np.abs(r) < self.foot_radius, self.f, 0.0)
        return out

    def line(self, x):
        x = np.asarray(x, dtype=float)
        out = self.g0 * math.sqrt(2.0 * math.pi) * self.sd * np.exp(-0.5 * (x / self.sd) ** 2)
        if self.f:
            b = self.foot_radius
            out = out + 2.0 * self.f * np.sqrt(np.clip(b * b - x * x, 0.0, None))
        return out

    def transform(self, k):
        k = np.abs(np.asarray(k, dtype=float))
        out = 2.0 * math.pi * self.sd**2 * self.g0 * np.exp(-0.5 * (self.sd * k) ** 2)
        if self.f:
            b = self.foot_radius
            kb = k * b
            with np.errstate(invalid="ignore", divide="ignore"):
                disc = np.where(kb > 1e-8, 2.0 * j1(kb) / np.where(kb > 1e-8, kb, 1.0),
                                1.0 - kb * kb / 8.0)
            out = out + self.f * math.pi * b * b * disc
        return out

    def __repr__(self):
        foot = (f", foot_radius_m={self.foot_radius:g}, foot_fraction={self.foot_fraction:g}"
                if self.f else "")
        return f"GaussianFoot(sd_m={self.sd:g}{foot})"


class TabulatedApparatus(ApparatusFunction):
    """A radial profile G(r_i) (piecewise linear, zero beyond r_max), normalised to unit
    integral over the plane.  Negative values are allowed (a calibrated G_xz can dip)."""

    def __init__(self, r_m, G, source: str = "table"):
        r = np.asarray(r_m, dtype=float)
        g = np.asarray(G, dtype=float)
        if r.ndim != 1 or r.shape != g.shape or r.size < 2:
            raise InputError(f"{source}: apparatus profile needs >= 2 points (r_m, G) of equal "
                             f"length")
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(g))):
            raise InputError(f"{source}: apparatus profile has non-finite values")
        if r[0] < 0 or np.any(np.diff(r) <= 0):
            raise InputError(f"{source}: apparatus r_m must be >= 0 and strictly increasing")
        if r[0] > 0:  # extend flat to the axis
            r = np.concatenate([[0.0], r])
            g = np.concatenate([[g[0]], g])
        total = self._plane_integral(r, g)
        if not (total > 0 and math.isfinite(total)):
            raise InputError(f"{source}: apparatus profile has integral {total:g} over the plane; "
                             f"it must be > 0 to be normalised")
        self.r = r
        self.G = g / total
        self.source = source
        self.support_radius = float(r[-1])
        self._abel_cache: dict = {}

    @staticmethod
    def _plane_integral(r, g):
        # 2 pi Int (a + b r) r dr over each segment, exact for piecewise-linear g
        r0, r1, g0, g1 = r[:-1], r[1:], g[:-1], g[1:]
        b = (g1 - g0) / (r1 - r0)
        a = g0 - b * r0
        seg = a * (r1**2 - r0**2) / 2.0 + b * (r1**3 - r0**3) / 3.0
        return float(2.0 * math.pi * seg.sum())

    def radial(self, r):
        r = np.abs(np.asarray(r, dtype=float))
        return np.interp(r, self.r, self.G, right=0.0)

    def line(self, x):
        """Exact Abel projection 2 Int_{|x|}^{r_max} G(r) r / sqrt(r^2 - x^2) dr of the
        piecewise-linear profile."""
        x = np.abs(np.asarray(x, dtype=float))
        shape = x.shape
        x = x.ravel()[:, None]
        r0, r1 = self.r[None, :-1], self.r[None, 1:]
        g0, g1 = self.G[None, :-1], self.G[None, 1:]
        b = (g1 - g0) / (r1 - r0)
        a = g0 - b * r0
        lo = np.maximum(r0, x)
        hi = r1
        active = hi > x

        def prim(r):
            s = np.sqrt(np.clip(r * r - x * x, 0.0, None))
            with np.errstate(divide="ignore", invalid="ignore"):
                lg = np.where(x > 0, x * x * np.log(np.where(r + s > 0, r + s, 1.0)), 0.0)
            return a * s + 0.5 * b * (r * s + lg)

        val = np.where(active, prim(np.where(active, hi, x)) - prim(np.where(active, lo, x)), 0.0)
        return (2.0 * val.sum(axis=1)).reshape(shape)

    def transform(self, k):
        """Hankel transform by quadrature of the line form: g^(k) = Int g(x) cos(kx) dx."""
        k = np.abs(np.asarray(k, dtype=float))
        n = 4096
        x = (np.arange(n) + 0.5) * (self.support_radius / n)
        g = self.line(x)
        w = self.support_radius / n
        flat = k.ravel()
        out = np.empty(flat.shape)
        for i in range(0, flat.size, 256):  # chunks: bounded memory
            out[i:i + 256] = 2.0 * w * (np.cos(np.multiply.outer(flat[i:i + 256], x)) @ g)
        return out.reshape(k.shape)

    def line_symbol(self, n: int, dx: float) -> np.ndarray:
        """The line form sampled on the periodic grid (centred on 0), transformed and
        renormalised to a unit discrete integral (exact conservation of Int S dx)."""
        n = int(n)
        j = np.arange(n)
        xs = np.where(j <= n // 2, j, j - n) * dx
        g = self.line(xs)
        sym = np.fft.rfft(g).real  # g is even on the periodic grid: real transform
        return sym / sym[0]

    def __repr__(self):
        return f"TabulatedApparatus({self.source!r}, {self.r.size} points, r_max={self.r[-1]:g} m)"


def load_apparatus_csv(path) -> TabulatedApparatus:
    """A user apparatus function from a CSV radial profile (columns r_m and G or G_per_m2)."""
    from .measured_io import read_radial_profile

    r, g, _ = read_radial_profile(path, ("G", "G_per_m2"), min_points=2)
    return TabulatedApparatus(r, g, source=str(path))


G_ZZ = GaussianFoot(561e-6)
"""Paper's G_zz: Gaussian, standard deviation 561 um."""
G_XZ = GaussianFoot(688e-6, foot_radius_m=1.35e-3, foot_fraction=0.041)
"""Paper's G_xz: Gaussian sd 688 um + uniform disc of diameter 2.7 mm at 4.1 % of G_xz(0)."""


def default_apparatus():
    """(G_zz, G_xz) of the paper."""
    return G_ZZ, G_XZ
