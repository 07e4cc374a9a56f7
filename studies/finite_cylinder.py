"""The paper's experiment in 3D: an 8 mm cover slide on a 129.2 mm lens sliding on the film.

    python -m studies.finite_cylinder [--quick] [--out DIR] [--workers N | --serial]

The paper measured P and Q/P but had to take P_L = Int S_zz dx and mu_d = Int S_xz dx /
Int S_zz dx from the sensor's profiles at y = 0, because the slide's sharp ends change the load
under the sensor (20 -> 220 N/m and 2.6 -> 2.0 as P goes 0.34 -> 2.75 N, while Q/P falls from
1.5 to 1.36).  Here the exact 3D model is given only P and mu = Q/P (Amontons, uniform; Q/P
between the two reported values interpolated linearly in ln P: an assumption), and predicts:

* the line load and the friction ratio carried at y = 0 (Int p(x, 0) dx, and the base's
  Int sigma_xz dx / -Int sigma_zz dx at y = 0);
* what the sensor reads there: Int S_zz dx and Int S_xz dx / Int S_zz dx at y = 0 (2D apparatus
  functions, G_yz = G_xz);
* the static (mu = 0) contact widths at y = 0 against the paper's 3D finite-element widths
  (3.00, 4.50, 5.34 mm at 0.69, 1.72, 2.75 N);
* the y = 0 base profiles against the plane-strain model at P/L and at the y = 0 line load
  (max |difference| / max |3D|).

Nothing is adjusted to match.  Writes finite_cylinder.csv and finite_cylinder.png.

The loads run as tasks of ``spectral_contact.sweep.map_tasks`` (studies/_common.run_points: a dask
LocalCluster of --workers processes, default the cores; in this process with --serial, with
--quick unless --workers is given, or without dask.distributed); the table does not depend on it.
"""
from __future__ import annotations

import math
import sys

import numpy as np

from spectral_contact import solve
from spectral_contact.instruments.sensor import sensor_maps

from ._common import parse, run_points, table

LENS_RADIUS = 0.1292      # m, the plano-convex lens
LENGTH = 0.008            # m, the cover slide along y
FILM = {"young": 2.2e6, "thickness": 0.002}
LOADS = (0.34, 0.69, 1.03, 1.72, 2.75)  # N
FE_WIDTHS_MM = {0.69: 3.00, 1.72: 4.50, 2.75: 5.34}  # the paper's static 3D FE widths
PAPER_PL = (20.0, 220.0)  # N/m at 0.34 and 2.75 N (from the sensor)
PAPER_MU = (2.6, 2.0)     # idem


def q_over_p(P: float) -> float:
    """Q/P: 1.5 at 0.34 N, 1.36 at 2.75 N (the paper), linear in ln P between (assumption)."""
    t = (math.log(P) - math.log(0.34)) / (math.log(2.75) - math.log(0.34))
    return 1.5 + t * (1.36 - 1.5)


def _line(r, field):
    j = int(np.argmin(np.abs(r.y)))
    return field[:, j]


def cylinder_point(point):
    """One load (P [N], tol): the sliding and static 3D solves, the sensor, the 2D comparisons;
    (table row, y = 0 profiles for the figure).  A task of the sweep engine."""
    P, tol = point
    mu = q_over_p(P)
    common = dict(indenter="cylinder", force=P, radius=LENS_RADIUS, length=LENGTH, tol=tol,
                  **FILM)
    r = solve(mu=mu, **common)
    static = solve(mu=0.0, **common)
    S = sensor_maps(r)
    dx = (r.x[1] - r.x[0]) * r.scene.length_unit
    m = r.maps()
    szz0, sxz0 = _line(r, m["base_sigma_zz_Pa"]), _line(r, m["base_sigma_xz_Pa"])
    Szz0, Sxz0 = _line(r, S["S_zz_Pa"]), _line(r, S["S_xz_Pa"])
    line_load = r.summary()["line_load_y0_N_per_m"]
    # 2D model at P/L and at the y = 0 line load: y = 0 base profiles compared on the 3D x
    x_m = r.x * r.scene.length_unit
    diffs = {}
    for name, PL in (("P_over_L", P / LENGTH), ("line_load_y0", line_load)):
        two = solve(load=PL, mu=mu, radius=LENS_RADIUS, tol=1e-4, **FILM)
        zz = np.interp(x_m, two.x_m, two.base_sigma_zz_Pa)
        diffs[name] = float(np.max(np.abs(zz - szz0)) / np.max(np.abs(szz0)))
        if name == "line_load_y0":
            line = (P, x_m, szz0, sxz0, Szz0, Sxz0, two, zz)
    j = int(np.argmin(np.abs(static.y)))
    sq = static.pressure[:, j] > 0
    xs = static.x[sq]
    width_static = (xs.max() - xs.min() + (static.x[1] - static.x[0])) * static.scene.length_unit
    row = {
        "P_N": P, "mu_Q_over_P": mu, "P_over_L_N_per_m": P / LENGTH,
        "line_load_y0_N_per_m": line_load,
        "base_ratio_y0": float(sxz0.sum() / -szz0.sum()),
        "sensor_Szz_integral_N_per_m": float(Szz0.sum() * dx),
        "sensor_ratio_y0": float(Sxz0.sum() / Szz0.sum()),
        "static_width_y0_mm": 1e3 * width_static,
        "paper_FE_width_mm": FE_WIDTHS_MM.get(P, float("nan")),
        "contact_y_half_width_mm": 1e3 * r.summary()["contact_y_half_width_m"],
        "max_diff_2D_at_P_over_L": diffs["P_over_L"],
        "max_diff_2D_at_line_load": diffs["line_load_y0"],
        "error_estimate": r.error_estimate,
        "grid": f"{r.grid_points[0]}x{r.grid_points[1]}",
    }
    return row, line


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/finite_cylinder", engine=True)
    loads = (0.34, 2.75) if args.quick else LOADS
    tol = 3e-2 if args.quick else 1e-2
    pairs = run_points(args, "studies.finite_cylinder", "cylinder_point",
                       [(P, tol) for P in loads], "loads")
    rows = [row for row, _ in pairs]
    lines = [line for _, line in pairs]
    table(rows, out / "finite_cylinder.csv",
          "finite cylinder (8 mm slide, R = 129.2 mm, E = 2.2 MPa, h = 2 mm), exact 3D model; "
          f"paper (sensor): P_L {PAPER_PL[0]:g} -> {PAPER_PL[1]:g} N/m, mu_d {PAPER_MU[0]} -> "
          f"{PAPER_MU[1]}; widths: static, at y = 0 (node count, +- one cell)")
    _plot(lines, rows, out / "finite_cylinder.png")
    return 0


def _plot(lines, rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    colors = plt.cm.viridis(np.linspace(0, 0.85, len(lines)))
    for c, (P, x, szz, _sxz, Szz, Sxz, _two, zz2) in zip(colors, lines):
        mm = 1e3 * x
        axes[0].plot(mm, -szz / 1e3, color=c, label=f"3D, P = {P} N")
        axes[0].plot(mm, -zz2 / 1e3, "--", color=c, lw=0.8)
        axes[1].plot(mm, Szz / 1e3, color=c, label=f"P = {P} N")
        axes[1].plot(mm, Sxz / 1e3, ":", color=c)
    axes[0].set_title("-sigma_zz(x, y=0, base): 3D (solid), 2D at the y=0 line load (dashed)",
                      fontsize=8)
    axes[0].set_ylabel("kPa")
    axes[1].set_title("MEMS at y = 0: S_zz (solid), S_xz (dotted)", fontsize=8)
    axes[1].set_ylabel("kPa")
    for ax in axes[:2]:
        ax.set_xlabel("x [mm] (apex = 0, sliding toward +x)")
        ax.set_xlim(-8, 10)
        ax.legend(fontsize=7)
    P = [r["P_N"] for r in rows]
    ax = axes[2]
    ax.plot(P, [r["sensor_Szz_integral_N_per_m"] for r in rows], "o-", label="Int S_zz dx (3D model)")
    ax.plot(P, [r["line_load_y0_N_per_m"] for r in rows], "s--", label="Int p(x,0) dx (3D model)")
    ax.plot(P, [r["P_over_L_N_per_m"] for r in rows], ":", color="0.5", label="P / L")
    ax.plot([0.34, 2.75], PAPER_PL, "kx", ms=9, label="paper (sensor), 0.34 and 2.75 N")
    ax.set_xlabel("P [N]")
    ax.set_ylabel("line load [N/m]")
    ax.legend(fontsize=7)
    ax.set_title("line load under the sensor", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
