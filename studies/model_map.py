"""Model map: where are the Hertz and Goodman models good enough, and the bound ``--model auto`` uses.

    python -m studies.model_map [--quick] [--out DIR] [--workers N | --serial]

Over s = a_Hertz/h in [0.05, 10] (log-spaced) and mu_d in [0, 5], each model (hertz: Hertz
pressure on the film, base transfer exact; goodman: frictionless pressure, friction loads the base
only) is compared with the exact model (fft method, reference tol 1e-5; 1e-4 with --quick) in

    a     |a_M - a| / a                       c     |x_c,M - x_c| / a  (contact centre)
    d     |d_M - d| / d  (indentation)        pmax  |p_max,M - p_max| / p_max
    szz   max|sigma_zz,M(x,0) - sigma_zz(x,0)| / max|sigma_zz(x,0)|   (on the exact model's grid)
    sxz   the same for sigma_xz(x,0)
    max   the largest of the six: what ``solvers.auto.model_error_bound`` bounds.

Goodman's fields come from one frictionless solve per s (Goodman's pressure and window do not
depend on mu; its base stresses are the film's symbols applied to -p0 and mu p0, as in the
solver: checked against ``solve(model="goodman")`` in the run), interpolated onto the exact
model's grid by cubic splines; Hertz's base stresses are evaluated on that grid directly.

Fit and validation of the bound: the s rows of even index are the fit set, the odd ones the
validation set.  On the fit set: C_H, P_H from the Hertz errors at mu = 0, C_G, P_G from the
Goodman errors / |mu| (log least squares over points with 10 tol_ref < error < 0.3), then K_H, K_G
= 1.5 x the largest measured/fitted ratio there.  Validation: the bound stored in
``solvers/auto.py`` and the fresh fit, against every measured point; a violation is a point where
the bound is below 0.1 (so auto could pick the model) but below the measured error by more than
the reference noise (2 x the reference tol).

The s rows run as tasks of ``spectral_contact.sweep.map_tasks`` (studies/_common.run_points: a
dask LocalCluster of --workers processes, default the cores; in this process with --serial, with
--quick unless --workers is given, or without dask.distributed): the tables are the same bit for
bit either way.

Writes model_map.csv (every point, every error), model_map_fit.csv (fit vs stored vs measured)
and model_map.png (contour maps with 1 %, 5 %, 10 % levels, measured solid / bound dashed, and
measured-vs-bound scatter).
"""
from __future__ import annotations

import math
import sys
import time

import numpy as np
from scipy.interpolate import CubicSpline

from spectral_contact import Scene, solve
from spectral_contact.errors import ConvergenceError
from spectral_contact.numerics.fft import get_rfft
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.film import base_stresses
from spectral_contact.reference.hertz import hertz_base_stresses, hertz_film_sinking, hertz_half_width
from spectral_contact.solvers import auto

from ._common import parse, run_points, table, write_rows

METRICS = ("a", "c", "d", "pmax", "szz", "sxz")
LEVELS = (0.01, 0.05, 0.10)
FIT_MAX = 0.3      # fit and scale on points whose error is below this (the range auto can use)
SAFETY = 1.5       # K = SAFETY x the largest measured/fitted ratio on the fit set


def scene_for(s: float, mu: float, base: Scene = Scene()) -> Scene:
    """A scene whose Hertz half-space half-width is s film thicknesses."""
    P = 2 * math.pi * s**2
    return base.with_(load=P * base.stress_unit * base.length_unit, mu=mu)


def _solve_ref(scene, model, tol):
    """The reference solve; relax tol by 2x (twice at most) if the solver gives up."""
    for t in (tol, 2 * tol, 4 * tol):
        try:
            return solve(scene, model=model, tol=t), t
        except ConvergenceError as exc:
            print(f"    note: {model} at P = {scene.P:.4g}, mu = {scene.mu:g}, tol {t:g}: {exc}",
                  file=sys.stderr)
    raise RuntimeError("reference solve failed at 4x the reference tolerance")


def _errors(ex, a, c, d, pmax, szz, sxz) -> dict:
    nzz = np.max(np.abs(ex.base_sigma_zz))
    nxz = np.max(np.abs(ex.base_sigma_xz))
    return {
        "a": abs(a - ex.half_width) / ex.half_width,
        "c": abs(c - ex.center) / ex.half_width,
        "d": abs(d - ex.indentation) / abs(ex.indentation),
        "pmax": abs(pmax - ex.max_pressure) / ex.max_pressure,
        "szz": float(np.max(np.abs(szz - ex.base_sigma_zz)) / nzz),
        "sxz": float(np.max(np.abs(sxz - ex.base_sigma_xz)) / nxz),
    }


class _Goodman:
    """Goodman's model for one s: one frictionless solve, base stresses for any mu."""

    def __init__(self, s, tol):
        self.r, self.tol = _solve_ref(scene_for(s, 0.0), "goodman", tol)
        r = self.r
        g = Grid(r.grid_points, r.domain_length, float(r.x[0]))
        fft = get_rfft(g.n)
        p = r.pressure
        z0, x0 = base_stresses(fft, g.k, -p, 0.0 * p)
        z1, x1 = base_stresses(fft, g.k, -p, p)
        self._zz = (z0, z1 - z0)   # sigma(mu) = sigma0 + mu * dsigma (linear in mu)
        self._xz = (x0, x1 - x0)

    def base(self, mu):
        return (self._zz[0] + mu * self._zz[1], self._xz[0] + mu * self._xz[1])

    def on(self, x, mu):
        """Base stresses interpolated (cubic spline) at x; 0 beyond the Goodman period."""
        zz, xz = self.base(mu)
        out = []
        for f in (zz, xz):
            v = CubicSpline(self.r.x, f, extrapolate=False)(x)
            out.append(np.nan_to_num(v, nan=0.0))
        return out


def measure(s: float, mu: float, tol_ref: float, goodman: _Goodman) -> dict:
    """All errors of hertz and goodman against exact at (s, mu)."""
    ex, t_used = _solve_ref(scene_for(s, mu), "exact", tol_ref)
    grid = Grid(ex.grid_points, ex.domain_length, float(ex.x[0]))
    aH = hertz_half_width(ex.scene.P)
    hz, hx = hertz_base_stresses(grid, aH, mu)
    eH = _errors(ex, aH, 0.0, hertz_film_sinking(aH), 4 * aH, hz, hx)
    gr = goodman.r
    gz, gx = goodman.on(ex.x, mu)
    eG = _errors(ex, gr.half_width, gr.center, gr.indentation, gr.max_pressure, gz, gx)
    row = {"s": float(s), "mu": float(mu), "a_exact": ex.half_width, "xc_exact": ex.center,
           "tol_ref": max(t_used, goodman.tol), "N_exact": ex.grid_points}
    for tag, e in (("H", eH), ("G", eG)):
        for m in METRICS:
            row[f"{tag}_{m}"] = float(e[m])
        row[f"{tag}_max"] = float(max(e.values()))
    return row


def measure_s(task) -> tuple[list, float | None]:
    """One s row of the map: ``task = (s, MU, tol_ref, check)``; returns the rows for every mu
    and, if ``check``, the Goodman reconstruction's relative difference from
    ``solve(model="goodman")`` at the largest mu (else None)."""
    s, MU, tol_ref, check = task
    gm = _Goodman(s, tol_ref)
    rows = [measure(s, mu, tol_ref, gm) for mu in MU]
    goodman_check = None
    if check:
        r = solve(scene_for(s, MU[-1]), model="goodman", tol=gm.tol)
        zz, xz = gm.base(MU[-1])
        goodman_check = float(max(np.max(np.abs(r.base_sigma_zz - zz)),
                                  np.max(np.abs(r.base_sigma_xz - xz))) / np.max(np.abs(zz)))
    return rows, goodman_check


# --- fit ----------------------------------------------------------------------------------------
def _powerfit(x, y):
    """y = C x^p by least squares in logs; returns (C, p)."""
    p, logC = np.polyfit(np.log(x), np.log(y), 1)
    return float(math.exp(logC)), float(p)


def fit_bound(rows, floor: float) -> dict:
    """Fit the bound's constants on ``rows`` (see module docstring); None where data lack."""
    h = [(r["s"], r["H_max"]) for r in rows if r["mu"] == 0 and floor < r["H_max"] < FIT_MAX]
    g = [(r["s"], r["G_max"] / r["mu"]) for r in rows
         if r["mu"] > 0 and floor < r["G_max"] < FIT_MAX]
    if len(h) < 2 or len(g) < 2:
        return None
    C_H, P_H = _powerfit(*map(np.array, zip(*h)))
    C_G, P_G = _powerfit(*map(np.array, zip(*g)))
    c = {"C_H": C_H, "P_H": P_H, "K_H": 1.0, "C_G": C_G, "P_G": P_G, "K_G": 1.0}
    kH = max(r["H_max"] / auto.model_error_bound("hertz", r["s"], r["mu"], c)
             for r in rows if r["H_max"] < FIT_MAX)
    kG = max(r["G_max"] / auto.model_error_bound("goodman", r["s"], r["mu"], c)
             for r in rows if 0 < r["mu"] and r["G_max"] < FIT_MAX)
    c["K_H"], c["K_G"] = SAFETY * kH, SAFETY * kG
    return c


def validate(rows, coeffs, label, noise: float) -> dict:
    """Compare a bound with the measured errors: ratios and violations (measured above the
    bound by more than the reference noise, where the bound is below 0.1)."""
    out = {"bound": label}
    for model, tag in (("hertz", "H"), ("goodman", "G")):
        ratios, viol = [], 0
        for r in rows:
            b = auto.model_error_bound(model, r["s"], r["mu"], coeffs)
            m = r[f"{tag}_max"]
            if m < FIT_MAX and b > 0:
                ratios.append(m / b)
            if b < 0.1 and m > b + noise:
                viol += 1
        out[f"{model}_max_measured_over_bound"] = float(max(ratios)) if ratios else float("nan")
        out[f"{model}_median_measured_over_bound"] = float(np.median(ratios)) if ratios else float("nan")
        out[f"{model}_violations"] = viol
    return out


def choices(rows, tols=(1e-3, 1e-2, 5e-2)):
    """What auto (stored bound) would pick, and whether the measured error respects tol."""
    out = []
    for tol in tols:
        picks = {"hertz": 0, "goodman": 0, "exact": 0}
        bad = 0
        for r in rows:
            m, _, _ = auto.choose_model(r["s"], r["mu"], tol)
            picks[m] += 1
            if m != "exact" and r[f"{m[0].upper()}_max"] >= tol:
                bad += 1
        out.append({"tol": tol, **{f"picks_{k}": v for k, v in picks.items()},
                    "picks_over_tol": bad})
    return out


# --- plots --------------------------------------------------------------------------------------
def _plot(rows, S, MU, fits, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    def grid_of(key):
        Z = np.full((len(MU), len(S)), np.nan)
        for r in rows:
            Z[MU.index(r["mu"]), S.index(r["s"])] = r[key]
        return Z

    def bound_grid(model):
        return np.array([[auto.model_error_bound(model, s, mu) for s in S] for mu in MU])

    X, Y = np.meshgrid(S, MU)
    panels = [("H_max", "hertz", "Hertz: max error vs exact"),
              ("G_max", "goodman", "Goodman: max error vs exact"),
              ("G_szz", None, "Goodman: base sigma_zz profile error"),
              ("G_sxz", None, "Goodman: base sigma_xz profile error")]
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.5))
    norm = LogNorm(1e-5, 1.0)
    for ax, (key, model, title) in zip(axes.flat, panels):
        Z = np.clip(grid_of(key), 1e-5, None)
        cf = ax.contourf(X, Y, Z, levels=np.logspace(-5, 0.5, 23), norm=norm, cmap="viridis",
                         extend="both")
        cs = ax.contour(X, Y, Z, levels=LEVELS, colors="w", linewidths=1.4)
        ax.clabel(cs, fmt=lambda v: f"{100 * v:g} %", fontsize=8)
        if model:  # same levels as the white lines, unlabelled (labels would overprint)
            ax.contour(X, Y, bound_grid(model), levels=LEVELS, colors="r", linestyles="--",
                       linewidths=1.0)
        ax.set_xscale("log")
        ax.set_yscale("symlog", linthresh=0.1, linscale=0.5)
        ax.set_xlabel("a_Hertz / h")
        ax.set_ylabel("mu_d")
        ax.set_title(title + ("\n(white: measured; red dashed: auto's bound, same levels)"
                              if model else "\n(white: measured)"), fontsize=9)
        cbar = fig.colorbar(cf, ax=ax, ticks=[1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1])
        cbar.set_label("relative error against the exact model", fontsize=8)
    # s-cuts of the error components at mu = mid value
    ax = axes.flat[4]
    mu_cut = MU[min(len(MU) - 1, max(1, len(MU) // 3))]
    cut = sorted((r for r in rows if r["mu"] == mu_cut), key=lambda r: r["s"])
    s_ = [r["s"] for r in cut]
    from matplotlib.lines import Line2D

    for m, col in zip(METRICS, ("C0", "C1", "C2", "C3", "C4", "C5")):
        ax.loglog(s_, [max(r[f"G_{m}"], 1e-9) for r in cut], "-", color=col, label=m)
        ax.loglog(s_, [max(r[f"H_{m}"], 1e-9) for r in cut], "--", color=col)
    ax.set_ylim(1e-7, 3)
    ax.set_xlabel("a_Hertz / h")
    ax.set_ylabel("relative error against the exact model")
    ax.set_title(f"error components at mu_d = {mu_cut:g}", fontsize=9)
    handles, labels = ax.get_legend_handles_labels()
    handles += [Line2D([], [], color="k", ls="-"), Line2D([], [], color="k", ls="--")]
    labels += ["Goodman", "Hertz"]
    ax.legend(handles, labels, fontsize=8, ncol=2, loc="lower right")
    # fit vs measured
    ax = axes.flat[5]
    for model, tag, mk in (("hertz", "H", "o"), ("goodman", "G", "s")):
        for which, alpha in ((0, 1.0), (1, 0.4)):
            pts = [(auto.model_error_bound(model, r["s"], r["mu"]), r[f"{tag}_max"])
                   for r in rows if fits.get(r["s"], 0) == which and r[f"{tag}_max"] > 0]
            if pts:
                b, m = zip(*pts)
                ax.loglog(b, m, mk, ms=3, alpha=alpha,
                          label=f"{model} ({'fit' if which == 0 else 'validation'} rows)")
    ax.loglog([1e-6, 10], [1e-6, 10], "k-", lw=0.8, label="measured = bound")
    ax.axhline(0.1, color="gray", lw=0.5)
    ax.axvline(0.1, color="gray", lw=0.5)
    ax.set_xlim(1e-5, 10)
    ax.set_ylim(1e-6, 3)
    ax.set_xlabel("auto's stored bound")
    ax.set_ylabel("measured max error")
    ax.set_title("fit vs measured: below the line wherever the bound < 0.1", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/model_map", engine=True)
    if args.quick:
        S = [float(v) for v in np.geomspace(0.05, 10, 6)]
        MU = [0.0, 0.1, 0.5, 1.0, 2.0, 5.0]
        tol_ref = 1e-4
    else:
        S = [float(v) for v in np.geomspace(0.05, 10, 22)]
        MU = [0.0, 0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0]
        tol_ref = 1e-5
    t0 = time.perf_counter()
    # one task per s (its Goodman solve serves every mu) on the sweep engine; the first also
    # checks the Goodman reconstruction against the solver's Goodman model
    tasks = [(s, MU, tol_ref, i == 0) for i, s in enumerate(S)]
    results = run_points(args, "studies.model_map", "measure_s", tasks, "s rows")
    rows = [r for rs, _ in results for r in rs]
    goodman_check = results[0][1]
    cols = ["s", "mu", "a_exact", "H_a", "H_pmax", "H_szz", "H_sxz", "H_max",
            "G_c", "G_szz", "G_sxz", "G_max"]
    printed = []
    for r in rows:
        d = {k: r[k] for k in cols}
        d["bound_H"] = auto.model_error_bound("hertz", r["s"], r["mu"])
        d["bound_G"] = auto.model_error_bound("goodman", r["s"], r["mu"])
        r.update({"bound_H": d["bound_H"], "bound_G": d["bound_G"]})
        printed.append(d)
    # the CSV keeps every column; the printed table the main ones
    write_rows(rows, out / "model_map.csv", f"Every scene of the map, every error (reference tol {tol_ref:g})")
    table(printed, out / "model_map_printed.csv",
          f"Model errors against the exact model (reference tol {tol_ref:g}); s = a_Hertz/h; "
          f"max = largest of a, centre, indentation, p_max, base sigma_zz and sigma_xz profiles")
    print(f"(all columns: {out / 'model_map.csv'})")
    print(f"Goodman reconstruction vs solve(model='goodman'): {goodman_check:.1e} relative")

    # fit on the even rows of s, validate on the odd ones (and everywhere)
    fits = {s: (j % 2) for j, s in enumerate(S)}  # 0: fit row, 1: validation row
    fit_rows = [r for r in rows if fits[r["s"]] == 0]
    val_rows = [r for r in rows if fits[r["s"]] == 1]
    fresh = fit_bound(fit_rows, floor=10 * tol_ref)
    report = []
    for label, coeffs in (("stored (solvers/auto.py)", None), ("fresh fit (this run)", fresh)):
        if coeffs is None and label.startswith("fresh"):
            continue
        c = auto.BOUND if coeffs is None else coeffs
        for subset, rs in (("fit rows", fit_rows), ("validation rows", val_rows), ("all", rows)):
            v = validate(rs, coeffs, label, noise=2 * tol_ref)
            v["rows"] = subset
            v.update({k: c[k] for k in ("C_H", "P_H", "K_H", "C_G", "P_G", "K_G")})
            report.append(v)
    table(report, out / "model_map_fit.csv",
          f"Bound vs measured (violation: bound < 0.1 but below the measured error by more "
          f"than the reference noise {2 * tol_ref:g})")
    print(f"stored bound provenance: {auto.PROVENANCE}")
    table(choices(rows), out / "model_map_auto.csv",
          "What --model auto picks on this map (stored bound) and how often the pick's measured "
          "error reaches tol (must be 0)")
    try:
        _plot(rows, S, MU, fits, out / "model_map.png")
        print(f"(written {out / 'model_map.png'})")
    except Exception as exc:  # a plot must never lose the table
        print(f"plot skipped: {exc}", file=sys.stderr)
    print(f"total {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
