"""Matplotlib figures (Agg backend: no display needed)."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

__all__ = ["plot_result"]


def plot_result(result, path, sensor: dict | None = None, window: float = 4.0):
    """Surface pressure and base stresses against x [mm] (kPa), apex frame; with the MEMS view
    (S_zz, S_xz) when ``sensor`` is given.  ``window``: half-width of the plot in film
    thicknesses beyond the contact."""
    s = result.scene
    mm = 1e3
    x = result.x_m * mm
    lo = (result.center - result.half_width - window) * s.length_unit * mm
    hi = (result.center + result.half_width + window) * s.length_unit * mm
    sel = (x >= lo) & (x <= hi)
    nrow = 3 if sensor else 2
    fig, axes = plt.subplots(nrow, 1, figsize=(7, 2.6 * nrow), sharex=True)
    ax = axes[0]
    ax.plot(x[sel], result.pressure_Pa[sel] / 1e3, label="pressure p = -sigma_zz(x, h)")
    ax.plot(x[sel], result.surface_shear_Pa[sel] / 1e3, "--", label="shear sigma_xz(x, h)")
    ax.set_ylabel("surface stress [kPa]")
    ax.set_title(f"{result.model} model ({result.method}): P_L = {s.load:g} N/m, mu_d = {s.mu:g}, "
                 f"E = {s.young / 1e6:g} MPa, R = {s.radius * 1e3:g} mm, h = {s.thickness * 1e3:g} mm",
                 fontsize=8)
    ax.legend(fontsize=8)
    ax = axes[1]
    ax.plot(x[sel], result.base_sigma_zz_Pa[sel] / 1e3, label="sigma_zz(x, 0)")
    ax.plot(x[sel], result.base_sigma_xz_Pa[sel] / 1e3, label="sigma_xz(x, 0)")
    ax.axhline(0, color="0.7", lw=0.5)
    ax.set_ylabel("base stress [kPa]")
    ax.legend(fontsize=8)
    if sensor:
        ax = axes[2]
        ax.plot(x[sel], sensor["S_zz_Pa"][sel] / 1e3, label="S_zz (MEMS, + compression)")
        ax.plot(x[sel], sensor["S_xz_Pa"][sel] / 1e3, label="S_xz (MEMS)")
        ax.axhline(0, color="0.7", lw=0.5)
        ax.set_ylabel("sensor stress [kPa]")
        ax.legend(fontsize=8)
    axes[-1].set_xlabel("x [mm] (from the indenter apex; sliding toward +x)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
