"""A sphere sliding on the film: the exact model against Goodman's, a/h 0.1 - 3, mu 0 - 3.

    python -m studies.sphere_sliding [--quick] [--out DIR] [--workers N | --serial]

For each Hertz half-width s = a_H/h (the force F = 32 s^3 E h^3 / (18 R), i.e. P = 32 s^3/3)
and friction mu: the exact model (friction coupled into the contact) and Goodman's (frictionless
contact, friction loading the base only), both at tol 1e-2 (1e-3 for the figure).  Reported:
the contact radius sqrt(A/pi), its x extents (leading/trailing, from the apex), the pressure
centroid, the peak pressure and where it sits, and the relative differences exact - Goodman.
The figure: base and MEMS maps of the sliding sphere at a/h ~ 1.3, mu = 1 (the paper's measured
field is drawn the same way: iso-lines, x along the sliding direction), plus the centroid shift
against mu.  Writes sphere_sliding.csv, sphere_sliding_maps.png and sphere_sliding.png.

The (a/h, mu) points run as tasks of ``spectral_contact.sweep.map_tasks`` (studies/_common.run_points:
a dask LocalCluster of --workers processes, default the cores; in this process with --serial,
with --quick unless --workers is given, or without dask.distributed); the table does not depend
on it.  The figure's single solve runs in this process.
"""
from __future__ import annotations

import sys

from spectral_contact import solve
from spectral_contact.cli.plots import plot_maps
from spectral_contact.instruments.sensor import sensor_maps

from ._common import parse, run_points, table

FILM = {"young": 2.2e6, "thickness": 0.002, "radius": 0.130}


def force_for(s: float) -> float:
    """F [N] whose Hertz half-space contact radius is s film thicknesses."""
    P = 32.0 * s**3 / 3.0
    return P * FILM["young"] * FILM["thickness"] ** 3 / (6.0 * FILM["radius"])


def sphere_point(point) -> dict:
    """The table row of one (s = a_H/h, mu, tol): the exact and Goodman solves side by side;
    a task of the sweep engine."""
    s, mu, tol = point
    kw = dict(indenter="sphere", force=force_for(s), mu=mu, tol=tol, **FILM)
    e = solve(model="exact", **kw).summary()
    g = solve(model="goodman", **kw).summary()
    h = FILM["thickness"]
    return {
        "aH_over_h": s, "mu": mu, "force_N": e["force_N"],
        "radius_exact_h": e["contact_radius_m"] / h,
        "radius_goodman_h": g["contact_radius_m"] / h,
        "x_min_exact_h": e["contact_x_min_m"] / h, "x_max_exact_h": e["contact_x_max_m"] / h,
        "x_min_goodman_h": g["contact_x_min_m"] / h,
        "x_max_goodman_h": g["contact_x_max_m"] / h,
        "centroid_exact_h": e["pressure_centroid_x_m"] / h,
        "peak_x_exact_h": e["max_pressure_x_m"] / h,
        "peak_exact_over_goodman": e["max_pressure_Pa"] / g["max_pressure_Pa"],
        "radius_rel_diff": e["contact_radius_m"] / g["contact_radius_m"] - 1.0,
        "error_estimate": max(e["error_estimate"], g["error_estimate"]),
    }


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/sphere_sliding", engine=True)
    sizes = (1.0,) if args.quick else (0.1, 0.3, 1.0, 3.0)
    mus = (0.0, 1.0) if args.quick else (0.0, 0.5, 1.0, 2.0, 3.0)
    tol = 3e-2 if args.quick else 1e-2
    rows = run_points(args, "studies.sphere_sliding", "sphere_point",
                      [(s, mu, tol) for s in sizes for mu in mus], "scenes")
    table(rows, out / "sphere_sliding.csv",
          "sliding sphere on the film: exact vs Goodman (lengths in h, from the apex)")
    # the maps figure: a/h ~ 1.3 on the film (Hertz 1.6), mu = 1
    r = solve(indenter="sphere", force=1.0, mu=1.0, tol=3e-3 if args.quick else 1e-3, **FILM)
    plot_maps(r, out / "sphere_sliding_maps.png", sensor=sensor_maps(r))
    _plot(rows, out / "sphere_sliding.png")
    return 0


def _plot(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for s in sorted({r["aH_over_h"] for r in rows}):
        sel = [r for r in rows if r["aH_over_h"] == s]
        mu = [r["mu"] for r in sel]
        axes[0].plot(mu, [r["centroid_exact_h"] / r["radius_exact_h"] for r in sel], "o-",
                     label=f"a_H/h = {s:g}")
        axes[1].plot(mu, [r["peak_exact_over_goodman"] for r in sel], "o-", label=f"a_H/h = {s:g}")
    axes[0].set_ylabel("pressure centroid x_c / contact radius (exact)")
    axes[1].set_ylabel("peak pressure, exact / Goodman")
    for ax in axes:
        ax.set_xlabel("mu_d")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    axes[0].set_title("friction shifts the exact contact forward (Goodman: 0)", fontsize=9)
    axes[1].set_title("and raises its peak", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
