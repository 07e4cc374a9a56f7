"""The paper's model figures from our solver: exact (solid) against Goodman (dashed).

    python -m studies.paper_figures [--quick] [--out DIR] [--workers N | --serial]

Figures (Scheibert et al. 2009, "Discussion"), E = 2.2 MPa, R = 130 mm, h = 2 mm:
  surface_mu.png    surface pressure, mu_d = 0.3 ... 3.0 (step 0.3) at P_L = 200 N/m
  surface_load.png  surface pressure, P_L = 20 ... 380 N/m (step 40) at mu_d = 2.0
  base_mu.png       base sigma_zz and sigma_xz, mu_d = 0 ... 3.0 (step 0.6) at P_L = 200 N/m
  base_load.png     base sigma_zz and sigma_xz, P_L = 20 ... 380 N/m (step 80) at mu_d = 2.0
  mems_*.png        the base profiles seen through the MEMS apparatus functions (S_zz, S_xz)
CSV: profiles_*.csv (long format) and widths.csv (contact widths, ours beside the caption's).

The scenes run as tasks of ``spectral_contact.sweep.map_tasks`` (studies/_common.run_points: a
dask LocalCluster of --workers processes, default the cores; in this process with --serial, with
--quick unless --workers is given, or without dask.distributed); the files do not depend on it.
"""
from __future__ import annotations

import sys

import numpy as np

from spectral_contact import Scene, solve

from ._common import parse, run_points, table

# contact widths 2a [mm] quoted in the caption of the paper's surface-profile figure (b)
CAPTION_WIDTHS_EXACT = [2.60, 3.40, 3.88, 4.24, 4.52, 4.80, 5.02, 5.24, 5.44, 5.62]
CAPTION_WIDTHS_GOODMAN = [2.68, 3.52, 4.00, 4.36, 4.66, 4.90, 5.12, 5.32, 5.52, 5.68]
X_MM = np.linspace(-8.0, 10.0, 901)  # plotting window [mm], apex frame


def _sweeps(quick: bool):
    if quick:
        return {"surface_mu": ("mu", [0.3, 1.5, 3.0], 200.0),
                "surface_load": ("load", [20.0, 180.0, 380.0], 2.0),
                "base_mu": ("mu", [0.0, 1.2, 3.0], 200.0),
                "base_load": ("load", [20.0, 180.0, 340.0], 2.0)}
    return {"surface_mu": ("mu", [round(0.3 * i, 1) for i in range(1, 11)], 200.0),
            "surface_load": ("load", [20.0 + 40 * i for i in range(10)], 2.0),
            "base_mu": ("mu", [round(0.6 * i, 1) for i in range(6)], 200.0),
            "base_load": ("load", [20.0 + 80 * i for i in range(5)], 2.0)}


def _on_window(r, field):
    """A periodic-grid profile (SI) interpolated onto the plotting window."""
    x = r.x_m * 1e3
    L = r.domain_length * r.scene.length_unit * 1e3
    return np.interp(X_MM, x, field, period=L)


def _label(kind: str, v: float) -> str:
    """Legend label with units: mu_d is dimensionless, the load in N/m."""
    return f"mu_d = {v:g}" if kind == "mu" else f"P_L = {v:g} N/m"


def _colors(plt, n: int):
    """n colours of plasma up to 0.8 (no pale yellow: every line readable on white)."""
    cmap = plt.get_cmap("plasma")
    return [cmap(0.8 * j / max(n - 1, 1)) for j in range(n)]


def _style_legend(ax, kind, ncol=2):
    """Sweep values (colours) plus what solid and dashed mean."""
    from matplotlib.lines import Line2D

    handles, labels = ax.get_legend_handles_labels()
    handles += [Line2D([], [], color="k", ls="-", lw=1), Line2D([], [], color="k", ls="--", lw=1)]
    labels += ["exact model", "Goodman model"]
    ax.legend(handles, labels, fontsize=7, ncol=ncol)


def _sensor(r):
    try:
        from spectral_contact.instruments.sensor import sensor_view
    except ImportError:
        return None
    return sensor_view(r)


def solve_pair(point) -> dict:
    """One point of a figure, (kind, value, fixed, tol): the scene solved with both models
    ({"exact": Result, "goodman": Result}); a task of the sweep engine."""
    kind, v, fixed, tol = point
    scene = Scene(mu=v, load=fixed) if kind == "mu" else Scene(load=v, mu=fixed)
    return {m: solve(scene, model=m, tol=tol) for m in ("exact", "goodman")}


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/paper_figures", engine=True)
    tol = 1e-3 if args.quick else 1e-4
    sweeps = _sweeps(args.quick)
    todo = [(name, v) for name, (_, vals, _) in sweeps.items() for v in vals]
    pairs = run_points(args, "studies.paper_figures", "solve_pair",
                       [(sweeps[name][0], v, sweeps[name][2], tol) for name, v in todo], "scenes")
    results = dict(zip(todo, pairs))

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    have_sensor = _sensor(results[todo[0]]["exact"]) is not None
    for name, (kind, vals, fixed) in sweeps.items():
        base = name.startswith("base")
        rows = []
        panels = [("base_sigma_zz_Pa", "sigma_zz(x, 0) [kPa]"), ("base_sigma_xz_Pa", "sigma_xz(x, 0) [kPa]")] \
            if base else [("pressure_Pa", "p = -sigma_zz(x, h) [kPa]")]
        fig, axes = plt.subplots(len(panels), 1, figsize=(7, 3.2 * len(panels)), squeeze=False)
        colors = _colors(plt, len(vals))
        for j, v in enumerate(vals):
            color = colors[j]
            for model, style in (("exact", "-"), ("goodman", "--")):
                r = results[name, v][model]
                prof = r.profiles()
                for ax, (col, _) in zip(axes[:, 0], panels):
                    y = _on_window(r, prof[col]) / 1e3
                    ax.plot(X_MM, y, style, color=color, lw=1,
                            label=_label(kind, v) if model == "exact" and ax is axes[0, 0] else None)
                rec = {"model": model, kind: v}
                for col, _ in panels:
                    rec[col] = _on_window(r, prof[col])
                rows.append(rec)
        for ax, (_, label) in zip(axes[:, 0], panels):
            ax.set_ylabel(label)
            ax.axhline(0, color="0.8", lw=0.5)
        _style_legend(axes[0, 0], kind)
        other = "P_L = %g N/m" % fixed if kind == "mu" else "mu_d = %g" % fixed
        axes[0, 0].set_title(f"{name}: exact (solid) vs Goodman (dashed), {other}", fontsize=9)
        axes[-1, 0].set_xlabel("x [mm] (apex frame, sliding toward +x)")
        fig.tight_layout()
        fig.savefig(out / f"{name}.png", dpi=110)
        plt.close(fig)
        _write_long(out / f"profiles_{name}.csv", rows, kind)
        if base and have_sensor:
            fig, axes = plt.subplots(2, 1, figsize=(7, 6.4))
            for j, v in enumerate(vals):
                color = colors[j]
                for model, style in (("exact", "-"), ("goodman", "--")):
                    r = results[name, v][model]
                    s = _sensor(r)
                    for ax, col in zip(axes, ("S_zz_Pa", "S_xz_Pa")):
                        ax.plot(X_MM, _on_window(r, s[col]) / 1e3, style, color=color, lw=1,
                                label=_label(kind, v) if model == "exact" and ax is axes[0] else None)
            axes[0].set_ylabel("S_zz [kPa] (+ compression)")
            axes[1].set_ylabel("S_xz [kPa]")
            _style_legend(axes[0], kind)
            axes[0].set_title(f"MEMS view of {name}: G (*) sigma, exact (solid) vs Goodman (dashed)", fontsize=9)
            for ax in axes:
                ax.axhline(0, color="0.8", lw=0.5)
            axes[1].set_xlabel("x [mm] (apex frame, sliding toward +x)")
            fig.tight_layout()
            fig.savefig(out / f"mems_{name}.png", dpi=110)
            plt.close(fig)
    if not have_sensor:
        print("MEMS module not available: mems_*.png skipped", file=sys.stderr)

    # contact widths: ours beside the caption's (surface figure (b): mu_d = 2, P_L = 20 ... 380)
    wrows = []
    kind, vals, fixed = sweeps["surface_load"]
    full = [20.0 + 40 * i for i in range(10)]
    for v in vals:
        i = full.index(v)
        ex, go = (results["surface_load", v][m] for m in ("exact", "goodman"))
        wrows.append({"load_N_per_m": v, "mu": fixed,
                      "width_exact_mm": 2e3 * ex.half_width_m, "caption_exact_mm": CAPTION_WIDTHS_EXACT[i],
                      "width_goodman_mm": 2e3 * go.half_width_m, "caption_goodman_mm": CAPTION_WIDTHS_GOODMAN[i],
                      "hertz_width_mm": 2e3 * np.sqrt(ex.scene.P / (2 * np.pi)) * ex.scene.length_unit})
    kind, vals, fixed = sweeps["surface_mu"]
    for v in vals:
        ex = results["surface_mu", v]["exact"]
        wrows.append({"load_N_per_m": fixed, "mu": v, "width_exact_mm": 2e3 * ex.half_width_m,
                      "caption_exact_mm": 2 * 2.36,
                      "width_goodman_mm": 2e3 * results["surface_mu", v]["goodman"].half_width_m,
                      "caption_goodman_mm": float("nan"),
                      "hertz_width_mm": 2e3 * np.sqrt(ex.scene.P / (2 * np.pi)) * ex.scene.length_unit})
    table(wrows, out / "widths.csv",
          "Contact widths 2a [mm]: ours vs the caption of the paper's surface figure "
          "(for mu sweep the caption quotes 'contact radius 2.36 +/- 0.03 mm', shown as 2 x 2.36)")
    return 0


def _write_long(path, rows, kind):
    import csv

    cols = [c for c in rows[0] if c not in ("model", kind)]
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["model", "mu" if kind == "mu" else "load_N_per_m", "x_m"] + cols)
        for rec in rows:
            for k, x in enumerate(X_MM):
                w.writerow([rec["model"], rec[kind], f"{x * 1e-3:.6g}"] + [f"{rec[c][k]:.8g}" for c in cols])


if __name__ == "__main__":
    sys.exit(main())
