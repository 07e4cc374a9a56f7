"""Calibration of the MEMS: deconvolve U = A G (*) sigma for the apparatus function G and A.

Inputs are radial profiles sampled along the +x axis from the sensor centre, on a uniform grid
r_i = i dr (i = 0..m-1): the measured output U(r) [mV] (rod scanned across the sensor) and the
computed base stress sigma(r) [Pa] under the same rod (``axisym.flat_punch_base_stresses``).
Sign conventions of the sensor: for "zz" pass S = -sigma_zz (positive in compression); for
"xz" pass sigma_xz(x = r, y = 0), the radial base shear.

As in the paper, 2D fields are built from the profiles by axisymmetry (cubic interpolation in
r) on a periodic square grid of step dr and side 4 r_max:

* "zz": f(x, y) = f(r);
* "xz": f(x, y) = f(r) x / r (a radial vector field seen through its x component: odd in x,
  zero integral).  An axisymmetric G maps f(r) x/r to g(r) x/r, so the same ratio applies.

Methods
-------
``method="ratio"`` (the paper's): A G = F^-1[(F{U} + n_U) / (F{sigma} + n_sigma)] with 2D FFTs.
n_U and n_sigma are white noises (flat amplitude spectrum, random phases) added to both spectra,
of amplitude ``floor`` (0.1: "10 times weaker") times the weakest *relevant* component of each
spectrum.  For "xz" both spectra vanish identically on the line k_x = 0 (odd fields), where
the ratio is floor/floor; with ``fill_zeros`` (default) those in-band values are replaced by
the ring's pooled estimate sum U^ conj(sigma^) / sum |sigma^|^2 (and k = 0 by extrapolation
in |k|^2).
The literal method (``fill_zeros=False``) leaves a random stripe there which, through the
far-field condition, biased A_xz by about -28 % in our round trips.
Relevant components form the band |k| < k_c, k_c the first ring of |k| where the rms of |F{U}|
falls below ``relevant`` (1e-5) times its largest ring rms or below 3 times the expected
spectral rms of the measurement noise on that ring (the profile noise pushed through the same
axisymmetric construction, computed as a Hankel sum).  Both fields are tapered to
zero over the outer half of r_max (cos^2) before the FFT: the steps at r_max otherwise leave a
~1e-5 high-|k| plateau in both spectra whose ratio (~A) puts a spike at r = 0.

``method="wiener"`` (Tikhonov, automatic parameter): the unknown is A G(r), piecewise linear
on r_l = l dr with compact support ``support_m`` (default r_max / 2; G = 0 beyond), and the data
are the measured profile points themselves: U(r_i) = sum_l K_il G_l, where column l is the
profile along +x of F^-1[H_l F{sigma}], H_l the 2D transform (Hankel, by Gauss quadrature) of
the l-th hat function, taken constant on fine rings of |k| (width pi / (2 side)), and F{sigma}
the 2D FFT of the (untapered) stress field.  U is thus never truncated, tapered or
interpolated, and G's far field (invisible to the data) is excluded by the support.  Penalty
lambda Int |grad(A G)|^2 dA (it does not shrink the level, so it does not bias A); lambda by
generalized cross-validation -- robust GCV (Lukas 2006) with gamma = 0.03, the default: plain
GCV under-smooths here because at low noise the residual is correlated model error -- or, if
``noise_sd_mV`` is given and ``parameter="discrepancy"``, by the discrepancy principle.  One
SVD serves every lambda and every bootstrap replicate.

Both: A = integral of A G over the plane (unit-integral G).  "ratio" for "xz": the integrals of
U and sigma vanish, so the k = 0 ratio is undetermined and G_xz is fixed up to a constant,
chosen so that G vanishes far away (mean over 1.5 r_max < r < 2 r_max set to zero); "wiener"
needs no such constant (compact support).  The radial output, at the data's radii, is the
azimuthal average of the 2D G for "ratio" (it averages the floor's white noise down) and the
basis values for "wiener".

Uncertainty band: bootstrap over noise realisations -- ``n_boot`` synthetic data sets
centre + noise, each deconvolved the same way (lambda re-chosen; new noise floors for "ratio");
the band is the central ``level`` (0.95) interval of the replicates of G(r) and of A, taken
about their median and placed on the estimate.  Noise sd: ``noise_sd_mV`` if given, else the
GCV residual estimate ("wiener") or the profile's 4th-difference MAD estimate ("ratio").
Centre: the fitted profile U_fit for "wiener" (parametric bootstrap); the measured U itself
for "ratio" (the ratio does not smooth the data), which adds the noise twice and so overstates
the band by up to sqrt(2).  The band measures the noise's effect, not the regularisation bias
(the round-trip tests measure that).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import CubicSpline

from ..errors import InputError
from ..numerics.fft import get_rfft
from ..numerics.grid import Grid
from .apparatus import PA_PER_BAR, TabulatedApparatus

__all__ = ["Calibration", "calibrate", "estimate_noise_sd", "axisymmetric_field"]

_log = logging.getLogger(__name__)  # progress (INFO): bootstrap realisations


@dataclass
class Calibration:
    """Result of a calibration.

    r_m : radii [m];  G : normalised radial apparatus function [1/m^2] (unit plane integral);
    A_mV_per_bar : conversion constant;  G_lo, G_hi, A_lo, A_hi : bootstrap band;
    component : "zz" | "xz";  method : "ratio" | "wiener";  U_fit_mV : the model profile
    A G (*) sigma at r_m;  info : details (lambda, noise sd, grid, ...).
    """

    r_m: np.ndarray
    G: np.ndarray
    A_mV_per_bar: float
    G_lo: np.ndarray
    G_hi: np.ndarray
    A_lo: float
    A_hi: float
    component: str
    method: str
    U_fit_mV: np.ndarray
    info: dict = field(default_factory=dict)

    def apparatus(self) -> TabulatedApparatus:
        """The calibrated G as an apparatus function (for ``sensor_view``)."""
        return TabulatedApparatus(self.r_m, self.G, source=f"calibrated G_{self.component}")

    def columns(self) -> dict:
        """CSV columns (SI; G in 1/m^2, A G in mV/bar/m^2)."""
        return {"r_m": self.r_m, "G_per_m2": self.G, "G_lo_per_m2": self.G_lo,
                "G_hi_per_m2": self.G_hi, "AG_mV_per_bar_per_m2": self.A_mV_per_bar * self.G}


def estimate_noise_sd(values) -> float:
    """Noise standard deviation of a smooth, finely sampled profile: median absolute 4th
    difference / (0.6745 sqrt(70))  (white noise: var(D4 e) = 70 var(e))."""
    v = np.asarray(values, dtype=float)
    if v.size < 8:
        return 0.0
    return float(np.median(np.abs(np.diff(v, 4))) / (0.6745 * math.sqrt(70.0)))


def _taper(rr, r_max, start):
    """1 for r < start r_max, cos^2 roll-off to 0 at r_max (start >= 1: none)."""
    if start >= 1.0:
        return np.ones_like(rr)
    t = np.clip((rr / r_max - start) / (1.0 - start), 0.0, 1.0)
    return np.cos(0.5 * np.pi * t) ** 2


def _build(rr, cos, r, values, harmonic, taper=1.0):
    """Cubic-spline interpolation of the profile at radii rr, extended to r < 0 as an even
    (harmonic 0) or odd (harmonic 1) function so the field is smooth through the axis; zero
    beyond the last radius; times f(r) x/r for harmonic 1."""
    r = np.asarray(r, dtype=float)
    v = np.asarray(values, dtype=float)
    sign = -1.0 if harmonic else 1.0
    start = 1 if r[0] == 0.0 else 0
    rx = np.concatenate([-r[start:][::-1], r])
    vx = np.concatenate([sign * v[start:][::-1], v])
    inside = rr <= r[-1]
    f = np.zeros(rr.shape)
    f[inside] = CubicSpline(rx, vx)(rr[inside]) * _taper(rr[inside], r[-1], taper)
    return f * cos if harmonic else f


def axisymmetric_field(r_m, values, n: int, dx: float, harmonic: int = 0) -> np.ndarray:
    """f(r) (harmonic 0) or f(r) x/r (harmonic 1) on an n x n periodic grid of step dx with the
    origin at index (0, 0) (cubic interpolation in r); zero beyond the last radius."""
    j = np.arange(int(n))
    c = np.where(j <= n // 2, j, j - n) * dx
    rr = np.hypot(c[:, None], c[None, :])
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.where(rr > 0, c[None, :] / np.where(rr > 0, rr, 1.0), 0.0)
    return _build(rr, cos, r_m, values, harmonic)


class _Grid:
    """The periodic 2D grid, its half spectrum, rings of |k| and the far annulus."""

    def __init__(self, r_m, harmonic: int, pad: float = 2.0):
        self.harmonic = harmonic
        self.r = np.asarray(r_m, dtype=float)
        self.m = self.r.size
        self.dx = float((self.r[-1] - self.r[0]) / (self.m - 1))
        self.r_max = float(self.r[-1])
        n = int(math.ceil(2.0 * pad * self.r_max / self.dx))
        self.n = n + (n % 2)
        self.L = self.n * self.dx
        j = np.arange(self.n)
        c = np.where(j <= self.n // 2, j, j - self.n) * self.dx
        self.rr = np.hypot(c[:, None], c[None, :])
        with np.errstate(invalid="ignore", divide="ignore"):
            self.cos = np.where(self.rr > 0, c[None, :] / np.where(self.rr > 0, self.rr, 1.0),
                                0.0)
        self.fft = get_rfft((self.n, self.n))
        grid = Grid((self.n, self.n), (self.L, self.L))  # arrays indexed [y, x]: rfft along x
        self.kx = grid.wavevector[1].ravel()
        self.k = grid.kmag
        w = np.full(self.k.shape, 2.0)  # Hermitian weights of the half spectrum
        w[:, 0] = 1.0
        w[:, -1] = 1.0
        self.w = w
        self.ring = np.rint(self.k / (2.0 * np.pi / self.L)).astype(int)
        self.n_rings = int(self.ring.max()) + 1
        self.ring_N = np.bincount(self.ring.ravel(), w.ravel(), self.n_rings)
        self.far = (self.rr >= 0.75 * (self.L / 2.0)) & (self.rr <= self.L / 2.0)
        bins = np.rint(self.rr / self.dx).astype(int)
        self.bins = np.where(bins < self.m, bins, self.m).ravel()
        self.bin_count = np.bincount(self.bins, minlength=self.m + 1)[:self.m]

    def field(self, values, taper=1.0):
        return _build(self.rr, self.cos, self.r, values, self.harmonic, taper)

    def spectrum(self, values, taper=1.0):
        return self.fft.forward(self.field(values, taper)) * self.dx**2

    def real(self, spec):
        return self.fft.backward(spec) / self.dx**2

    def radial_average(self, f2d):
        """Azimuthal average on rings r = i dr (width dr), i = 0..m-1."""
        return np.bincount(self.bins, f2d.ravel(), self.m + 1)[:self.m] / self.bin_count

    def axis_matrix(self, ring_col_sums, radii):
        """M[i, j] = profile at x = radii[i], y = 0 of the inverse transform of the spectrum
        restricted to ring j (given its ring/column sums)."""
        E = np.exp(1j * np.multiply.outer(self.kx, radii))
        return (ring_col_sums @ E).real.T / (self.n * self.n * self.dx * self.dx)


def _noise_ring_rms(grid: _Grid, taper: float = 0.5) -> np.ndarray:
    """Expected spectral rms, per ring of |k|, of the 2D field built from unit-variance white
    profile noise: |e^(rho)|^2 = (2 pi dr)^2 sum_i (w_i r_i J_nu(rho r_i))^2 (nu = harmonic;
    the cos(phi) of harmonic 1 averages to 1/2 on a ring)."""
    from scipy.special import jv

    kr = np.bincount(grid.ring.ravel(), (grid.w * grid.k).ravel(), grid.n_rings) / \
        np.maximum(grid.ring_N, 1e-300)
    ri = grid.r * _taper(grid.r, grid.r_max, taper)
    ri = np.where(grid.r == 0.0, 0.25 * grid.dx, ri)  # the axis sample carries ~ a disc dr/2
    out = np.empty(grid.n_rings)
    for j0 in range(0, grid.n_rings, 256):
        J = jv(grid.harmonic, np.multiply.outer(kr[j0:j0 + 256], grid.r))
        out[j0:j0 + 256] = 2.0 * np.pi * grid.dx * np.sqrt(np.sum((J * ri) ** 2, axis=1))
    return out / math.sqrt(2.0) if grid.harmonic else out


def _unit_white(grid, rng):
    z = grid.fft.forward(rng.standard_normal((grid.n, grid.n)))
    return z / np.maximum(np.abs(z), 1e-300)


class _Ratio:
    """The paper's Fourier ratio with white-noise floors."""

    taper = 0.5

    def __init__(self, grid: _Grid, S, floor, relevant, fill):
        self.fill = bool(fill)
        self.g = grid
        self.Sh = grid.spectrum(S, taper=self.taper)
        self.Sh_full = grid.spectrum(S)  # untapered: for the forward fit
        self.floor, self.relevant = floor, relevant
        self.noise_ring = _noise_ring_rms(grid, self.taper)

    def solve(self, U, noise_sd, rng):
        g = self.g
        Uh = g.spectrum(U, taper=self.taper)
        aU = np.abs(Uh)
        # relevance is decided per ring of |k| (isolated noise peaks must not count)
        ring_rms = np.sqrt(np.bincount(g.ring.ravel(), (g.w * aU**2).ravel(), g.n_rings)
                           / np.maximum(g.ring_N, 1.0))
        ok = (ring_rms >= self.relevant * ring_rms.max()) & \
            (ring_rms >= 3.0 * noise_sd * self.noise_ring)
        # the relevant band is contiguous: up to the first failing ring (ring 0 is empty for xz)
        bad = np.nonzero(~ok[1:])[0]
        j_c = int(bad[0]) + 1 if bad.size else g.n_rings
        mask = (g.ring < j_c) & (aU > 0)
        if not mask.any():
            raise InputError("calibrate: no spectral component of U above the noise")
        # "the weakest relevant component": the weakest relevant ring (rms over the ring), so
        # that the structural zeros of the xz spectra (k_x = 0) do not count
        S_rms = np.sqrt(np.bincount(g.ring.ravel(), (g.w * np.abs(self.Sh) ** 2).ravel(),
                                    g.n_rings) / np.maximum(g.ring_N, 1.0))
        rel = np.arange(g.n_rings) < j_c
        rel[0] = rel[0] and not g.harmonic  # k = 0 is a structural zero for xz
        eps_U = self.floor * ring_rms[rel].min()
        eps_S = self.floor * S_rms[rel].min()
        AGh = (Uh + eps_U * _unit_white(g, rng)) / (self.Sh + eps_S * _unit_white(g, rng))
        if g.harmonic and self.fill:
            # structural zeros of the xz spectra (k_x = 0, where both vanish by symmetry): the
            # ratio there is floor/floor; use the ring's pooled estimate instead
            num = np.bincount(g.ring.ravel(), (g.w * (Uh * np.conj(self.Sh)).real).ravel(),
                              g.n_rings)
            den = np.bincount(g.ring.ravel(), (g.w * np.abs(self.Sh) ** 2).ravel(), g.n_rings)
            pooled = np.where(den > 0, num / np.where(den > 0, den, 1.0), 0.0)
            if g.n_rings > 2:
                pooled[0] = (4.0 * pooled[1] - pooled[2]) / 3.0  # even in |k|: extrapolate
            zero = np.zeros(AGh.shape, dtype=bool)
            zero[:, 0] = True
            inband = zero & (g.ring < j_c)
            AGh[inband] = pooled[g.ring[inband]]
        AG = g.real(AGh)
        if g.harmonic:
            AG = AG - AG[g.far].mean()
        A = float(AG.sum() * g.dx**2)
        U_fit = g.real(g.fft.forward(AG) * g.dx**2 * self.Sh_full)[0, :g.m]
        return g.radial_average(AG), A, U_fit, {"eps_U": eps_U, "eps_sigma": eps_S,
                                               "k_c_per_m": float(j_c * 2.0 * np.pi / g.L)}


class _Tikhonov:
    """Tikhonov fit of the profile points for G(r) piecewise linear on r_l = l dr < support
    (G = 0 beyond), penalty lambda Int |grad G|^2 dA, through one SVD."""

    rgcv_gamma = 0.03

    def __init__(self, grid: _Grid, S, support_m: float, sub: int = 4):
        g = grid
        self.g = grid
        M = max(int(round(support_m / g.dx)), 4)
        self.M = M
        self.r_basis = np.arange(M) * g.dx
        Sh = g.spectrum(S)  # no taper: the data are compared point by point
        # fine rings of |k| (width 2 pi / (sub L)): the spectrum of each basis function is
        # taken constant on a ring
        ring = np.rint(g.k / (2.0 * np.pi / (sub * g.L))).astype(int)
        n_r = int(ring.max()) + 1
        idx = (ring * g.kx.size + np.arange(g.kx.size)[None, :]).ravel()
        size = n_r * g.kx.size
        wS = (g.w * Sh).ravel()
        sums = (np.bincount(idx, wS.real, size) + 1j * np.bincount(idx, wS.imag, size))
        sums = sums.reshape(n_r, g.kx.size)
        N = np.bincount(ring.ravel(), g.w.ravel(), n_r)
        kr = np.bincount(ring.ravel(), (g.w * g.k).ravel(), n_r) / np.maximum(N, 1e-300)
        K_ring = g.axis_matrix(sums, g.r)  # (m, rings): profile response to ring value 1
        H = self._hat_transforms(kr, g.dx, M)  # (rings, M): 2D transforms of the hats
        self.K = K_ring @ H  # (m, M)
        self.area = H[0] if kr[0] == 0.0 else self._hat_areas(g.dx, M)
        # gradient penalty: rows sqrt(w_l) (G_{l+1} - G_l), G_M = 0  (square, invertible)
        w = 2.0 * np.pi * (self.r_basis + 0.5 * g.dx) / g.dx
        D = np.diag(-np.sqrt(w)) + np.diag(np.sqrt(w[:-1]), 1)
        self.Dinv = np.linalg.inv(D)
        self.U_, self.s, self.Vt = np.linalg.svd(self.K @ self.Dinv, full_matrices=False)

    @staticmethod
    def _hat_areas(dr, M):
        a = 2.0 * np.pi * dr * dr * np.arange(M, dtype=float)
        a[0] = 2.0 * np.pi * dr * dr / 6.0
        return a

    @staticmethod
    def _hat_transforms(k, dr, M, q: int = 8):
        """H[j, l] = 2 pi Int hat_l(r) J0(k_j r) r dr (hat_l: 1 at r_l = l dr, 0 at r_{l+-1})."""
        from scipy.special import j0

        xg, wg = np.polynomial.legendre.leggauss(q)
        t = 0.5 * (xg + 1.0)  # nodes on [0, 1] within each segment [i dr, (i+1) dr]
        wt = 0.5 * wg
        seg = np.arange(M)  # segments [i dr, (i+1) dr], i < M (G_M = 0)
        rq = (seg[:, None] + t[None, :]) * dr  # (M, q)
        H = np.zeros((k.size, M))
        for i0 in range(0, k.size, 512):
            kk = k[i0:i0 + 512]
            J = j0(kk[:, None, None] * rq[None, :, :]) * (2.0 * np.pi * rq * wt * dr)[None]
            # segment i contributes to hat i (weight 1 - t) and hat i+1 (weight t)
            left = np.einsum("kiq,q->ki", J, 1.0 - t)
            right = np.einsum("kiq,q->ki", J, t)
            H[i0:i0 + 512] += left
            H[i0:i0 + 512, 1:] += right[:, :-1]
        return H

    def choose(self, U, parameter, noise_sd):
        beta = self.U_.T @ U
        resid0 = max(float(U @ U - beta @ beta), 0.0)  # part of U outside the range of K
        s2 = self.s**2
        lams = s2[0] * np.logspace(-20, 2, 221)
        f = s2[None, :] / (s2[None, :] + lams[:, None])
        rss = np.sum(((1.0 - f) * beta[None, :]) ** 2, axis=1) + resid0
        dof = self.g.m - f.sum(axis=1)
        if parameter == "gcv":
            # robust GCV (Lukas 2006): V(lambda) (gamma + (1 - gamma) tr(H^2)/m); gamma = 1 is
            # plain GCV, which under-smooths when the residual is correlated model error
            m = self.g.m
            crit = rss / np.maximum(dof, 1e-12) ** 2
            gam = self.rgcv_gamma
            crit = crit * (gam + (1.0 - gam) * np.sum(f * f, axis=1) / m)
            i = int(np.argmin(crit))
        else:  # discrepancy principle: the largest lambda with rss <= m sd^2
            ok = np.nonzero(rss <= self.g.m * noise_sd**2)[0]
            i = int(ok[-1]) if ok.size else 0
        return float(lams[i]), float(rss[i]), float(dof[i])

    def solve(self, U, lam):
        beta = self.U_.T @ U
        z = self.Vt.T @ (self.s / (self.s**2 + lam) * beta)
        Gl = self.Dinv @ z
        A = float(self.area @ Gl)
        AG = np.zeros(self.g.m)
        n = min(self.M, self.g.m)
        AG[:n] = Gl[:n]
        return AG, A, self.K @ Gl


def _check_profiles(r_m, U_mV, sigma_Pa):
    r = np.asarray(r_m, dtype=float)
    U = np.asarray(U_mV, dtype=float)
    S = np.asarray(sigma_Pa, dtype=float)
    if r.ndim != 1 or U.shape != r.shape or S.shape != r.shape or r.size < 8:
        raise InputError("calibrate: r_m, U and sigma must be 1D arrays of equal length >= 8")
    if not (np.all(np.isfinite(r)) and np.all(np.isfinite(U)) and np.all(np.isfinite(S))):
        raise InputError("calibrate: profiles must be finite")
    d = np.diff(r)
    if np.any(d <= 0) or np.ptp(d) > 1e-3 * d.mean():
        raise InputError("calibrate: r_m must be increasing and uniform")
    if abs(r[0]) > 1e-3 * d.mean():
        raise InputError(f"calibrate: radial profiles must start at r = 0 (first r_m = {r[0]:g})")
    if not np.any(S != 0):
        raise InputError("calibrate: the computed stress profile is zero")
    if not np.any(U != 0):
        raise InputError("calibrate: the measured profile is zero")
    return r, U, S


def calibrate(r_m, U_mV, sigma_Pa, component: str = "zz", method: str = "ratio", *,
              noise_sd_mV: float | None = None, parameter: str = "gcv", floor: float = 0.1,
              relevant: float = 1e-5, fill_zeros: bool = True,
              support_m: float | None = None, n_boot: int = 40,
              level: float = 0.95,
              seed: int = 0, progress=None) -> Calibration:
    """Deconvolve the radial profiles U_mV(r) = A G (*) sigma_Pa(r); see the module docstring.

    r_m : uniform radii from 0 [m], shared by both profiles;  U_mV : measured output [mV];
    sigma_Pa : computed base stress in the sensor convention (compression positive for "zz");
    parameter : "gcv" or "discrepancy" (needs noise_sd_mV), for method="wiener".
    progress : optional callable(done, total), called after each bootstrap replicate.
    Returns a ``Calibration`` (A in mV/bar).
    """
    if component not in ("zz", "xz"):
        raise InputError(f"component must be 'zz' or 'xz'; got {component!r}")
    if method not in ("ratio", "wiener"):
        raise InputError(f"method must be 'ratio' or 'wiener'; got {method!r}")
    if parameter not in ("gcv", "discrepancy"):
        raise InputError(f"parameter must be 'gcv' or 'discrepancy'; got {parameter!r}")
    if parameter == "discrepancy" and noise_sd_mV is None:
        raise InputError("parameter='discrepancy' needs noise_sd_mV")
    if noise_sd_mV is not None and not (math.isfinite(float(noise_sd_mV)) and noise_sd_mV >= 0):
        raise InputError(f"noise_sd_mV must be >= 0; got {noise_sd_mV}")
    if not (0.0 < level < 1.0):
        raise InputError(f"level must be in (0, 1); got {level}")
    r, U, S = _check_profiles(r_m, U_mV, sigma_Pa)
    harmonic = 1 if component == "xz" else 0
    rng = np.random.default_rng(seed)
    grid = _Grid(r, harmonic)
    info = {"grid_points": grid.n, "grid_step_m": grid.dx, "domain_m": grid.L}

    if method == "ratio":
        solver = _Ratio(grid, S, floor, relevant, fill_zeros)
        sd = estimate_noise_sd(U) if noise_sd_mV is None else float(noise_sd_mV)
        AG, A, U_fit, extra = solver.solve(U, sd, rng)

        def replicate(Ub):
            AGb, Ab, _, _ = solver.solve(Ub, sd, rng)
            return AGb, Ab
        centre = U  # the ratio's forward fit is not a smoother: perturb the data themselves
    else:
        if support_m is None and grid.r_max < 8 * grid.dx:
            raise InputError(f"calibrate: method wiener needs radial profiles reaching r >= 8 dr "
                             f"(at least 9 rows; G's support is r_max/2 >= 4 dr); got r_max = "
                             f"{grid.r_max:g} m with dr = {grid.dx:g} m")
        support = 0.5 * grid.r_max if support_m is None else float(support_m)
        if not (grid.dx * 4 <= support <= grid.r_max):
            raise InputError(f"support_m must be within [4 dr, r_max]; got {support}")
        solver = _Tikhonov(grid, S, support)
        lam, rss, dof = solver.choose(U, parameter, noise_sd_mV or 0.0)
        AG, A, U_fit = solver.solve(U, lam)
        sd = (math.sqrt(rss / max(dof, 1.0)) if noise_sd_mV is None else float(noise_sd_mV))
        extra = {"lambda": lam, "lambda_rel": lam / solver.s[0] ** 2, "dof_resid": dof,
                 "parameter": parameter, "support_m": support}

        def replicate(Ub):
            lam_b, _, _ = solver.choose(Ub, parameter, sd)
            AGb, Ab, _ = solver.solve(Ub, lam_b)
            return AGb, Ab
        centre = U_fit
    info.update(extra)
    if not (math.isfinite(A) and A != 0.0):
        raise InputError("calibrate: the deconvolved apparatus function has zero integral")
    G = AG / A
    Gs, As = [], []
    for i in range(int(n_boot)):
        if i % 5 == 0:
            _log.info("calibrate %s (%s): bootstrap realisation %d of %d", component, method,
                      i + 1, n_boot)
        AGb, Ab = replicate(centre + sd * rng.standard_normal(r.size))
        if progress is not None:
            progress(i + 1, int(n_boot))
        if math.isfinite(Ab) and Ab != 0.0:
            Gs.append(AGb / Ab)
            As.append(Ab)
    q = (0.5 * (1.0 - level), 0.5 * (1.0 + level))
    if Gs:
        # spread of the replicates about their median, placed on the estimate (the replicates
        # of a regularised estimate are smoothed twice, so their own centre is biased)
        Gb, Ab_ = np.array(Gs), np.array(As)
        mG, mA = np.median(Gb, axis=0), float(np.median(Ab_))
        qG = np.quantile(Gb, q, axis=0)
        qA = np.quantile(Ab_, q)
        G_lo, G_hi = G + (qG[0] - mG), G + (qG[1] - mG)
        A_lo, A_hi = A + float(qA[0] - mA), A + float(qA[1] - mA)
    else:
        G_lo, G_hi, A_lo, A_hi = G.copy(), G.copy(), A, A
    info.update({"noise_sd_mV": sd, "noise_sd_given": noise_sd_mV is not None,
                 "n_boot": len(Gs), "level": level})
    return Calibration(r_m=np.arange(grid.m) * grid.dx, G=G, A_mV_per_bar=A * PA_PER_BAR,
                       G_lo=G_lo, G_hi=G_hi, A_lo=A_lo * PA_PER_BAR, A_hi=A_hi * PA_PER_BAR,
                       component=component, method=method, U_fit_mV=U_fit, info=info)
