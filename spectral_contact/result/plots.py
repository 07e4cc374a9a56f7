"""The results' figures (matplotlib, imported here only): a line's profiles (``_plot``) and a
surface's maps (``_plot_maps``); ``ContactResult.plot`` and ``ContactResult3D.plot`` call them."""
from __future__ import annotations

import numpy as np

TAIL_FRACTION = 0.01
"""The plots' x range holds the base stresses down to this fraction of their peak (issue 24:
contact +- 2 h cut S_xz at 14 kPa, a quarter of its peak)."""


def _xrange_mm(result, margin_h: float = 2.0):
    """Plot range [mm]: the contact plus ``margin_h`` film thicknesses on each side, widened
    to where both base stresses have fallen below TAIL_FRACTION of their peak."""
    L, mm = result.scene.length_unit, 1e3
    x = result.x_m * mm
    iv = result.contact_intervals
    lo, hi = (iv[0][0], iv[-1][1]) if iv else (0.0, 0.0)
    lo, hi = (lo - margin_h) * L * mm, (hi + margin_h) * L * mm
    base = np.maximum(np.abs(np.asarray(result.base_sigma_zz_Pa)),
                      np.abs(np.asarray(result.base_sigma_xz_Pa)))
    if base.size == x.size and base.size and np.max(base) > 0:
        big = x[base >= TAIL_FRACTION * np.max(base)]
        lo, hi = min(lo, float(big.min())), max(hi, float(big.max()))
    return max(lo, x.min()), min(hi, x.max())


def _plot(result, ax=None, sensor=None):
    from matplotlib.figure import Figure

    s = result.scene
    mm, kPa = 1e3, 1e-3
    if sensor is not None and not isinstance(sensor, dict):
        sensor = sensor.profiles()
    nrow = 3 if sensor is not None else 2
    if ax is None:
        fig = Figure(figsize=(7.0, 2.5 * nrow + 0.5), layout="constrained")
        axes = list(fig.subplots(nrow, 1))
    elif hasattr(ax, "plot"):
        axes, fig = [ax], ax.figure
    else:
        axes = list(ax)
        fig = axes[0].figure
    x = result.x_m * mm
    xs = None
    if sensor is not None:
        xs = np.asarray(sensor.get("x_m", result.x_m), dtype=float) * mm
    lo, hi = _xrange_mm(result)
    sel = (x >= lo) & (x <= hi)
    intervals = [(a * s.length_unit * mm, b * s.length_unit * mm) for a, b in result.contact_intervals]

    def mark_contact(a, label=False):
        for i, (u, v) in enumerate(intervals):
            a.axvspan(u, v, color="0.9", zorder=0,
                      label="contact" if (label and i == 0) else None)
        a.axhline(0.0, color="0.6", lw=0.5, zorder=1)

    a0 = axes[0]
    mark_contact(a0, label=True)
    a0.plot(x[sel], result.pressure_Pa[sel] * kPa, color="C0", label="pressure p = -sigma_zz(x, h)")
    a0.set_ylabel("pressure p [kPa]", color="C0")
    if np.any(result.surface_shear_Pa[sel] != 0.0):
        # one axis, both in kPa (issue 24: a right axis scaled by mu_d drew the Amontons shear
        # on top of the pressure, adding nothing)
        a0.plot(x[sel], result.surface_shear_Pa[sel] * kPa, "--", color="C3",
                label=("surface shear sigma_xz(x, h)" if result.shear is not None
                       else f"surface shear sigma_xz(x, h) = {s.mu:g} p"))
        a0.set_ylabel("surface stress [kPa]", color="black")
    handles, labels = a0.get_legend_handles_labels()
    leg_ax = a0
    leg_ax.legend(handles, labels, fontsize=7, loc="lower left", bbox_to_anchor=(0.0, 1.0),
                  ncols=2, frameon=False, borderaxespad=0.2)
    split = f"; contact in {len(intervals)} intervals" if len(intervals) > 1 else ""
    if ax is None:  # a figure of our own: the scene as its title
        fig.suptitle(f"{result.model} model ({result.method}): P_L = {s.load:g} N/m, mu_d = {s.mu:g}, "
                     f"E = {s.young / 1e6:g} MPa, R = {s.radius * mm:g} mm, h = {s.thickness * mm:g} mm"
                     f"{split}" + ("" if s.friction_law == "amontons" else
                                   f"; {s.friction_law} friction law"), fontsize=10)
    if len(axes) > 1:
        a1 = axes[1]
        mark_contact(a1)
        a1.plot(x[sel], result.base_sigma_zz_Pa[sel] * kPa, color="C0", label="sigma_zz(x, 0)")
        a1.plot(x[sel], result.base_sigma_xz_Pa[sel] * kPa, color="C3", label="sigma_xz(x, 0)")
        a1.set_ylabel("base stress [kPa]")
        a1.legend(fontsize=7, loc="best", title="sigma_zz < 0 in compression", title_fontsize=7)
    if sensor is not None and len(axes) > 2:
        a2 = axes[2]
        mark_contact(a2)
        ss = (xs >= lo) & (xs <= hi)
        a2.plot(xs[ss], np.asarray(sensor["S_zz_Pa"])[ss] * kPa, color="C0", label="S_zz (> 0 compression)")
        a2.plot(xs[ss], np.asarray(sensor["S_xz_Pa"])[ss] * kPa, color="C3", label="S_xz")
        a2.set_ylabel("MEMS view S [kPa]")
        a2.legend(fontsize=7, loc="best")
    xlabel = "x [mm] from the indenter apex (sliding toward +x)"
    for a in axes:
        a.set_xlim(lo, hi)
    if intervals and len(axes) > 1:
        u, v = intervals[0][0], intervals[-1][1]
        if v - u < 0.25 * (hi - lo):  # a small contact: its own zoom on the surface panel
            pad = 0.25 * (v - u)
            a0.set_xlim(u - pad, v + pad)
            a0.set_xlabel(xlabel + ", zoomed on the contact", fontsize=8)
    for a in axes[1:-1]:  # the base and sensor panels share the range: one label at the bottom
        a.sharex(axes[-1])
        a.tick_params(labelbottom=False)
    axes[-1].set_xlabel(xlabel)
    return fig


def _plot_maps(result, sensor, window):
    """3D result: maps of the pressure and of the three base tractions (and the MEMS maps
    S_zz, S_xz, S_yz with ``sensor``, drawn like the paper's measured field: iso-lines), x the
    sliding direction, in mm from the apex, stresses in kPa, the contact outline in black.
    ``window``: film thicknesses shown beyond the contact."""
    import numpy as np
    from matplotlib.figure import Figure

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
    ncol = 3 if not sensor else 4
    nrow = int(np.ceil((len(panels) + 1) / ncol))  # + the y = 0 line
    fig = Figure(figsize=(3.8 * ncol, 3.5 * nrow))
    axes = fig.subplots(nrow, ncol, squeeze=False)
    X, Y = np.meshgrid(x[sx], y[sy], indexing="ij")
    contact = result.pressure[np.ix_(sx, sy)] > 0
    clipped = []
    for ax, (key, title) in zip(axes.ravel(), panels):
        f = fields[key][np.ix_(sx, sy)] / 1e3
        top = max(np.max(np.abs(f)), 1e-30)
        # the colour scale stops at a percentile of |value| (issue 24: the finite cylinder's
        # singular ends took the whole scale); the clipped maximum is said in the title
        lim = max(float(np.percentile(np.abs(f), MAP_CLIP_PERCENTILE)), 1e-30)
        lim = top if top <= 1.05 * lim else lim
        if lim < top:
            clipped.append(f"{title.split(' [')[0]} max {top:.3g} kPa")
        signed = key != "pressure_Pa"
        cmap = "RdBu_r" if signed else "viridis"
        if key.startswith("S_"):  # the paper's measured field: iso-lines, with a colour bar
            cs = ax.contour(X, Y, np.clip(f, -lim, lim), levels=8, cmap=cmap,
                            vmin=-lim if signed else None, vmax=lim if signed else None)
            ax.clabel(cs, fontsize=8, fmt="%.2g")
            fig.colorbar(cs, ax=ax, label="kPa", shrink=0.85)
        else:
            im = ax.pcolormesh(X, Y, f, shading="auto", cmap=cmap,
                               vmin=-lim if signed else 0.0, vmax=lim)
            fig.colorbar(im, ax=ax, label="kPa", shrink=0.85,
                         extend=("both" if signed else "max") if lim < top else "neither")
        ax.contour(X, Y, contact.astype(float), levels=[0.5], colors="k", linewidths=0.8)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("x [mm] (sliding toward +x)")
        ax.set_ylabel("y [mm]")
        ax.set_aspect("equal")
    # the line the sensor measures: y = 0 (issue 24)
    ax = axes.ravel()[len(panels)]
    j = int(np.argmin(np.abs(y)))
    for key, label, style in (("pressure_Pa", "pressure p", "k-"),
                              ("base_sigma_zz_Pa", "base sigma_zz", "C0-"),
                              ("base_sigma_xz_Pa", "base sigma_xz", "C3-"),
                              ("S_zz_Pa", "MEMS S_zz", "C0--"), ("S_xz_Pa", "MEMS S_xz", "C3--")):
        if key in fields:
            ax.plot(x[sx], fields[key][sx, j] / 1e3, style, lw=1.2, label=label)
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.set_title(f"the line y = {y[j]:.3g} mm", fontsize=10)
    ax.set_xlabel("x [mm] (sliding toward +x)")
    ax.set_ylabel("stress [kPa]")
    ax.legend(fontsize=7)
    for ax in axes.ravel()[len(panels) + 1:]:
        ax.set_visible(False)
    note = (f"; colour scales clipped at the {MAP_CLIP_PERCENTILE:g}th percentile of |value| "
            f"({', '.join(clipped)})" if clipped else "")
    fig.suptitle(f"{result.model} model, {s.indenter}: F = {s.force:g} N, mu_d = {s.mu:g}, "
                 f"E = {s.young / 1e6:g} MPa, R = {s.radius * 1e3:g} mm, "
                 f"h = {s.thickness * 1e3:g} mm (black: contact outline){note}", fontsize=10,
                 wrap=True)
    fig.tight_layout()
    return fig


MAP_CLIP_PERCENTILE = 99.5
"""The maps' colour scales end at this percentile of |value| in the window when the maximum is
more than 5 % above it (singular edges: the finite cylinder's ends); the title says so."""
