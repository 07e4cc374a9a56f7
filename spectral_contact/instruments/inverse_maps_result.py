"""The surface inverse's result (issue 21): ``MapInversion``, its record, maps and plot."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..numerics.blas_threads import single_blas_thread
from .inverse_laws import law_curves
from .inverse_result import LineInversion

__all__ = ["MapInversion", "MAP_OUT_KEYS"]

MAP_OUT_KEYS = ("x_m", "y_m", "pressure_Pa", "pressure_sd_Pa", "shear_x_Pa", "shear_x_sd_Pa",
                "shear_y_Pa", "shear_y_sd_Pa")


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

    # the record's accessors are the line result's (one implementation)
    summary = LineInversion.summary
    to_dict = LineInversion.to_dict
    laws = LineInversion.laws
    __getattr__ = LineInversion.__getattr__

    def resolve(self, p_Pa, qx_Pa, qy_Pa):
        """The tractions as the posterior mean sees them: R (p, q_x, q_y), the posterior mean of
        noise-free data made from these tractions, with this inversion's prior and
        hyperparameters.  The mean minus R(truth) is the noise's part of the error, the truth
        minus R(truth) the resolution's (what the film, the apparatus and the noise do not let
        through).  Arrays [x, y] on this inversion's grid; returns three arrays."""
        with single_blas_thread():  # the contact prior's small dense algebra, as in the inverse
            return self.resolution_operator(np.stack([p_Pa, qx_Pa, qy_Pa]))

    def maps(self) -> dict:
        return {k: getattr(self, k) for k in MAP_OUT_KEYS}

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
            for label, qq in law_curves(r["laws"], pp):
                a.plot(pp * kPa, qq * kPa, label=label)
        a.set_xlabel("p [kPa]")
        a.set_ylabel("q along the total shear [kPa]")
        a.legend(fontsize=7)
        return fig
