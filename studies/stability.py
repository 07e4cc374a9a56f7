"""Where the FFT method fails, and how: domain length, grid spacing, friction, thin film.

    python -m studies.stability [--quick] [--out DIR] [--workers N | --serial]

Four sweeps, each against a reference the sweep does not touch:

1. Domain length (periodic images).  Errors of a, x_c, d against L - 2a, on nested grids of the
   same spacing and the same node positions (so the discretisation error is identical and
   cancels), against the predicted exp(-0.739 (L - 2a)); reference L - 2a = 40.
2. Grid spacing (under-resolution).  Errors against the points across the contact 2a/dx on a
   fixed period, raw (one grid) and averaged over a half-cell shift (what the solver returns);
   reference: the averaged solve on a grid 2^6-2^8 times finer.  Then the edge phase error: the
   sub-grid edge error in units of dx against theta, the edge's position within its cell
   (the grid shifted by s dx, s in [0, 1)), before and after the half-cell average.
3. Friction mu_d up to 1000: the automatic solve (tol 1e-4, and 1e-6 for some), its iterations,
   residual, failures; a cold start on a fixed grid; the number of contact intervals.
4. Thin film, mu_d = 0: a and p_max against the thin incompressible-layer asymptote.  For
   k h << 1 the compliance is H(k) ~ k^2/3, i.e. w = -(1/3) p''.  With w = d - x^2 in the contact
   and p = p' = 0 at x = +-a:  p = (a^2 - x^2)^2 / 4,  d = a^2/3,  P = 4 a^5 / 15,  so
   a_thin = (15 P / 4)^(1/5) and p_max = a_thin^4 / 4 (units: lengths h, stresses E h/6R).

Writes stability_domain.csv, stability_grid.csv, stability_phase.csv, stability_mu.csv,
stability_thin.csv and stability.png (one panel per aspect, failures marked with x).

Every point of the four sweeps runs as a task of ``spectral_contact.sweep.map_tasks``
(studies/_common.run_points: a dask LocalCluster of --workers processes, default the cores; in this
process with --serial, with --quick unless --workers is given, or without dask.distributed); the
tables do not depend on it, except time_s (stability_mu.csv), the wall time of the automatic
solve on its worker: with several workers on shared cores it is inflated (use --serial to time).
"""
from __future__ import annotations

import math
import re
import sys
import time

import numpy as np

from spectral_contact import ConvergenceError, Scene, solve
from spectral_contact.numerics.contact import solve_contact
from spectral_contact.numerics.edges import fit_edges, peak
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.film import DECAY_RATE
from spectral_contact.physics.indenters import Cylinder

from ._common import parse, run_points, table, write_rows

NAN = float("nan")
_FAILURES = (ConvergenceError, ValueError, np.linalg.LinAlgError)


def short(exc) -> str:
    """A one-word-ish status for a failure: which check failed, and by how much."""
    msg = str(exc)
    if "did not settle" in msg:
        return f"fail: active set did not settle ({getattr(exc, 'iterations', 0)} its)"
    m = re.search(r"relative residual (\S+) \((.*?)\)", msg)
    if m:
        parts = [p.split() for p in m.group(2).split(",")]
        worst = max(parts, key=lambda kv: float(kv[1]))[0]
        return f"fail: residual {m.group(1)} ({worst})"
    if "grid refinement" in msg:
        return "fail: refinement reached max N"
    return f"fail: {type(exc).__name__}"


# --- measuring one grid solution -----------------------------------------------------------------
def measure(sol) -> dict:
    """a, x_c (envelope of the contact runs), d, p_max, the outer edges and the number of runs."""
    edges = fit_edges(sol.grid.x, sol.grid.dx, sol.gap, sol.pressure, sol.active)
    left, right = min(e[0] for e in edges), max(e[1] for e in edges)
    pm, _ = peak(sol.grid.x, sol.pressure)
    return {"a": 0.5 * (right - left), "c": 0.5 * (right + left), "d": float(sol.indentations[0]),
            "pmax": pm, "left": left, "right": right, "runs": len(edges)}


def mean(q0: dict, q1: dict) -> dict:
    return {k: 0.5 * (q0[k] + q1[k]) for k in ("a", "c", "d", "pmax", "left", "right")}


def errors(q: dict, ref: dict) -> dict:
    """Relative errors: a and x_c relative to a, d to d, p_max to p_max."""
    return {"err_a": abs(q["a"] - ref["a"]) / ref["a"], "err_c": abs(q["c"] - ref["c"]) / ref["a"],
            "err_d": abs(q["d"] - ref["d"]) / abs(ref["d"]),
            "err_p": abs(q["pmax"] - ref["pmax"]) / ref["pmax"]}


def solve_grid(n, L, center, mu, P, shift=0.0):
    """One cold contact solve: n points on period L, the middle node at center + shift dx."""
    g = Grid.centered(n, L, center + shift * L / n)
    return solve_contact(g, mu, [Cylinder(0.0, P)])


# --- 1. domain length ----------------------------------------------------------------------------
def domain_point(scene, mu, margins, across):
    """The rows of one mu_d: every margin against the reference L - 2a = 40."""
    rows = []
    r = solve(scene.with_(mu=mu), tol=1e-4)  # locates the contact only
    a0, c0 = r.half_width, r.center
    dx = 2 * a0 / across
    n_ref = 2 * round((2 * a0 + 40.0) / dx / 2)
    ref = measure(solve_grid(n_ref, n_ref * dx, c0, mu, scene.P))
    for m in margins:
        n = 2 * round((2 * a0 + m) / dx / 2)  # same dx, same nodes (middle node at c0)
        L = n * dx
        row = {"mu": mu, "L_minus_2a": L - 2 * ref["a"], "N": n, "L": L, "status": "ok",
               "err_a": NAN, "err_c": NAN, "err_d": NAN, "err_p": NAN,
               "predicted": math.exp(-DECAY_RATE * (L - 2 * ref["a"])), "its": 0}
        try:
            sol = solve_grid(n, L, c0, mu, scene.P)
            row.update(errors(measure(sol), ref))
            row["its"] = sol.iterations
        except _FAILURES as exc:
            row["status"] = short(exc)
        rows.append(row)
    return rows


# --- 2. grid spacing and edge phase --------------------------------------------------------------
def locate(scene):
    """(a, x_c) of the automatic solve at tol 1e-4: where the grid and phase sweeps put their grids."""
    r = solve(scene, tol=1e-4)  # locates the contact only
    return r.half_width, r.center


def grid_point(n, L, c0, mu, P):
    """The measurements on n points, unshifted and shifted half a cell; a status on failure."""
    try:
        return measure(solve_grid(n, L, c0, mu, P)), measure(solve_grid(n, L, c0, mu, P, 0.5))
    except _FAILURES as exc:
        return short(exc)


def grid_rows(exps, nr, L, ref_q, qs):
    """The grid-spacing rows from the reference's and each grid's measurements (grid_point)."""
    ref = mean(*ref_q)
    rows = []
    for e, q01 in zip(exps, qs):
        n = 2**e
        row = {"N": n, "across": 2 * ref["a"] / (L / n), "status": "ok"}
        for tag in ("raw", "avg"):
            for q in ("a", "c", "d", "p"):
                row[f"{tag}_err_{q}"] = NAN
        if isinstance(q01, str):
            row["status"] = q01
        else:
            q0, q1 = q01
            for tag, q in (("raw", q0), ("avg", mean(q0, q1))):
                for k, v in errors(q, ref).items():
                    row[f"{tag}_{k}"] = v
        rows.append(row)
    return rows, {"L": L, "ref_N": nr, "ref_across": 2 * ref["a"] / (L / nr)}


def phase_point(a0, c0, mu, P, across, shifts):
    """Edge error / dx against theta (edge position within its cell), raw and half-cell averaged,
    at one resolution: (rows, summary row)."""
    L = 2 * a0 + 30.0
    rows = []
    dx = 2 * a0 / across
    n = 2 * math.ceil(L / dx / 2)
    Lg = n * dx
    nf = 32 * n  # reference: 32 times finer, averaged over its own half-cell shift
    ref = mean(measure(solve_grid(nf, Lg, c0, mu, P)),
               measure(solve_grid(nf, Lg, c0, mu, P, 0.5)))
    qs = [measure(solve_grid(n, Lg, c0, mu, P, s)) for s in shifts]
    ns = len(shifts)
    for i, s in enumerate(shifts):
        q, qh = qs[i], qs[(i + ns // 2) % ns]  # the grid shifted by a further half cell
        origin = Grid.centered(n, Lg, c0 + s * dx).origin
        row = {"across": across, "s": s}
        for side in ("right", "left"):
            e_ref = ref[side]
            row[f"theta_{side}"] = ((e_ref - origin) / dx) % 1.0
            row[f"raw_{side}"] = (q[side] - e_ref) / dx
            row[f"avg_{side}"] = (0.5 * (q[side] + qh[side]) - e_ref) / dx
        row["raw_a_rel"] = (q["a"] - ref["a"]) / ref["a"]
        row["avg_a_rel"] = (0.5 * (q["a"] + qh["a"]) - ref["a"]) / ref["a"]
        rows.append(row)
    sel = [rw for rw in rows if rw["across"] == across]
    stat = {"across": across, "N": n}
    for tag in ("raw", "avg"):
        v = np.array([[rw[f"{tag}_right"], rw[f"{tag}_left"]] for rw in sel])
        stat[f"{tag}_mean_dx"] = float(v.mean())
        stat[f"{tag}_rms_dx"] = float(np.sqrt(np.mean((v - v.mean(axis=0)) ** 2)))
        stat[f"{tag}_max_dx"] = float(np.abs(v).max())
        stat[f"{tag}_max_a_rel"] = float(max(abs(rw[f"{tag}_a_rel"]) for rw in sel))
    return rows, stat


# --- 3. friction ---------------------------------------------------------------------------------
def _runs_gap(edges):
    e = sorted(edges)
    return max((e[i + 1][0] - e[i][1] for i in range(len(e) - 1)), default=0.0)


def mu_point(scene, mu, fine, fixed_n):
    """One mu_d: the automatic solve (and at tol 1e-6 if ``fine``), the cold start on fixed_n."""
    row = {"mu": mu, "status": "ok", "a": NAN, "c": NAN, "d": NAN, "pmax": NAN, "runs": 0,
           "runs_gap": NAN, "N": 0, "L": NAN, "levels": 0, "asi_final": 0, "gmres_total": 0,
           "residual": NAN, "estimate": NAN, "time_s": NAN, "tol6_status": "",
           "tol6_diff": NAN, "cold_status": "", "cold_asi": 0, "cold_gmres": 0}
    sc = scene.with_(mu=mu)
    t = time.perf_counter()
    try:
        r = solve(sc, tol=1e-4)
        row.update(a=r.half_width, c=r.center, d=r.indentation, pmax=r.max_pressure,
                   runs=len(r.info["edges"]), runs_gap=_runs_gap(r.info["edges"]),
                   N=r.grid_points, L=r.domain_length, levels=len(r.info["levels"]),
                   asi_final=r.iterations, gmres_total=r.info["krylov_iterations"],
                   residual=r.residual, estimate=r.error_estimate)
    except ConvergenceError as exc:
        row["status"] = short(exc)
        r = None
    row["time_s"] = time.perf_counter() - t
    if fine:
        try:
            r6 = solve(sc, tol=1e-6)
            row["tol6_status"] = "ok"
            if r is not None:
                row["tol6_diff"] = abs(r.half_width - r6.half_width) / r6.half_width
        except ConvergenceError as exc:
            row["tol6_status"] = short(exc)
    # cold start (Hertz guess) on a fixed grid covering the contact: the active-set iteration
    # without the solver's warm starts
    L = r.domain_length if r is not None else 2 * 8.0 + 20
    ctr = r.center if r is not None else 0.0
    try:
        sol = solve_grid(fixed_n, L, ctr, mu, sc.P)
        row.update(cold_status="ok", cold_asi=sol.iterations, cold_gmres=sol.krylov_iterations)
    except _FAILURES as exc:
        row["cold_status"] = short(exc)
    return row


def split_threshold(scene, lo, hi, steps):
    """Bisect the smallest mu at which the automatic solve returns two contact intervals."""
    def runs(mu):
        return len(solve(scene.with_(mu=mu), tol=1e-4).info["edges"])
    if runs(lo) != 1 or runs(hi) < 2:
        return NAN, NAN
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if runs(mid) == 1 else (lo, mid)
    return lo, hi


# --- 4. thin film --------------------------------------------------------------------------------
def thin_point(scene, A):
    """The thin-film row of a_thin = A (mu = 0)."""
    P = 4 * A**5 / 15
    sc = scene.with_(load=P * scene.stress_unit * scene.length_unit, mu=0.0)
    row = {"a_thin": A, "P": sc.P, "status": "ok", "a": NAN, "a_over_thin": NAN,
           "thin_minus_a": NAN, "pmax_over_thin": NAN, "d_over_thin": NAN,
           "a_hertz": math.sqrt(sc.P / (2 * math.pi)), "N": 0, "L": NAN, "estimate": NAN}
    try:
        r = solve(sc, tol=1e-4)
        row.update(a=r.half_width, a_over_thin=r.half_width / A, thin_minus_a=A - r.half_width,
                   pmax_over_thin=r.max_pressure / (A**4 / 4),
                   d_over_thin=r.indentation / (A * A / 3), N=r.grid_points,
                   L=r.domain_length, estimate=r.error_estimate)
    except ConvergenceError as exc:
        row["status"] = short(exc)
    return row


_POINTS = {"domain": domain_point, "grid": grid_point, "phase": phase_point, "mu": mu_point,
           "thin": thin_point}


def point(task):
    """One task of the sweep engine: (kind, *arguments) -> kind_point(*arguments)."""
    kind, *a = task
    return _POINTS[kind](*a)


# --- figure --------------------------------------------------------------------------------------
def plot(path, dom, grid, phase, mus, thin):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 3, figsize=(15, 8.5))
    # 1. domain
    a = ax[0, 0]
    lowest = 1.0
    failed = False
    for mu in sorted({r["mu"] for r in dom}):
        sel = [r for r in dom if r["mu"] == mu]
        ok = [r for r in sel if r["status"] == "ok"]
        m = np.array([r["L_minus_2a"] for r in ok])
        err = np.array([max(r["err_a"], r["err_c"], r["err_d"]) for r in ok])
        a.semilogy(m, np.maximum(err, 1e-17), "o-", ms=3, label=f"max(a, x_c, d) error, mu_d = {mu:g}")
        if err.size and np.any(err > 0):
            lowest = min(lowest, float(err[err > 0].min()))
        for r in sel:
            if r["status"] != "ok":
                a.plot(r["L_minus_2a"], 1.0, "rx", ms=9)
                failed = True
    m = np.linspace(0, max(r["L_minus_2a"] for r in dom), 50)
    a.semilogy(m, np.exp(-DECAY_RATE * m), "k--", label="exp(-0.739 (L-2a))")
    a.axvline(math.log(100 / 1e-4) / DECAY_RATE, color="g", ls=":", label="solver margin, tol 1e-4")
    if failed:
        a.plot([], [], "rx", label="solve failed")
    a.set_xlabel("L - 2a [h]")
    a.set_ylabel("relative error (images)")
    a.set_ylim(max(lowest / 5, 1e-17), 10)  # down to the data, not to round-off
    a.legend(fontsize=7)
    a.set_title("1. periodic images")
    # 2. grid
    a = ax[0, 1]
    ok = [r for r in grid if r["status"] == "ok"]
    x = [r["across"] for r in ok]
    for tag, st in (("raw", "o-"), ("avg", "s-")):
        a.loglog(x, [max(r[f"{tag}_err_a"], r[f"{tag}_err_c"]) for r in ok], st, ms=3,
                 label=f"a, x_c ({tag})")
        a.loglog(x, [r[f"{tag}_err_d"] for r in ok], st, ms=3, alpha=0.6, label=f"d ({tag})")
    for r in grid:
        if r["status"] != "ok":
            a.plot(r["across"], 1.0, "rx", ms=9)
    if any(r["status"] != "ok" for r in grid):
        a.plot([], [], "rx", label="solve failed")
    xx = np.array([min(x), max(x)])
    a.loglog(xx, 0.02 / xx, "k:", label="0.02 dx/a")
    a.set_xlabel("points across the contact 2a/dx")
    a.set_ylabel("relative error")
    a.legend(fontsize=7)
    a.set_title("2. grid spacing (mu_d = 2)")
    # 3. phase
    a = ax[0, 2]
    across = sorted({r["across"] for r in phase})
    for k, ac in enumerate(across):
        sel = sorted((r for r in phase if r["across"] == ac), key=lambda r: r["theta_right"])
        th = [r["theta_right"] for r in sel]
        a.plot(th, [r["raw_right"] for r in sel], "o-", ms=3, color=f"C{k}",
               label=f"raw, {ac:g} across")
        a.plot(th, [r["avg_right"] for r in sel], "s--", ms=3, color=f"C{k}",
               label=f"half-cell average, {ac:g} across")
    a.axhline(0, color="k", lw=0.5)
    a.set_xlabel("theta: right edge position within its cell")
    a.set_ylabel("edge error / dx")
    a.legend(fontsize=7)
    a.set_title("2b. edge phase error")
    # 4. mu: iterations
    a = ax[1, 0]
    mu_ok = [r for r in mus if r["status"] == "ok"]
    cold = [r for r in mus if r["cold_status"] == "ok"]
    a.loglog([max(r["mu"], 0.1) for r in cold], [r["cold_gmres"] for r in cold], "o-", ms=3,
             label="GMRES its, cold start, fixed N")
    a.loglog([max(r["mu"], 0.1) for r in cold], [r["cold_asi"] for r in cold], "s-", ms=3,
             label="active-set its, cold start, fixed N")
    for r in mus:
        if r["cold_status"] != "ok":
            a.plot(max(r["mu"], 0.1), 300, "C1x", ms=10)
    if any(r["cold_status"] != "ok" for r in mus):
        a.plot([], [], "C1x", label="cold start fails")
    a.loglog([max(r["mu"], 0.1) for r in mu_ok], [r["gmres_total"] for r in mu_ok], "^-", ms=3,
             label="GMRES its, automatic solve (all levels)")
    for r in mus:
        if r["status"] != "ok":
            a.plot(max(r["mu"], 0.1), r["gmres_total"] or 1e3, "rx", ms=10)
        if r["tol6_status"].startswith("fail"):
            a.plot(max(r["mu"], 0.1), 3e3, "mx", ms=10)
    if any(r["status"] != "ok" for r in mus):  # legend entries only for markers drawn
        a.plot([], [], "rx", label="automatic solve fails (tol 1e-4)")
    if any(r["tol6_status"].startswith("fail") for r in mus):
        a.plot([], [], "mx", label="automatic solve fails (tol 1e-6)")
    a.set_xlabel("mu_d (0 drawn at 0.1)")
    a.set_ylabel("iterations")
    a.legend(fontsize=7)
    a.set_title("3. friction: iterations and failures")
    # 5. mu: physics
    a = ax[1, 1]
    a.semilogx([max(r["mu"], 0.1) for r in mu_ok], [r["a"] for r in mu_ok], "o-", ms=3, label="a")
    a.semilogx([max(r["mu"], 0.1) for r in mu_ok], [r["c"] for r in mu_ok], "s-", ms=3, label="x_c")
    two = [r for r in mu_ok if r["runs"] > 1]
    if two:
        a.semilogx([r["mu"] for r in two], [10 * r["runs_gap"] for r in two], "rd-", ms=4,
                   label="10 x gap between the two contact intervals")
    a.set_xlabel("mu_d (0 drawn at 0.1)")
    a.set_ylabel("lengths [h]")
    tw = a.twinx()  # one unit per axis: stresses on the right
    tw.semilogx([max(r["mu"], 0.1) for r in mu_ok], [r["pmax"] for r in mu_ok], "^-", ms=3,
                color="C2", label="p_max (right axis)")
    tw.set_ylabel("p_max [E h / 6R]", color="C2")
    h1, l1 = a.get_legend_handles_labels()
    h2, l2 = tw.get_legend_handles_labels()
    a.legend(h1 + h2, l1 + l2, fontsize=7, loc="upper left")
    a.set_title("3b. friction: contact (tol 1e-4)")
    # 6. thin
    a = ax[1, 2]
    ok = [r for r in thin if r["status"] == "ok"]
    A = [r["a_thin"] for r in ok]
    a.loglog(A, [r["a_over_thin"] for r in ok], "o-", ms=3, label="a / a_thin")
    a.loglog(A, [r["pmax_over_thin"] for r in ok], "s-", ms=3, label="p_max / (a_thin^4/4)")
    a.loglog(A, [r["d_over_thin"] for r in ok], "^-", ms=3, label="d / (a_thin^2/3)")
    AA = np.array(A)
    pos = AA > 1.46 * 1.05  # the fitted offset, where it is positive
    a.loglog(AA[pos], 1 - 1.46 / AA[pos], "k:", label="1 - 1.46 h / a_thin")
    for r in thin:
        if r["status"] != "ok":
            a.plot(r["a_thin"], 1.0, "rx", ms=10)
    if any(r["status"] != "ok" for r in thin):
        a.plot([], [], "rx", label="solver fails")
    a.axhline(1, color="k", lw=0.5)  # every curve drawn whole (log scale, no clipping)
    a.set_ylabel("ratio to the thin-film asymptote")
    from matplotlib.ticker import FormatStrFormatter, LogLocator

    a.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    a.yaxis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
    a.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
    a.tick_params(axis="y", which="minor", labelsize=7)
    a.set_xlabel("a_thin = (15 P / 4)^(1/5)  [h]   (mu = 0)")
    a.legend(fontsize=7)
    a.set_title("4. thin-film limit")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/stability", engine=True)
    scene = Scene()
    if args.quick:
        dom_mus, margins, across_dom = [2.0], [0.5, 2, 4, 8, 12, 16, 20], 64
        exps, ref_exp = list(range(5, 13)), 15
        acrosses, shifts = [32], [i / 8 for i in range(8)]
        mus, fine_mus, fixed_n = [0.0, 2.0, 10.0, 50.0, 100.0], [], 2**12
        split = None
        thins = [1.0, 3.0, 10.0, 20.0]
    else:
        dom_mus = [0.0, 2.0, 10.0]
        margins = [0.25, 0.5, 1, 2, 3, 4, 5, 6, 8, 10, 12, 14, 16, 18, 20, 22, 25, 28, 32]
        across_dom = 128
        exps, ref_exp = list(range(4, 18)), 20
        acrosses, shifts = [16, 64, 256], [i / 32 for i in range(32)]
        mus = [0.0, 0.5, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0,
               80.0, 85.0, 90.0, 95.0, 96.0, 98.0, 100.0, 120.0, 150.0, 200.0, 300.0, 500.0,
               600.0, 700.0, 1000.0]
        fine_mus = [2.0, 20.0, 50.0, 80.0, 85.0, 90.0, 100.0]
        fixed_n = 2**13
        split = (95.0, 96.0, 7)
        thins = [0.5, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0, 50.0, 100.0, 150.0, 200.0]

    # every point of the four sweeps, one task each, on the sweep engine (the bisection for the
    # split threshold is sequential: it runs here, after them)
    a0, c0 = locate(scene)
    L = 2 * a0 + 30.0  # images ~ exp(-0.739 * 30) = 2e-10
    nr = 2**ref_exp
    mu, P = scene.mu, scene.P
    tasks = ([("domain", scene, m, margins, across_dom) for m in dom_mus]
             + [("grid", nr, L, c0, mu, P)] + [("grid", 2**e, L, c0, mu, P) for e in exps]
             + [("phase", a0, c0, mu, P, ac, shifts) for ac in acrosses]
             + [("mu", scene, m, m in fine_mus, fixed_n) for m in mus]
             + [("thin", scene, A) for A in thins])
    res = iter(run_points(args, "studies.stability", "point", tasks, "points"))
    dom = [row for _ in dom_mus for row in next(res)]
    ref_q = next(res)
    if isinstance(ref_q, str):  # the reference must solve (as before: its failure ends the study)
        raise ConvergenceError(f"grid-spacing reference N = {nr}: {ref_q}")
    grid, gmeta = grid_rows(exps, nr, L, ref_q, [next(res) for _ in exps])
    phase, psum = [], []
    for _ in acrosses:
        rows, stat = next(res)
        phase += rows
        psum.append(stat)
    murows = [next(res) for _ in mus]
    thin = [next(res) for _ in thins]
    table(dom, out / "stability_domain.csv",
          f"1. Periodic images: errors vs L - 2a at fixed dx = 2a/{across_dom} (same nodes), "
          f"reference L - 2a = 40; predicted = exp(-0.739 (L - 2a))")
    table(grid, out / "stability_grid.csv",
          f"2. Grid spacing (mu = {scene.mu:g}, P = {scene.P:.4g}): relative errors vs points "
          f"across the contact, period {gmeta['L']:.2f} h; raw = one grid, avg = mean with the "
          f"half-cell shifted grid; reference N = {gmeta['ref_N']} "
          f"({gmeta['ref_across']:.0f} across), averaged")
    main_across = acrosses[len(acrosses) // 2]
    table([r for r in phase if r["across"] == main_across], out / "stability_phase.csv",
          f"2b. Edge phase error (edge error / dx) vs theta, {main_across} points across; "
          f"avg = mean with the grid shifted half a cell (reference: 32x finer, averaged)")
    if len(acrosses) > 1:  # every resolution, CSV only (the chart shows them all)
        write_rows(phase, out / "stability_phase_all.csv",
                   "2b. Edge phase error (edge error / dx) vs theta, every resolution")
    table(psum, out / "stability_phase_summary.csv",
          "2b. Edge phase error summary over theta (both edges): mean (bias), rms about the mean, "
          "max |error| in dx; max relative error of a")
    table(murows, out / "stability_mu.csv",
          f"3. Friction: automatic solve at tol 1e-4 (tol6 = at 1e-6: status, |a - a6|/a6), and a "
          f"cold start on N = {fixed_n} (cold_*); runs = contact intervals, runs_gap = widest gap "
          f"between them [h]")
    if split:
        lo, hi = split_threshold(scene, *split)
        print(f"contact splits into two intervals between mu_d = {lo:.4f} and {hi:.4f}")
    table(thin, out / "stability_thin.csv",
          "4. Thin film (mu = 0): solver vs asymptote a_thin = (15P/4)^(1/5), p_max = a_thin^4/4, "
          "d = a_thin^2/3 (tol 1e-4); a_hertz = sqrt(P/2pi), the half-space width")
    try:
        plot(out / "stability.png", dom, grid, phase, murows, thin)
    except Exception as exc:  # a plot must never lose the tables
        print(f"plot skipped: {exc}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
