"""Matplotlib figures (Agg backend: no display needed)."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

__all__ = ["plot_result", "plot_maps"]


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
    ax.plot(x[sel], result.surface_shear_Pa[sel] / 1e3, "--", label="shear sigma_xz(x, h) = mu p")
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


def plot_maps(result, path, sensor: dict | None = None, window: float = 3.0):
    """3D result: maps of the pressure and of the three base tractions (and the MEMS maps
    S_zz, S_xz, S_yz with ``sensor``, drawn like the paper's measured field: iso-lines), x the
    sliding direction, in mm from the apex, stresses in kPa, the contact outline in black.
    ``window``: film thicknesses shown beyond the contact."""
    import numpy as np

    s = result.scene
    maps = result.maps()
    mm = 1e3
    x, y = maps["x_m"] * mm, maps["y_m"] * mm
    q, L = result.measures, s.length_unit * mm
    sx = (x >= (q["x_min"] - window) * L) & (x <= (q["x_max"] + window) * L)
    sy = (y >= (q["y_min"] - window) * L) & (y <= (q["y_max"] + window) * L)
    panels = [("pressure_Pa", "pressure p = -sigma_zz(h)"),
              ("base_sigma_zz_Pa", "base sigma_zz(x, y, 0)"),
              ("base_sigma_xz_Pa", "base sigma_xz(x, y, 0)"),
              ("base_sigma_yz_Pa", "base sigma_yz(x, y, 0)")]
    fields = {k: maps[k] for k, _ in panels}
    if sensor:
        panels += [("S_zz_Pa", "MEMS S_zz [kPa] (+ compression)"), ("S_xz_Pa", "MEMS S_xz [kPa]"),
                   ("S_yz_Pa", "MEMS S_yz [kPa]")]
        fields.update({k: sensor[k] for k in ("S_zz_Pa", "S_xz_Pa", "S_yz_Pa")})
    ncol = 4 if not sensor else 4
    nrow = int(np.ceil(len(panels) / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.6 * ncol, 3.3 * nrow), squeeze=False)
    X, Y = np.meshgrid(x[sx], y[sy], indexing="ij")
    contact = result.pressure[np.ix_(sx, sy)] > 0
    for ax, (key, title) in zip(axes.ravel(), panels):
        f = fields[key][np.ix_(sx, sy)] / 1e3
        lim = max(np.max(np.abs(f)), 1e-30)
        signed = key != "pressure_Pa"
        if key.startswith("S_"):  # the paper's measured field: iso-lines
            cs = ax.contour(X, Y, f, levels=12, cmap="RdBu_r" if signed else "viridis",
                            vmin=-lim if signed else None, vmax=lim if signed else None)
            ax.clabel(cs, fontsize=6, fmt="%.3g")
        else:
            im = ax.pcolormesh(X, Y, f, shading="auto", cmap="RdBu_r" if signed else "viridis",
                               vmin=-lim if signed else 0.0, vmax=lim)
            fig.colorbar(im, ax=ax, label="kPa", shrink=0.85)
        ax.contour(X, Y, contact.astype(float), levels=[0.5], colors="k", linewidths=0.8)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("x [mm] (sliding toward +x)")
        ax.set_ylabel("y [mm]")
        ax.set_aspect("equal")
    for ax in axes.ravel()[len(panels):]:
        ax.set_visible(False)
    fig.suptitle(f"{result.model} model, {s.indenter}: F = {s.force:g} N, mu_d = {s.mu:g}, "
                 f"E = {s.young / 1e6:g} MPa, R = {s.radius * 1e3:g} mm, "
                 f"h = {s.thickness * 1e3:g} mm (black: contact outline)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
