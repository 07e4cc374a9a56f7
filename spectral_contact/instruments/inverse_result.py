"""The line inverse's result (issue 21): ``LineInversion``, its summary, profiles and plot."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .inverse_laws import law_curves

__all__ = ["LineInversion"]


@dataclass(repr=False, eq=False)
class LineInversion:
    """Tractions at the interface inferred from a line record (all SI at the edge).

    x_m : node positions [m] (the file's frame); pressure_Pa, shear_Pa : posterior means of p
    (>= 0 in compression) and q = sigma_xz(x, h) (> 0 drags the film toward +x);
    pressure_sd_Pa, shear_sd_Pa : posterior sd; mu_local, mu_local_sd : q/p and its sd where
    p > 3 sd (NaN elsewhere); ``summary()``: the JSON record (``INVERT_JSON_KEYS``);
    ``profiles()``: the CSV columns; ``plot()``: a Figure.
    """

    x_m: np.ndarray
    pressure_Pa: np.ndarray
    pressure_sd_Pa: np.ndarray
    shear_Pa: np.ndarray
    shear_sd_Pa: np.ndarray
    mu_local: np.ndarray
    mu_local_sd: np.ndarray
    record: dict
    data: dict
    cov: np.ndarray = None  # nodal covariance [Pa^2], (p, q) stacked

    def summary(self) -> dict:
        return dict(self.record)

    to_dict = summary

    @property
    def laws(self) -> dict:
        return self.record["laws"]

    def profiles(self) -> dict:
        return {"x_m": self.x_m, "pressure_Pa": self.pressure_Pa,
                "pressure_sd_Pa": self.pressure_sd_Pa, "shear_Pa": self.shear_Pa,
                "shear_sd_Pa": self.shear_sd_Pa, "mu_local": self.mu_local,
                "mu_local_sd": self.mu_local_sd}

    def __getattr__(self, name):
        rec = self.__dict__.get("record")
        if rec is not None and name in rec:
            return rec[name]
        raise AttributeError(name)

    def __repr__(self):
        r = self.record
        return (f"<LineInversion: P = {r['load_N_per_m']:.5g} +- {r['load_sigma_N_per_m']:.2g} N/m,"
                f" Q = {r['tangential_load_N_per_m']:.5g} +- "
                f"{r['tangential_load_sigma_N_per_m']:.2g} N/m, Q/P = {r['Q_over_P']:.4g} +- "
                f"{r['Q_over_P_sigma']:.2g}; resolution {r['resolution_length_m'] * 1e3:.3g} mm; "
                f"best law {r['laws'].get('best')}>")

    def plot(self, fig=None):
        """Tractions with 95 % bands, mu_local with its band, the data against the data
        re-predicted from the estimate (with residuals), and the local (p, q) pairs."""
        from matplotlib.figure import Figure

        fig = fig or Figure(figsize=(10, 8), layout="constrained")
        ax = fig.subplots(2, 2)
        mm, kPa = 1e3, 1e-3
        x = self.x_m * mm
        a = ax[0, 0]
        for f, s, c, lab in ((self.pressure_Pa, self.pressure_sd_Pa, "C0", "p"),
                             (self.shear_Pa, self.shear_sd_Pa, "C1", "q")):
            a.fill_between(x, (f - 1.96 * s) * kPa, (f + 1.96 * s) * kPa, color=c, alpha=0.3)
            a.plot(x, f * kPa, c + "-", label=f"{lab} (95 % band)")
        a.axhline(0, color="0.6", lw=0.5)
        a.set_xlabel("x [mm] (file's frame)")
        a.set_ylabel("traction [kPa]")
        a.legend(fontsize=8)
        a.set_title(f"P = {self.record['load_N_per_m']:.4g} +- "
                    f"{self.record['load_sigma_N_per_m']:.2g} N/m, Q/P = "
                    f"{self.record['Q_over_P']:.4g} +- {self.record['Q_over_P_sigma']:.2g}",
                    fontsize=9)
        a = ax[0, 1]
        ok = np.isfinite(self.mu_local)
        a.fill_between(x[ok], (self.mu_local - 1.96 * self.mu_local_sd)[ok],
                       (self.mu_local + 1.96 * self.mu_local_sd)[ok], color="C2", alpha=0.3)
        a.plot(x[ok], self.mu_local[ok], "C2.-", label="mu_local = q/p (p > 3 sd), 95 %")
        a.set_xlabel("x [mm]")
        a.set_ylabel("q / p")
        a.legend(fontsize=8)
        a = ax[1, 0]
        d = self.data
        xd = d["x_m"] * mm
        for key, c, lab in (("zz", "C0", "zz"), ("xz", "C1", "xz")):
            a.plot(xd, d[key] * kPa, c + ".", ms=2, label=f"data {lab}")
            a.plot(xd, d[key + "_fit"] * kPa, "k-", lw=0.8)
            a.plot(xd, (d[key] - d[key + "_fit"]) * kPa, c + "-", lw=0.6, alpha=0.7,
                   label=f"residual {lab}")
        a.set_xlabel("x [mm]")
        a.set_ylabel(("S" if self.record["view"] == "sensor" else "base stress") + " [kPa]")
        a.legend(fontsize=7)
        a = ax[1, 1]
        res = ok
        a.errorbar(self.pressure_Pa[res] * kPa, self.shear_Pa[res] * kPa,
                   xerr=self.pressure_sd_Pa[res] * kPa, yerr=self.shear_sd_Pa[res] * kPa,
                   fmt="k.", ms=3, lw=0.5, label="local (p, q), 1 sd")
        pp = np.linspace(0, max(self.pressure_Pa[res].max() if res.any() else 1.0, 1.0), 50)
        for label, qq in law_curves(self.record["laws"], pp):
            a.plot(pp * kPa, qq * kPa, label=label)
        a.set_xlabel("p [kPa]")
        a.set_ylabel("q [kPa]")
        a.legend(fontsize=7)
        return fig
