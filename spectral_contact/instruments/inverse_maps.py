"""From measured base-stress maps to the interface: tractions p(x, y), q_x(x, y), q_y(x, y)
with pointwise uncertainty, the totals F, Q_x, Q_y and the local friction law (issue 21,
surfaces; the line records are ``instruments.inverse``).

Data.  On a uniform grid x_i, y_j (the file's frame; no apex assumed), arrays [x, y] of

    d_zz = -sigma_zz(x, y, 0)  (compression > 0),  d_xz = sigma_xz(x, y, 0),  d_yz = sigma_yz(x, y, 0)

(``view="base"``: the package's ``--maps`` keys and signs) or the MEMS view through the 2D
apparatus functions (``view="sensor"``: S_zz = G_zz (*) d_zz, S_xz = G_xz (*) d_xz,
S_yz = G_xz (*) d_yz, as ``instruments.sensor.sensor_maps`` writes them).

Forward map.  Linear and diagonal in Fourier space: per wavevector k the 3x3 symbol M(k) that
takes the surface tractions (p^, q_x^, q_y^) to the data, built from the film's public base
transfer (``physics.film.Film.base_transfer``: physics3d.md A, B, C and sech K) times the
apparatus symbols; M(0) = I (the base carries the loads).  Nyquist planes: the terms odd in n
are averaged over the two aliases (``Grid.alias_average``), as the solver does.

The window.  A stationary model is exact on a periodic record.  ``solve --maps`` writes the
solver's periodic domain, whose margin lets the base field decay (~1e-4 of its peak at the
border): there the record *is* one period, and nothing lies beyond it.  A record cut from a
larger field (a measured window) still carries 4-12 % of the peak at its border, and a
periodic model would wrap those tails.  Such records are refused, not inverted: after the fit,
if the re-predicted data on the outermost rows or columns exceed ``BORDER_Z`` noise sd and
``BORDER_REL`` of the peak, the call raises InputError (an axis along which the field does not
vary, a line record repeated along y, is periodic and not checked) (modelling tractions beyond a window,
as the line inverse does with its margins, is not done for maps).

Prior.  p, q_x, q_y are independent zero-mean stationary Gaussian processes with Matern
spectral densities, per field f

    lambda_f(k) = s_f^2 4 pi nu l_f^2 (1 + k^2 l_f^2)^-(nu + 1)     (pointwise variance s_f^2),

amplitudes s_p, s_qx, s_qy, lengths l_p and l_q (q_x and q_y share one), smoothness nu.  The
noise is white and Gaussian, one sd per component (sigma_zz, sigma_xz, sigma_yz).  The eight
hyperparameters maximise the evidence, exact for a stationary model on a periodic record and
cheap: per mode the data covariance M Lambda M^H + Sigma_n is 3x3 (Whittle's form, exact for a
periodic field); analytic gradient (checked against differences), L-BFGS-B; nu is then chosen
among ``KERNEL_NUS`` by the same evidence.  None is set by hand.

Posterior.  Per mode: A = M^H D^-1 M + Lambda^-1, mean A^-1 M^H D^-1 d^, covariance A^-1.  The
pointwise variance (1/N) Sum_k diag A^-1(k) is exact, and the same at every point (the prior is
stationary): it is the posterior's average uncertainty, not larger at the contact's edges where
the errors concentrate (see studies/inverse_maps.py for the coverage this gives).  The
covariance of two cells is the inverse transform of A^-1 at their offset.  Totals F = Int p dA,
Q = Int q dA are the k = 0 mode, with variances N A^-1(0) dA^2.  (The tractions are on the
record's grid; the margin of the solver's domain is part of it.)

Resolution length.  The posterior mean of p is the truth seen through the point-spread
function R_pp = [A^-1 M^H D^-1 M]_pp; the resolution length is sqrt of its equivalent area
(Int R)^2 / Int R^2 (the side of the square of equal area).

Laws.  The local (p, q_par) pairs, q_par = q . e with e the direction of the total tangential
force, at cells where p is resolved (mean > ``RESOLVED_Z`` sd) and at least
``LAW_EDGE_GUARD`` resolution lengths inside the resolved region, thinned to a lattice of step
half a resolution length (at most ``LAW_MAX_PAIRS``), go to ``inverse.fit_laws`` with their full
posterior covariance: Amontons, q = tau0 + alpha p and the power law, sigmas and AIC.

Units: lengths in h in the core, stresses scaled by the data's peak; SI at the edge.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..numerics.grid import Grid
from ..physics.film import Film

__all__ = ["invert", "invert_maps", "read_maps", "MapInversion", "MAP_INVERT_JSON_KEYS",
           "MAP_OUT_KEYS", "base_maps_from_tractions", "KERNEL_NUS", "BORDER_Z"]

KERNEL_NU = 1.5
"""Default smoothness of the Matern prior."""
KERNEL_NUS = (0.5, 1.5, 2.5)
"""The smoothness values the evidence chooses among."""
BORDER_Z = 3.0
BORDER_REL = 1e-3
"""A record is a window (refused) if its re-predicted border data exceed this many noise sd
and ``BORDER_REL`` of the data's peak (noise-free records: the peak alone)."""
RESOLVED_Z = 3.0
LAW_EDGE_GUARD = 1.0
LAW_MAX_PAIRS = 300
MIN_POINTS = 8

MAP_OUT_KEYS = ("x_m", "y_m", "pressure_Pa", "pressure_sd_Pa", "shear_x_Pa", "shear_x_sd_Pa",
                "shear_y_Pa", "shear_y_sd_Pa")
MAP_INVERT_JSON_KEYS = ("force_N", "force_sigma_N", "tangential_force_x_N",
                        "tangential_force_x_sigma_N", "tangential_force_y_N",
                        "tangential_force_y_sigma_N", "Q_over_P", "Q_over_P_sigma",
                        "resolution_length_m", "regularisation", "log_evidence",
                        "noise_sd_zz_Pa", "noise_sd_xz_Pa", "noise_sd_yz_Pa", "view", "points",
                        "laws")

_VIEWS = {"base": ("base_sigma_zz_Pa", "base_sigma_xz_Pa", "base_sigma_yz_Pa"),
          "sensor": ("S_zz_Pa", "S_xz_Pa", "S_yz_Pa")}


# --- forward ----------------------------------------------------------------------------------

def _symbol(grid: Grid, film: Film, apparatus=None, h_m: float = 1.0):
    """M(k): (kshape + (3, 3)) complex, data (d_zz, d_xz, d_yz)^ per traction (p, q_x, q_y)^,
    on ``grid`` (lengths in h).  apparatus: None or (G_zz, G_xz) ApparatusFunction [m]."""
    kmag = grid.kmag
    coef = film.base_coefficients(kmag)
    one, zero = np.ones(grid.kshape, complex), np.zeros(grid.kshape, complex)
    cols = []
    for szz, tx, ty in ((-one, zero, zero), (zero, one, zero), (zero, zero, one)):
        s0, (x0, y0) = grid.alias_average(
            lambda n, szz=szz, tx=tx, ty=ty: film.base_transfer(n, kmag, szz, (tx, ty), coef))
        cols.append((-s0, x0, y0))
    M = np.empty(grid.kshape + (3, 3), complex)
    for j, col in enumerate(cols):
        for i, c in enumerate(col):
            M[..., i, j] = c
    if apparatus is not None:
        gzz = np.asarray(apparatus[0].transform(kmag / h_m), float)
        gxz = np.asarray(apparatus[1].transform(kmag / h_m), float)
        M[..., 0, :] *= gzz[..., None]
        M[..., 1:, :] *= gxz[..., None, None]
    return M


def base_maps_from_tractions(x_m, y_m, p_Pa, qx_Pa, qy_Pa, thickness: float,
                             poisson: float = 0.5):
    """Base stresses (sigma_zz, sigma_xz, sigma_yz)(x, y, 0) [Pa] of surface tractions on a
    uniform grid taken as one period (pad the tractions with zeros well beyond them).  Signs of
    the package: p >= 0 in compression, q = (sigma_xz, sigma_yz)(h); sigma_zz(base) < 0 in
    compression.  (The film's ``base_stresses`` on the grid.)"""
    from ..numerics.fft import get_rfft

    x, y = np.asarray(x_m, float), np.asarray(y_m, float)
    dx, dy = (x[-1] - x[0]) / (x.size - 1), (y[-1] - y[0]) / (y.size - 1)
    grid = Grid((x.size, y.size), (x.size * dx / thickness, y.size * dy / thickness))
    film = Film(1.0, poisson)
    szz, (sxz, syz) = film.base_stresses(get_rfft(grid.shape), grid, -np.asarray(p_Pa, float),
                                         (np.asarray(qx_Pa, float), np.asarray(qy_Pa, float)))
    return szz, sxz, syz


def _weights(shape):
    """Multiplicity of each rfft2 mode in the full spectrum (2, or 1 on the ky = 0 and
    ky = Nyquist columns)."""
    ny = shape[1]
    w = np.full(ny // 2 + 1, 2.0)
    w[0] = 1.0
    if ny % 2 == 0:
        w[-1] = 1.0
    return w[None, :]


# --- prior and evidence -----------------------------------------------------------------------

def _spectrum(kmag, s, length, nu, cell):
    """Matern spectral density on the grid (per-mode eigenvalue of the covariance circulant)
    and d log lambda / d log length."""
    u = (kmag * length) ** 2
    lam = s * s * 4.0 * math.pi * nu * length**2 * (1.0 + u) ** (-(nu + 1.0)) / cell
    return lam, 2.0 - 2.0 * (nu + 1.0) * u / (1.0 + u)


class _Model:
    """Per-mode Gaussian model of the (scaled) data on the periodic record."""

    def __init__(self, M, Y, shape, cell, kmag, nu):
        self.M, self.Y = M, Y  # Y: (kshape, 3) rfft2 of the data (unnormalised)
        self.N = shape[0] * shape[1]
        self.w = np.broadcast_to(_weights(shape), kmag.shape)
        self.cell, self.kmag, self.nu = cell, kmag, nu

    def lam(self, th):
        lp, lq = math.exp(th[0]), math.exp(th[1])
        s = np.exp(th[2:5])
        lam_p, dp = _spectrum(self.kmag, s[0], lp, self.nu, self.cell)
        lam_x, dq = _spectrum(self.kmag, s[1], lq, self.nu, self.cell)
        lam_y, _ = _spectrum(self.kmag, s[2], lq, self.nu, self.cell)
        return np.stack([lam_p, lam_x, lam_y], -1), dp, dq

    def evaluate(self, th, grad=False):
        lam, dp, dq = self.lam(th)
        noise = np.exp(2.0 * th[5:8])
        M = self.M
        S = np.einsum("...ij,...j,...kj->...ik", M, lam, M.conj())
        S[..., [0, 1, 2], [0, 1, 2]] += noise
        Si = np.linalg.inv(S)
        _, logdet = np.linalg.slogdet(S)
        a = np.einsum("...ij,...j->...i", Si, self.Y)
        quad = np.einsum("...i,...i->...", self.Y.conj(), a).real / self.N
        w = self.w
        logev = -0.5 * float(np.sum(w * (quad + logdet))) - 1.5 * self.N * math.log(2 * math.pi)
        if not grad:
            return logev
        # d logev = 1/2 Sum w tr(G dS), G = a a^H / N - Si
        Ma = np.einsum("...ij,...i->...j", M.conj(), a)            # m_f^H a
        SiM = np.einsum("...ij,...jf->...if", Si, M)
        mSm = np.einsum("...if,...if->...f", M.conj(), SiM).real    # m_f^H Si m_f
        gf = (np.abs(Ma) ** 2 / self.N - mSm) * lam                 # x lambda_f: d/d log lambda_f
        g = np.zeros(8)
        g[0] = 0.5 * np.sum(w * gf[..., 0] * dp)
        g[1] = 0.5 * np.sum(w * (gf[..., 1] + gf[..., 2]) * dq)
        for f in range(3):
            g[2 + f] = np.sum(w * gf[..., f])  # 1/2 x 2 (lambda ~ s^2)
        Gcc = (np.abs(a) ** 2 / self.N - np.real(Si[..., [0, 1, 2], [0, 1, 2]]))
        for c in range(3):
            g[5 + c] = np.sum(w * Gcc[..., c]) * noise[c]
        return logev, g

    def posterior(self, th):
        """Per-mode posterior covariance A^-1 (kshape, 3, 3) and mean (kshape, 3)."""
        lam, _, _ = self.lam(th)
        noise = np.exp(2.0 * th[5:8])
        M = self.M
        A = np.einsum("...ki,k,...kj->...ij", M.conj(), 1.0 / noise, M)
        A[..., [0, 1, 2], [0, 1, 2]] += 1.0 / lam
        C = np.linalg.inv(A)
        C = 0.5 * (C + np.swapaxes(C.conj(), -1, -2))
        b = np.einsum("...ki,k,...k->...i", M.conj(), 1.0 / noise, self.Y)
        mean = np.einsum("...ij,...j->...i", C, b)
        return C, mean, A


def _noise_guess(d):
    """Noise sd from second differences along both axes (white noise: var = 6 sigma^2)."""
    d2 = np.concatenate([np.diff(d, 2, axis=0).ravel(), np.diff(d, 2, axis=1).ravel()])
    return float(np.median(np.abs(d2))) / 0.6745 / math.sqrt(6.0)


def _optimise(model: _Model, d, dt, start=None):
    from scipy.optimize import minimize

    scale = max(float(np.max(np.abs(d))), 1e-300)
    n0 = [min(max(_noise_guess(c), 1e-4 * scale), 0.3 * scale) for c in d]
    th0 = np.array([math.log(0.5), math.log(0.5), math.log(0.5 * scale), math.log(0.3 * scale),
                    math.log(0.1 * scale)] + [math.log(v) for v in n0])
    lo = np.array([math.log(max(dt, 0.02))] * 2 + [math.log(1e-5 * scale)] * 3
                  + [math.log(1e-8 * scale)] * 3)
    hi = np.array([math.log(20.0)] * 2 + [math.log(1e3 * scale)] * 3 + [math.log(10 * scale)] * 3)
    th0 = np.clip(th0 if start is None else start, lo, hi)

    def f(z):
        try:
            v, g = model.evaluate(z, grad=True)
        except np.linalg.LinAlgError:
            return 1e300, np.zeros(z.size)
        if not np.isfinite(v):
            return 1e300, np.zeros(z.size)
        return -v, -g

    res = minimize(f, th0, jac=True, method="L-BFGS-B", bounds=list(zip(lo, hi)),
                   options={"maxiter": 400, "ftol": 1e-12, "gtol": 1e-4})
    return res.x, -res.fun, res


# --- the result -------------------------------------------------------------------------------

@dataclass(repr=False, eq=False)
class MapInversion:
    """Tractions at the interface inferred from base-stress maps (SI at the edge).

    x_m, y_m : the grid of the tractions [m] (the record's; with a pad, the record's cells
    only); pressure_Pa (p >= 0 in compression), shear_x_Pa, shear_y_Pa (q = (sigma_xz,
    sigma_yz)(h)) : posterior means, arrays [x, y]; *_sd_Pa : posterior sd.
    ``summary()``: the JSON record (``MAP_INVERT_JSON_KEYS``); ``maps()``: the NPZ arrays
    (``MAP_OUT_KEYS``); ``plot()``: a Figure.
    """

    x_m: np.ndarray
    y_m: np.ndarray
    pressure_Pa: np.ndarray
    pressure_sd_Pa: np.ndarray
    shear_x_Pa: np.ndarray
    shear_x_sd_Pa: np.ndarray
    shear_y_Pa: np.ndarray
    shear_y_sd_Pa: np.ndarray
    record: dict
    data: dict
    pairs: dict
    resolution_operator: object = None  # (p, q_x, q_y) [Pa] maps -> what the mean sees of them

    def summary(self) -> dict:
        return dict(self.record)

    def resolve(self, p_Pa, qx_Pa, qy_Pa):
        """The tractions as the posterior mean sees them: R (p, q_x, q_y), R = A^-1 M^H D^-1 M
        per mode (the mean of noise-free data made from these tractions, with this inversion's
        hyperparameters).  The mean minus R(truth) is the noise's part of the error, the truth
        minus R(truth) the resolution's (what the film, the apparatus and the noise do not let
        through).  Arrays [x, y] on this inversion's grid; returns three arrays."""
        return self.resolution_operator(np.stack([p_Pa, qx_Pa, qy_Pa]))

    to_dict = summary

    @property
    def laws(self) -> dict:
        return self.record["laws"]

    def maps(self) -> dict:
        return {k: getattr(self, k) for k in MAP_OUT_KEYS}

    def __getattr__(self, name):
        rec = self.__dict__.get("record")
        if rec is not None and name in rec:
            return rec[name]
        raise AttributeError(name)

    def __repr__(self):
        r = self.record
        return (f"<MapInversion: F = {r['force_N']:.5g} +- {r['force_sigma_N']:.2g} N, Q_x = "
                f"{r['tangential_force_x_N']:.5g} +- {r['tangential_force_x_sigma_N']:.2g} N, "
                f"Q_y = {r['tangential_force_y_N']:.3g} +- "
                f"{r['tangential_force_y_sigma_N']:.2g} N; resolution "
                f"{r['resolution_length_m'] * 1e3:.3g} mm; best law {r['laws'].get('best')}>")

    def plot(self, fig=None):
        """Maps of p, |q| and their sd; the line y = 0 with 95 % bands; the data against the
        data re-predicted from the estimate on y = 0, with residuals; the local (p, q) pairs
        with the fitted laws."""
        from matplotlib.figure import Figure

        fig = fig or Figure(figsize=(14, 8), layout="constrained")
        ax = fig.subplots(2, 4)
        mm, kPa = 1e3, 1e-3
        x, y = self.x_m * mm, self.y_m * mm
        qabs = np.hypot(self.shear_x_Pa, self.shear_y_Pa)
        with np.errstate(invalid="ignore", divide="ignore"):
            qsd = np.sqrt((self.shear_x_Pa * self.shear_x_sd_Pa) ** 2
                          + (self.shear_y_Pa * self.shear_y_sd_Pa) ** 2) / qabs
        qsd = np.where(qabs > 0, qsd, np.hypot(self.shear_x_sd_Pa, self.shear_y_sd_Pa))
        # the maps: where p or |q| exceeds 5 % of its peak, and 2 h around
        big = (np.abs(self.pressure_Pa) > 0.05 * np.abs(self.pressure_Pa).max()) | \
            (qabs > 0.05 * qabs.max())
        h = self.record["thickness_m"] * mm
        if big.any():
            ii, jj = np.nonzero(big.any(1))[0], np.nonzero(big.any(0))[0]
            sx = (x >= x[ii.min()] - 2 * h) & (x <= x[ii.max()] + 2 * h)
            sy = (y >= y[jj.min()] - 2 * h) & (y <= y[jj.max()] + 2 * h)
        else:
            sx, sy = np.ones(x.size, bool), np.ones(y.size, bool)
        for a, f, title in ((ax[0, 0], self.pressure_Pa, "p [kPa]"),
                            (ax[0, 1], qabs, "|q| [kPa]"),
                            (ax[1, 0], self.pressure_sd_Pa, "sd(p) [kPa]"),
                            (ax[1, 1], qsd, "sd(|q|) [kPa] (first order)")):
            f = f[np.ix_(sx, sy)] * kPa
            lo, hi = float(f.min()), float(f.max())
            if hi - lo < 1e-6 * max(abs(hi), 1e-300):  # uniform (stationary prior): one colour
                lo, hi = lo - 0.5 * abs(lo) - 1e-300, hi + 0.5 * abs(hi) + 1e-300
            im = a.pcolormesh(x[sx], y[sy], f.T, shading="nearest", cmap="viridis",
                              vmin=lo, vmax=hi)
            fig.colorbar(im, ax=a, shrink=0.8)
            a.set_aspect("equal")
            a.set_title(title, fontsize=9)
            a.set_xlabel("x [mm]")
            a.set_ylabel("y [mm]")
        j = int(np.argmin(np.abs(self.y_m)))
        a = ax[0, 2]
        for f, s, c, lab in ((self.pressure_Pa, self.pressure_sd_Pa, "C0", "p"),
                             (self.shear_x_Pa, self.shear_x_sd_Pa, "C1", "q_x"),
                             (self.shear_y_Pa, self.shear_y_sd_Pa, "C2", "q_y")):
            a.fill_between(x, (f[:, j] - 1.96 * s[:, j]) * kPa, (f[:, j] + 1.96 * s[:, j]) * kPa,
                           color=c, alpha=0.3)
            a.plot(x, f[:, j] * kPa, c + "-", label=f"{lab} (95 % band)")
        r = self.record
        a.set_title(f"line y = {self.y_m[j] * mm:.3g} mm\nF = {r['force_N']:.4g} +- "
                    f"{r['force_sigma_N']:.2g} N, Q_x/F = {r['Q_over_P']:.4g}", fontsize=9)
        a.set_xlabel("x [mm]")
        a.set_ylabel("traction [kPa]")
        a.set_xlim(x[sx][0], x[sx][-1])
        a.legend(fontsize=7)
        a = ax[0, 3]
        d = self.data
        for i, (c, lab) in enumerate((("C0", "zz"), ("C1", "xz"), ("C2", "yz"))):
            a.plot(x, d["data"][i][:, j] * kPa, c + ".", ms=2, label=f"data {lab}")
            a.plot(x, d["fit"][i][:, j] * kPa, "k-", lw=0.7)
        a.set_title("data (dots), re-predicted (lines)", fontsize=9)
        a.set_xlabel("x [mm]")
        a.set_ylabel(("S" if r["view"] == "sensor" else "base stress") + " [kPa]")
        a.set_xlim(x[sx][0], x[sx][-1])
        a.legend(fontsize=7)
        a = ax[1, 2]
        for i, (c, lab) in enumerate((("C0", "zz"), ("C1", "xz"), ("C2", "yz"))):
            a.plot(x, (d["data"][i][:, j] - d["fit"][i][:, j]) * kPa, c + "-", lw=0.7,
                   label=f"residual {lab}")
        nz = r["noise_sd_zz_Pa"] * kPa
        a.axhspan(-2 * nz, 2 * nz, color="0.85", zorder=0, label="+-2 noise sd (zz)")
        a.set_xlabel("x [mm]")
        a.set_ylabel("residual [kPa]")
        a.set_xlim(x[sx][0], x[sx][-1])
        a.legend(fontsize=7)
        a = ax[1, 3]
        pr = self.pairs
        if pr["p"].size:
            a.errorbar(pr["p"] * kPa, pr["q"] * kPa, xerr=pr["p_sd"] * kPa, yerr=pr["q_sd"] * kPa,
                       fmt="k.", ms=3, lw=0.5, label="local (p, q_par), 1 sd")
            pp = np.linspace(0, float(pr["p"].max()), 50)
            laws = r["laws"]
            for law, f in (("amontons", lambda p, rr: rr["mu"] * p),
                           ("linear", lambda p, rr: rr["tau0_Pa"] + rr["alpha"] * p),
                           ("power", lambda p, rr: rr["k_Pa"] * (p / rr["p_ref_Pa"]) ** rr["n"])):
                rec = laws.get(law, {})
                if "aic" in rec:
                    a.plot(pp * kPa, f(pp, rec) * kPa, label=f"{law} (AIC {rec['aic']:.1f})")
        a.set_xlabel("p [kPa]")
        a.set_ylabel("q along the total shear [kPa]")
        a.legend(fontsize=7)
        return fig


# --- checks and reading -----------------------------------------------------------------------

def _check_axis(a, name, src):
    a = np.asarray(a, dtype=float)
    if a.ndim != 1:
        raise InputError(f"{src}{name} must be a 1D array; got shape {a.shape}")
    if a.size < MIN_POINTS:
        raise InputError(f"{src}{name} has {a.size} points; the inversion needs at least "
                         f"{MIN_POINTS} along each axis")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{src}{name} has non-finite values")
    d = np.diff(a)
    step = (a[-1] - a[0]) / (a.size - 1)
    if np.any(d <= 0) or np.max(np.abs(d - step)) > 1e-3 * step:
        raise InputError(f"{src}{name} must be strictly increasing and uniformly spaced "
                         f"(within 0.1 %)")
    return a


def _check_maps(x_m, y_m, fields, names, src=""):
    x = _check_axis(x_m, "x_m", src)
    y = _check_axis(y_m, "y_m", src)
    out = []
    for f, nm in zip(fields, names):
        f = np.asarray(f, dtype=float)
        if f.shape != (x.size, y.size):
            raise InputError(f"{src}{nm} has shape {f.shape}; x_m and y_m need "
                             f"({x.size}, {y.size}) (arrays indexed [x, y])")
        if not np.all(np.isfinite(f)):
            raise InputError(f"{src}{nm} has non-finite values")
        out.append(f)
    if not any(np.any(f) for f in out):
        raise InputError(f"{src}the maps are zero everywhere: nothing to invert")
    return x, y, out


def read_maps(path):
    """Base-stress maps from an NPZ: ``x_m, y_m`` and either ``base_sigma_zz_Pa,
    base_sigma_xz_Pa, base_sigma_yz_Pa`` (the package's ``--maps`` keys and signs: sigma_zz < 0
    in compression) or ``S_zz_Pa, S_xz_Pa, S_yz_Pa`` (the MEMS view, S_zz > 0 in compression),
    arrays [x, y]; one view per file (a ``solve --maps --sensor`` file holds both: refused,
    keep one).  Returns (x_m, y_m, (d_zz, d_xz,
    d_yz), view) with d_zz > 0 in compression.  Raises InputError (one line naming the file)."""
    import zipfile

    name = str(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            keys = set(z.files)
            arrays = {k: z[k] for k in keys if k in {"x_m", "y_m", *_VIEWS["base"],
                                                     *_VIEWS["sensor"]}}
    except FileNotFoundError:
        raise InputError(f"{name}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{name}: is a directory, not an NPZ file") from None
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as e:
        raise InputError(f"{name}: not a readable NPZ file ({type(e).__name__})") from None
    want = " or ".join("x_m, y_m, " + ", ".join(v) for v in _VIEWS.values())
    for k in ("x_m", "y_m"):
        if k not in keys:
            raise InputError(f"{name}: missing {k}; need {want}")
    present = [v for v, ks in _VIEWS.items() if any(k in keys for k in ks)]
    if not present:
        raise InputError(f"{name}: no stress maps; need {want}")
    if len(present) > 1:
        raise InputError(f"{name}: mixes views (base_sigma_* and S_*, as solve --maps --sensor "
                         f"writes); keep one in the file: {want}")
    view = present[0]
    miss = [k for k in _VIEWS[view] if k not in keys]
    if miss:
        raise InputError(f"{name}: missing {', '.join(miss)}; need {want}")
    x, y, (zz, xz, yz) = _check_maps(arrays["x_m"], arrays["y_m"],
                                     [arrays[k] for k in _VIEWS[view]], _VIEWS[view],
                                     src=f"{name}: ")
    return x, y, ((-zz if view == "base" else zz), xz, yz), view


# --- the inversion ----------------------------------------------------------------------------

def invert_maps(x_m, y_m, zz_Pa, xz_Pa, yz_Pa, *, thickness: float = 0.002,
                poisson: float = 0.5, view: str = "base", apparatus=None,
                smoothness=KERNEL_NUS, progress=None) -> MapInversion:
    """Interface tractions from maps (see the module docstring).

    x_m, y_m : uniform increasing axes [m]; zz_Pa : -sigma_zz(x, y, 0) (compression > 0) or
    S_zz; xz_Pa, yz_Pa : sigma_xz, sigma_yz (x, y, 0) or S_xz, S_yz; arrays [x, y].
    view : "base" or "sensor" (apparatus: None for the paper's G_zz, G_xz or a pair of
    ``ApparatusFunction``); thickness [m], poisson : the film; smoothness : the Matern nu
    values the evidence chooses among; progress : None or a callable(str).
    """
    from ..physics.scene import check_poisson, check_positive

    say = progress or (lambda s: None)
    h = check_positive("thickness", thickness, "m")
    nu = check_poisson(poisson)
    x, y, d = _check_maps(x_m, y_m, (zz_Pa, xz_Pa, yz_Pa), ("zz", "xz", "yz"))
    if view not in ("base", "sensor"):
        raise InputError(f"view must be 'base' or 'sensor'; got {view!r}")
    if view == "sensor":
        from .sensor import _resolve

        apparatus = _resolve(apparatus)
    elif apparatus is not None:
        raise InputError("an apparatus applies to sensor maps (view='sensor'), not to base "
                         "stresses")
    d = np.stack(d)
    nx, ny = x.size, y.size
    dx, dy = (x[-1] - x[0]) / (nx - 1) / h, (y[-1] - y[0]) / (ny - 1) / h
    scale = float(np.max(np.abs(d)))
    ds = d / scale
    film = Film(1.0, nu)
    grid = Grid((nx, ny), (nx * dx, ny * dy))
    M = _symbol(grid, film, apparatus, h)
    Y = np.moveaxis(np.fft.rfft2(ds, axes=(1, 2)), 0, -1)
    N = nx * ny
    fits = []
    th_prev = None
    for knu in smoothness:
        say(f"evidence, Matern nu = {knu:g}")
        model = _Model(M, Y, (nx, ny), dx * dy, grid.kmag, float(knu))
        th, logev, opt = _optimise(model, ds, min(dx, dy), th_prev)
        th_prev = th
        fits.append((logev, float(knu), th, opt, model))
    logev, knu, theta, opt, model = max(fits, key=lambda f: f[0])
    noise = np.exp(theta[5:8])
    C, mean_k, _ = model.posterior(theta)
    mean = np.fft.irfft2(np.moveaxis(mean_k, -1, 0), s=(nx, ny), axes=(1, 2))
    fit = np.fft.irfft2(np.moveaxis(np.einsum("...ij,...j->...i", M, mean_k), -1, 0),
                        s=(nx, ny), axes=(1, 2))
    # the border: the outermost rows and columns, along each axis where the field varies
    # (a field invariant along an axis, a line record repeated along y, is periodic along it)
    edges = [np.zeros((3, 1))]
    for ax in (1, 2):
        if np.any(np.ptp(fit, axis=ax).max(axis=-1) > BORDER_Z * noise):
            edges.append(np.abs(np.take(fit, [0, -1], axis=ax)).reshape(3, -1))
    border = np.concatenate(edges, axis=1).max(axis=1)
    border_z = border / noise
    if np.any((border_z > BORDER_Z) & (border > BORDER_REL)):
        c = int(np.argmax(border_z))
        raise InputError(f"the record's border carries {border_z[c]:.3g} noise sd of signal "
                         f"({('zz', 'xz', 'yz')[c]}): a window cut from a larger field, which "
                         f"a periodic model would wrap; give maps that extend until the base "
                         f"field has decayed (as solve --maps writes them)")
    w = _weights((nx, ny))
    cov1 = np.array([[float(np.sum(w * C[..., i, j].real)) / N for j in range(3)]
                     for i in range(3)])
    sd = np.sqrt(np.diag(cov1))
    # totals (SI): the k = 0 mode
    cellA = dx * dy * h * h
    tot = mean.sum(axis=(1, 2)) * cellA * scale
    vtot = N * C[0, 0].real * (cellA * scale) ** 2
    F, Qx, Qy = tot
    ratio = Qx / F if F else float("nan")
    vR = ((vtot[1, 1] - 2 * ratio * vtot[0, 1] + ratio**2 * vtot[0, 0]) / F**2 if F
          else float("nan"))
    # resolution: the point-spread function of p
    R = np.einsum("...ij,...kj,k,...kl->...il", C, M.conj(), 1.0 / noise**2, M)[..., 0, 0].real
    psf = np.fft.irfft2(R, s=(nx, ny))
    res_h = math.sqrt(float(psf.sum() ** 2 / np.sum(psf**2)) * dx * dy)
    pairs, laws = _laws(mean * scale, sd * scale, C * scale**2, (nx, ny), (dx, dy), res_h,
                        (Qx, Qy))
    lp, lq = np.exp(theta[:2])
    sf = np.exp(theta[2:5]) * scale
    rec = {"force_N": float(F), "force_sigma_N": float(math.sqrt(max(vtot[0, 0], 0.0))),
           "tangential_force_x_N": float(Qx),
           "tangential_force_x_sigma_N": float(math.sqrt(max(vtot[1, 1], 0.0))),
           "tangential_force_y_N": float(Qy),
           "tangential_force_y_sigma_N": float(math.sqrt(max(vtot[2, 2], 0.0))),
           "Q_over_P": float(ratio), "Q_over_P_sigma": float(math.sqrt(max(vR, 0.0))),
           "resolution_length_m": res_h * h,
           "resolution_rule": "sqrt of the equivalent area (Int R)^2 / Int R^2 of the "
                              "posterior mean's point-spread function R for p",
           "regularisation": {
               "prior": f"p, q_x, q_y: independent zero-mean stationary Gaussian processes, "
                        f"Matern spectra (nu = {knu:g})",
               "smoothness_nu": knu,
               "log_evidence_by_nu": {f"{f[1]:g}": float(f[0] - 3 * N * math.log(scale))
                                      for f in fits},
               "length_p_m": float(lp * h), "length_q_m": float(lq * h),
               "amplitude_p_Pa": float(sf[0]), "amplitude_qx_Pa": float(sf[1]),
               "amplitude_qy_Pa": float(sf[2]),
               "chosen_by": "maximum evidence (marginal likelihood of the periodic record, "
                            "exact per mode)",
               "optimizer_converged": bool(opt.success)},
           "log_evidence": float(logev - 3 * N * math.log(scale)),
           "noise_sd_zz_Pa": float(noise[0] * scale), "noise_sd_xz_Pa": float(noise[1] * scale),
           "noise_sd_yz_Pa": float(noise[2] * scale),
           "border_signal_over_noise": [float(v) for v in border_z],
           "variance": "exact per mode (stationary prior on the periodic record): the same "
                       "sd at every point",
           "view": view, "points": [int(nx), int(ny)], "thickness_m": h, "poisson": nu,
           "resolved_rule": f"laws on cells where p > {RESOLVED_Z:g} sd(p), at least "
                            f"{LAW_EDGE_GUARD:g} resolution lengths inside that region, on a "
                            f"lattice of half a resolution length",
           "laws": laws}
    data = {"data": d, "fit": fit * scale}
    mm = mean * scale
    sdm = np.broadcast_to((sd * scale)[:, None, None], (3, nx, ny)).copy()
    Rfull = np.einsum("...ij,...kj,k,...kl->...il", C, M.conj(), 1.0 / noise**2, M)

    def resolution_operator(f):
        fk = np.moveaxis(np.fft.rfft2(np.asarray(f, float), axes=(1, 2)), 0, -1)
        out = np.fft.irfft2(np.moveaxis(np.einsum("...ij,...j->...i", Rfull, fk), -1, 0),
                            s=(nx, ny), axes=(1, 2))
        return out[0], out[1], out[2]

    return MapInversion(x, y, mm[0], sdm[0], mm[1], sdm[1], mm[2], sdm[2], rec, data, pairs,
                        resolution_operator)


def _laws(mean, sd, C, shape, steps, res, Q):
    """Local (p, q_par) pairs and the law fits (see the module docstring).  C: the per-mode
    posterior covariance [Pa^2]; the covariance of two cells is its inverse transform at
    their offset."""
    from scipy.ndimage import distance_transform_edt

    from .inverse_laws import fit_laws

    nx, ny = shape
    dx, dy = steps
    p, qx, qy = mean
    Qx, Qy = Q
    nrm = math.hypot(Qx, Qy)
    e = (Qx / nrm, Qy / nrm) if nrm > 0 else (1.0, 0.0)
    q = e[0] * qx + e[1] * qy
    resolved = p > RESOLVED_Z * sd[0]
    dist = distance_transform_edt(resolved, sampling=(dx, dy))
    inside = resolved & (dist > LAW_EDGE_GUARD * res)
    sx, sy = max(1, int(round(0.5 * res / dx))), max(1, int(round(0.5 * res / dy)))
    lattice = np.zeros(shape, bool)
    lattice[::sx, ::sy] = True
    sel = np.argwhere(inside & lattice)
    if len(sel) > LAW_MAX_PAIRS:
        sel = sel[np.linspace(0, len(sel) - 1, LAW_MAX_PAIRS).astype(int)]
    empty = {"p": np.zeros(0), "q": np.zeros(0), "p_sd": np.zeros(0), "q_sd": np.zeros(0)}
    if len(sel) < 3:
        return empty, {"note": f"only {len(sel)} resolved cells at least {LAW_EDGE_GUARD:g} "
                               f"resolution lengths inside the contact: no law fitted",
                       "best": None}
    cov = {}
    for a, b in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)):
        cov[a, b] = np.fft.irfft2(C[..., a, b], s=shape)  # c_ab(r) = Cov(f_a(x + r), f_b(x))
    flip = (lambda c: np.roll(np.flip(c, (0, 1)), 1, (0, 1)))  # c(-r)
    cqq = (e[0] ** 2 * cov[1, 1] + e[1] ** 2 * cov[2, 2]
           + e[0] * e[1] * (cov[1, 2] + flip(cov[1, 2])))
    cpq = e[0] * cov[0, 1] + e[1] * cov[0, 2]
    ii, jj = sel[:, 0], sel[:, 1]
    di = (ii[:, None] - ii[None, :]) % nx
    dj = (jj[:, None] - jj[None, :]) % ny
    Cpp, Cqq, Cpq = cov[0, 0][di, dj], cqq[di, dj], cpq[di, dj]
    pp, qq = p[ii, jj], q[ii, jj]
    laws = fit_laws(pp, qq, 0.5 * (Cpp + Cpp.T), 0.5 * (Cqq + Cqq.T), Cpq)
    laws["direction"] = [float(e[0]), float(e[1])]
    laws["pairs"] = int(len(sel))
    pairs = {"p": pp, "q": qq, "p_sd": np.sqrt(np.diag(Cpp)), "q_sd": np.sqrt(np.diag(Cqq))}
    return pairs, laws


# --- entry: the package's ``invert`` for lines and maps ---------------------------------------

def invert(source=None, *, x_m=None, y_m=None, zz_Pa=None, xz_Pa=None, yz_Pa=None,
           view: str | None = None, thickness: float | None = None,
           poisson: float | None = None, apparatus=None, **line_options):
    """Interface tractions with uncertainties from base stresses: a line record (-> the line
    inverse, ``instruments.inverse.invert``, with all its options) or maps (-> ``invert_maps``):

        >>> from spectral_contact import invert, solve
        >>> inv = invert(solve(indenter="sphere", force=1.0, mu=1.0))  # its base maps
        >>> inv.summary()["force_N"], inv.maps()["pressure_Pa"].shape
        >>> inv = invert("maps.npz", thickness=0.002)  # solve --maps, or S_* maps
        >>> inv.plot()

    Maps when ``source`` is a 3D result (``ContactResult3D``: its base maps, view "base",
    thickness and poisson from its scene), an .npz path (``read_maps``), or when ``y_m`` is
    given with ``x_m, zz_Pa, xz_Pa, yz_Pa`` arrays [x, y] (zz > 0 in compression:
    -sigma_zz(x, y, 0) or S_zz; ``view`` "base" by default, or "sensor").  Returns a
    ``MapInversion``; otherwise what the line inverse returns (``LineInversion``)."""
    is_result3d = source is not None and hasattr(source, "base_sigma_yz")
    is_npz = isinstance(source, (str,)) or hasattr(source, "__fspath__")
    is_npz = is_npz and str(source).lower().endswith(".npz")
    if not (is_result3d or is_npz or y_m is not None):
        from .inverse import invert as invert_line_entry

        if yz_Pa is not None:
            raise InputError("yz_Pa is for maps: give y_m as well (arrays [x, y])")
        return invert_line_entry(source, x_m=x_m, zz_Pa=zz_Pa, xz_Pa=xz_Pa, view=view,
                                 thickness=thickness, poisson=poisson, apparatus=apparatus,
                                 **line_options)
    bad = [k for k, v in line_options.items() if v not in (None, False)]
    if bad:
        raise InputError(f"{bad[0]}: not available for maps; line records only")
    if is_result3d:
        mp = source.maps()
        x, y, kind = mp["x_m"], mp["y_m"], "base"
        zz, xz, yz = -mp["base_sigma_zz_Pa"], mp["base_sigma_xz_Pa"], mp["base_sigma_yz_Pa"]
        thickness = source.scene.thickness if thickness is None else thickness
        poisson = source.scene.poisson if poisson is None else poisson
    elif is_npz:
        x, y, (zz, xz, yz), kind = read_maps(source)
        if view is not None and view != kind:
            raise InputError(f"{source}: holds {kind} maps; view={view!r} does not apply")
    else:
        if x_m is None or zz_Pa is None or xz_Pa is None or yz_Pa is None:
            raise InputError("maps need x_m, y_m, zz_Pa, xz_Pa and yz_Pa")
        x, y, zz, xz, yz, kind = x_m, y_m, zz_Pa, xz_Pa, yz_Pa, view or "base"
    return invert_maps(x, y, zz, xz, yz, thickness=0.002 if thickness is None else thickness,
                       poisson=0.5 if poisson is None else poisson, view=kind,
                       apparatus=apparatus)
