"""Error estimate against the true error: how far the FFT solver's error_estimate is from it.

    python -m studies.error_estimate [--quick | --holdout] [--out DIR] [--workers N | --serial]

The verification sweep of issue 13: scenes a_Hertz/h = s in [0.05, 65] (14 values, log-spaced;
the film's a/h = 0.05 ... 8.6 frictionless, up to 22 at mu_d = 10) x mu_d in {0, 0.5, 2, 5, 10},
each solved by the FFT method at tol 1e-2, 1e-3, 1e-4 and 1e-5 (the automatic resolution): 280
runs.  The true error is measured against the Abel method at 96 nodes (spectral; its difference
from 64 nodes, ref_check, bounds its own error and is reported for every scene), with the
solver's own metric: the largest of |da|/a, |dx_c|/a, |dd|/d, |dp_max|/p_max (``which`` names
it).  ratio = error_estimate / true error (> 1: the estimate is conservative).  Writes
error_estimate.csv and error_estimate.png.  --quick: 3 x 2 scenes at tol 1e-3.

The estimate's rule (solvers/fft.py ``_discretisation_error``) was designed on this sweep;
``HOLDOUT`` is a second sweep at other loads and friction coefficients (s in [0.07, 50], mu_d
in {0.25, 1, 3, 7}) that it was not designed on, and tests/test_error_estimate_sweep.py runs a
third, smaller one.

The scenes run as tasks of ``spectral_contact.sweep.map_tasks`` (studies/_common.run_points: a
dask LocalCluster of --workers processes, default the cores; in this process with --serial, with
--quick unless --workers is given, or without dask.distributed); the table does not depend on it
but for time_s, the solve's wall time on its worker (inflated when workers share cores).
"""
from __future__ import annotations

import math
import sys
import time

import numpy as np

from spectral_contact import PAPER_SCENE, solve

from ._common import parse, run_points, table

REF_NODES, CHECK_NODES = 96, 64
FULL = ([float(v) for v in np.geomspace(0.05, 65.0, 14)], [0.0, 0.5, 2.0, 5.0, 10.0],
        [1e-2, 1e-3, 1e-4, 1e-5])
HOLDOUT = ([float(v) for v in np.geomspace(0.07, 50.0, 9)], [0.25, 1.0, 3.0, 7.0],
           [1e-2, 1e-3, 1e-4, 1e-5])
QUICK = ([0.05, 0.5, 3.0], [0.0, 2.0], [1e-3])


def scene_for(s: float, mu: float):
    """The paper's film and cylinder with the load whose Hertz half-width is s film thicknesses."""
    b = PAPER_SCENE
    return b.with_(load=2 * math.pi * s * s * b.stress_unit * b.length_unit, mu=mu)


def errors(q, r) -> dict:
    """The solver's metric (solvers/fft.py) per quantity: relative difference of a, x_c (over a),
    d, p_max of q from r."""
    a = abs(r.half_width)
    return {"a": abs(q.half_width - r.half_width) / a, "x_c": abs(q.center - r.center) / a,
            "d": abs(q.indentation - r.indentation) / abs(r.indentation),
            "p_max": abs(q.max_pressure - r.max_pressure) / r.max_pressure}


def difference(q, r) -> float:
    """The solver's metric: the largest of ``errors(q, r)``."""
    return max(errors(q, r).values())


def scene_point(point) -> list[dict]:
    """The rows of one scene (s, mu, tols): the Abel reference (and its check), then the FFT
    solve at each tol; a task of the sweep engine."""
    s, mu, tols = point
    rows = []
    scene = scene_for(s, mu)
    ref = solve(scene, method="abel", grid_points=REF_NODES)
    ref_check = difference(solve(scene, method="abel", grid_points=CHECK_NODES), ref)
    for tol in tols:
        t = time.perf_counter()
        try:
            r = solve(scene, tol=tol)
        except Exception as exc:  # a failure is a finding: keep the row
            rows.append({"s": s, "mu": mu, "tol": tol, "a_over_h": ref.half_width,
                         "status": f"fail: {type(exc).__name__}", "N": 0,
                         "error_estimate": float("nan"), "true_error": float("nan"), "which": "",
                         "ratio": float("nan"), "ref_check": ref_check,
                         "time_s": time.perf_counter() - t})
            continue
        errs = errors(r, ref)
        true = max(errs.values())
        rows.append({"s": s, "mu": mu, "tol": tol, "a_over_h": ref.half_width, "status": "ok",
                     "N": r.grid_points, "error_estimate": r.error_estimate, "true_error": true,
                     "which": max(errs, key=errs.get),
                     "ratio": r.error_estimate / true if true > 0 else float("inf"),
                     "ref_check": ref_check, "time_s": time.perf_counter() - t})
    return rows


def sweep_rows(args, points) -> list[dict]:
    """The rows of the scenes ``points = (S, MU, TOLS)`` (S x MU, each at every tol), through the
    engine of ``args`` (studies/_common.run_points)."""
    S, MU, TOLS = points
    return [row for rows_s in run_points(args, "studies.error_estimate", "scene_point",
                                          [(s, mu, TOLS) for mu in MU for s in S], "scenes")
            for row in rows_s]


def summary(rows) -> dict:
    """What the verification asks: runs, failures, the ratio's minimum and median, how many
    runs have the estimate below the true error, the largest true error over tol, the largest
    reference check."""
    ok = [r for r in rows if r["status"] == "ok"]
    ratio = np.array([r["ratio"] for r in ok])
    return {"runs": len(rows), "failed": len(rows) - len(ok),
            "ratio_min": float(ratio.min()), "ratio_median": float(np.median(ratio)),
            "below": int(np.sum(ratio < 1.0)),
            "true_over_tol_max": max(r["true_error"] / r["tol"] for r in ok),
            "ref_check_max": max(r["ref_check"] for r in rows)}


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/error_estimate", engine=True,
                      extra=lambda p: p.add_argument(
                          "--holdout", action="store_true",
                          help="the HOLDOUT sweep (other loads and mu_d) instead of the full one"))
    rows = sweep_rows(args, QUICK if args.quick else HOLDOUT if args.holdout else FULL)
    table(rows, out / "error_estimate.csv",
          f"FFT error_estimate vs true error (reference: Abel at {REF_NODES} nodes; ref_check = "
          f"its difference from {CHECK_NODES} nodes); s = a_Hertz/h, a_over_h = the film's a/h")
    ok = [r for r in rows if r["status"] == "ok"]
    ratio = np.array([r["ratio"] for r in ok])
    below = ratio < 1.0
    print(f"{len(ok)} runs ({len(rows) - len(ok)} failed); a/h {min(r['a_over_h'] for r in ok):.3g}"
          f" ... {max(r['a_over_h'] for r in ok):.3g}; reference check <= "
          f"{max(r['ref_check'] for r in rows):.1e}")
    print(f"ratio estimate / true error: min {ratio.min():.3g}, 5 % {np.quantile(ratio, 0.05):.3g}, "
          f"median {np.median(ratio):.3g}, 95 % {np.quantile(ratio, 0.95):.3g}, max {ratio.max():.3g}")
    worst = f", by up to {1.0 / ratio[below].min():.3g}x" if below.any() else ""
    print(f"estimate below the true error in {below.sum()} of {ratio.size} runs "
          f"({100 * below.mean():.1f} %){worst}")
    for tol in sorted({r["tol"] for r in ok}):
        sel = [r for r in ok if r["tol"] == tol]
        e = np.array([r["true_error"] for r in sel])
        print(f"  tol {tol:g}: true error <= tol in {np.sum(e <= tol)} of {e.size} runs "
              f"(max {e.max():.2g}); median ratio {np.median([r['ratio'] for r in sel]):.3g}")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(1, 2, figsize=(10, 4.2))
        for k, tol in enumerate(sorted({r["tol"] for r in ok})):
            sel = [r for r in ok if r["tol"] == tol]
            ax[0].loglog([r["true_error"] for r in sel], [r["error_estimate"] for r in sel], "os^"[k % 3],
                         ms=4, mfc="none", color=f"C{k}", label=f"tol {tol:g}")
            ax[0].axhline(tol, color=f"C{k}", lw=0.5, ls=":")
        lim = [min(r["true_error"] for r in ok) / 2, max(r["error_estimate"] for r in ok) * 2]
        ax[0].loglog(lim, lim, "k-", lw=0.8, label="estimate = true error")
        ax[0].set_xlabel(f"true error (against Abel, {REF_NODES} nodes)")
        ax[0].set_ylabel("error_estimate")
        ax[0].legend(fontsize=8)
        ax[0].set_title("each run (dotted: tol)", fontsize=9)
        for k, mu in enumerate(sorted({r["mu"] for r in ok})):
            sel = sorted((r for r in ok if r["mu"] == mu), key=lambda r: r["a_over_h"])
            ax[1].loglog([r["a_over_h"] for r in sel], [r["ratio"] for r in sel], "o", ms=3,
                         color=f"C{k}", label=f"mu_d = {mu:g}")
        ax[1].axhline(1.0, color="k", lw=0.8)
        ax[1].set_xlabel("a / h (film)")
        ax[1].set_ylabel("error_estimate / true error")
        ax[1].legend(fontsize=8)
        ax[1].set_title("ratio (< 1: the estimate is too small), all tols", fontsize=9)
        fig.tight_layout()
        fig.savefig(out / "error_estimate.png", dpi=110)
        plt.close(fig)
    except Exception as exc:  # a plot must never lose the table
        print(f"plot skipped: {exc}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
