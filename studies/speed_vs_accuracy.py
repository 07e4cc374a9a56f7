"""Speed against accuracy: the FFT solver and the Abel solver on the same scenes.

    python -m studies.speed_vs_accuracy [--quick] [--out DIR] [--workers N | --serial]

Scenes (E = 2.2 MPa, R = 130 mm, h = 2 mm, mu_d = 2): the paper's (P_L = 200 N/m, a = 1.25 h)
and a thin-film one (P_L = 1900 N/m, a = 3.04 h).

Reference: the Abel solver at 48 Nystrom nodes (abel_fields, load matched to 1e-13), checked
against Abel at 64 nodes and against the FFT solver at a very small tol (1e-6; 1e-5 with --quick).

Runs, each timed as the median of 5 warm runs of the whole call (1 with --quick, whose times
are not worth reading; the first, cold call is not timed):
  FFT   tol = 1e-2 ... 1e-6 (automatic grid and period), and fixed N = 2^8 ... 2^17 on a fixed
        period (the automatic period at tol 1e-4);
  Abel  fixed node count 6 ... 24 (solve_abel rejects n < 6) and tol = 1e-2 ... 1e-8; profiles
        evaluated on the comparison window only.  The Abel kernel quadrature (20-point
        Gauss-Legendre panels in k) is not exposed by solve_abel, so it is not varied; the k-rule
        size used is written in the CSV.  One more Abel run at tol 1e-4 evaluates the profile at
        one point only ("abel scalars only": the cost of a, x_c, d, p_max alone).
Defaults: tol 1e-4 for each method (starred on the charts).

Errors against the reference: "scalar" = max relative error of a, x_c (relative to a), the
indentation d and p_max; "base" = max over sigma_zz(x, 0) and sigma_xz(x, 0) of
max |diff| / max |ref| on the window x_c +- (a + 4 h) (FFT: on its own grid nodes there, so no
interpolation enters).

The accuracy of every run (one solve each, and the reference checks) runs as tasks of
``spectral_contact.sweep.map_tasks`` (studies/_common.run_points: a dask LocalCluster of --workers
processes, default the cores; in this process with --serial, with --quick unless --workers is
given, or without dask.distributed); the errors do not depend on it.  The times are measured
afterwards in this process, one run after the other (never concurrently, never on a worker).

Writes speed_vs_accuracy.csv (every run), speed_vs_accuracy_winners.csv (fastest run of each
method reaching a target error), speed_vs_accuracy_reference.csv and one chart per scene
(speed_vs_accuracy_paper.png, speed_vs_accuracy_thin.png: scalar and base panels, log-log).
"""
from __future__ import annotations

import functools
import math
import statistics
import sys
import time
import warnings

import numpy as np

from spectral_contact import Scene, solve
from spectral_contact.solvers.abel import abel_fields, solve_abel

from ._common import parse, run_points, table

SCENES = {"paper": Scene(load=200.0, mu=2.0), "thin": Scene(load=1900.0, mu=2.0)}
REF_NODES, REF_CHECK_NODES = 48, 64
WINDOW_MARGIN = 4.0  # h beyond the contact on each side
TARGETS = (1e-3, 1e-4, 1e-5, 1e-6, 1e-8, 1e-12)
FLOOR = 1e-16  # errors are clipped here for the log axes


def _median_time(fn, repeats: int):
    out = fn()  # warm: plans, caches
    ts = []
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts), out


class Reference:
    """Abel at REF_NODES nodes: scalars and base stresses anywhere (apex frame)."""

    def __init__(self, scene: Scene):
        self.scene = scene
        s = abel_fields(scene, scene.mu, REF_NODES)
        self.s = s
        self.a, self.c, self.d, self.pmax = s.sol.a, -s.x0, s.inv_alpha, s.pmax
        lo, hi = self.c - self.a - WINDOW_MARGIN, self.c + self.a + WINDOW_MARGIN
        self.window = (lo, hi)
        self.x = np.linspace(lo, hi, 401)
        self.szz, self.sxz = self.base(self.x)

    def base(self, x):
        return self.s.sol.base_stresses(np.asarray(x) + self.s.x0, self.scene.mu)

    def scalar_errors(self, a, c, d, pmax) -> dict:
        return {"err_a": abs(a / self.a - 1), "err_xc": abs(c - self.c) / self.a,
                "err_d": abs(d / self.d - 1), "err_pmax": abs(pmax / self.pmax - 1)}

    def base_error(self, x, szz, sxz, rzz=None, rxz=None) -> float:
        if rzz is None:
            rzz, rxz = self.base(x)
        return max(np.max(np.abs(szz - rzz)) / np.max(np.abs(rzz)),
                   np.max(np.abs(sxz - rxz)) / np.max(np.abs(rxz)))


def _record(ref, scene_name, method, sweep, param, r, t, base_err, n_or_nodes, extra=None):
    e = ref.scalar_errors(r.half_width, r.center, r.indentation, r.max_pressure)
    rec = {"scene": scene_name, "method": method, "sweep": sweep, "param": param,
           "N_or_nodes": n_or_nodes, "median_ms": 1e3 * t,
           "err_scalar": max(max(e.values()), FLOOR), **e, "err_base": max(base_err, FLOOR),
           "error_estimate": float(r.error_estimate)}
    # does the method's own estimate cover the true error (roundoff level excepted)?
    rec["estimate_covers"] = int(rec["error_estimate"] >= rec["err_scalar"] or rec["err_scalar"] < 1e-13)
    rec.update(extra or {})
    return rec


@functools.cache
def reference(scene_name: str) -> Reference:
    """The Reference of SCENES[scene_name], made once per process (deterministic: every worker
    makes the same one, bit for bit)."""
    return Reference(SCENES[scene_name])


def _call(ref, kind, kw):
    """The call a run times and measures: "fft" = solve, "abel" = solve_abel on the reference's
    window, "scalars" = solve_abel with the profile at x_c only."""
    if kind == "fft":
        return lambda: solve(ref.scene, **kw)
    if kind == "abel":
        return lambda: solve_abel(ref.scene, x=ref.x, **kw)
    return lambda: solve_abel(ref.scene, x=np.array([ref.c]), **kw)


def accuracy_point(run) -> dict:
    """A task of the sweep engine: ("check", scene) -> the reference row of the scene (Abel at
    REF_CHECK_NODES against REF_NODES); (kind, scene, sweep, param, kw) -> the run's record, its
    errors against the reference, without its time (median_ms NaN: timed later, serially)."""
    if run[0] == "check":
        name = run[1]
        ref, scene = reference(name), SCENES[name]
        check = abel_fields(scene, scene.mu, REF_CHECK_NODES)
        ce = ref.scalar_errors(check.sol.a, -check.x0, check.inv_alpha, check.pmax)
        cb = ref.base_error(ref.x, *check.sol.base_stresses(ref.x + check.x0, scene.mu),
                            ref.szz, ref.sxz)
        return {"scene": name, "load_N_per_m": scene.load, "mu": scene.mu,
                "a_h": ref.a, "xc_h": ref.c, "indentation": ref.d, "pmax": ref.pmax,
                f"abel{REF_CHECK_NODES}_scalar_diff": max(max(ce.values()), FLOOR),
                f"abel{REF_CHECK_NODES}_base_diff": max(cb, FLOOR)}
    kind, name, sweep, param, kw = run
    ref = reference(name)
    nan = float("nan")
    if kind == "fft":
        r = _call(ref, kind, kw)()
        lo, hi = ref.window
        m = (r.x >= lo) & (r.x <= hi)
        berr = ref.base_error(r.x[m], r.base_sigma_zz[m], r.base_sigma_xz[m])
        return _record(ref, name, "fft", sweep, param, r, nan, berr, r.grid_points,
                       {"domain_h": r.domain_length, "k_rule_points": 0, "warned": 0})
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        r = _call(ref, kind, kw)()
    if kind == "abel":
        berr = ref.base_error(ref.x, r.base_sigma_zz, r.base_sigma_xz, ref.szz, ref.sxz)
        warned = int(len(w) > 0)
    else:  # the Abel cost without base stresses (profile at one point): scalars only
        berr, warned = nan, 0
    return _record(ref, name, "abel", sweep, param, r, nan, berr, r.info["n_nodes"],
                   {"domain_h": nan, "k_rule_points": r.info["kernel_quadrature_points"],
                    "warned": warned})


def time_runs(runs, repeats: int) -> list[float]:
    """Median wall time [s] of ``repeats`` warm calls (one untimed call first) of each run, one
    run after the other in this process: timings never run concurrently."""
    ts = []
    for kind, name, _sweep, _param, kw in runs:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ts.append(_median_time(_call(reference(name), kind, kw), repeats)[0])
    return ts


def _winners(rows, scene_name, err_key, pool):
    """Fastest run of each method with error <= target; pool "any" (every run, fixed N or node
    count included) or "tol-driven" (the automatic runs a user gets from a tolerance)."""
    out = []
    sweeps = {"any": ("fft tol", "fft fixed N", "abel nodes", "abel tol"),
              "tol-driven": ("fft tol", "abel tol")}[pool]
    for target in TARGETS:
        rec = {"scene": scene_name, "error": err_key.replace("err_", ""), "runs": pool,
               "target": target}
        for method in ("fft", "abel"):
            ok = [r for r in rows if r["scene"] == scene_name and r["method"] == method
                  and r["sweep"] in sweeps and r[err_key] <= target]
            best = min(ok, key=lambda r: r["median_ms"]) if ok else None
            rec[f"{method}_ms"] = best["median_ms"] if best else float("nan")
            rec[f"{method}_run"] = f"{best['sweep']} {best['param']}" if best else "not reached"
        f, a = rec["fft_ms"], rec["abel_ms"]
        if math.isnan(f) and math.isnan(a):
            rec["winner"] = "none"
        elif math.isnan(f) or (not math.isnan(a) and a < f):
            rec["winner"] = "abel"
        else:
            rec["winner"] = "fft"
        both = not (math.isnan(f) or math.isnan(a))
        rec["speedup"] = max(f, a) / min(f, a) if both else float("nan")
        out.append(rec)
    return out


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/speed_vs_accuracy", engine=True)
    quick = args.quick
    repeats = 1 if quick else 5  # --quick checks the errors, not the times
    fft_tols = [1e-2, 1e-3, 1e-4, 1e-5] if quick else [1e-2, 1e-3, 1e-4, 1e-5, 1e-6]
    ref_tol = 1e-5 if quick else 1e-6
    exps = range(8, 13) if quick else range(8, 18)
    nodes = [6, 8, 12, 16, 24] if quick else [6, 8, 10, 12, 14, 16, 20, 24]
    abel_tols = [1e-2, 1e-4, 1e-6] if quick else [1e-2, 1e-3, 1e-4, 1e-6, 1e-8]
    runs = []
    for name, scene in SCENES.items():
        L_m = solve(scene, tol=1e-4).domain_length * scene.length_unit
        runs += [("fft", name, "fft tol", f"{tol:.0e}", {"tol": tol}) for tol in fft_tols]
        runs += [("fft", name, "fft fixed N", f"2^{e}", {"grid_points": 2**e, "domain_length": L_m})
                 for e in exps]
        runs += [("abel", name, "abel nodes", str(n), {"n_nodes": n}) for n in nodes]
        runs += [("abel", name, "abel tol", f"{tol:.0e}", {"tol": tol}) for tol in abel_tols]
        runs.append(("scalars", name, "abel scalars only", "1e-04", {"tol": 1e-4}))
    # the accuracy of every run (and the reference checks) on the sweep engine ...
    res = run_points(args, "studies.speed_vs_accuracy", "accuracy_point",
                     [("check", name) for name in SCENES] + runs, "runs")
    checks, rows = res[:len(SCENES)], res[len(SCENES):]
    # ... then the times, serially in this process (never two timings at once)
    print(f"timing {len(runs)} runs serially (median of {repeats} warm calls each)",
          file=sys.stderr, flush=True)
    for rec, t in zip(rows, time_runs(runs, repeats)):
        rec["median_ms"] = 1e3 * t
    refrows, winners = [], []
    for name, chk in zip(SCENES, checks):
        fft_check = next(r for r in rows if r["scene"] == name and r["sweep"] == "fft tol"
                         and r["param"] == f"{ref_tol:.0e}")
        refrows.append({**chk, "fft_check_tol": ref_tol, "fft_scalar_diff": fft_check["err_scalar"],
                        "fft_base_diff": fft_check["err_base"],
                        "fft_error_estimate": fft_check["error_estimate"]})
        for pool in ("tol-driven", "any"):
            for key in ("err_scalar", "err_base"):
                winners += _winners(rows, name, key, pool)

    cols = ["scene", "method", "sweep", "param", "N_or_nodes", "median_ms", "err_scalar",
            "err_base", "error_estimate", "err_a", "err_xc", "err_d", "err_pmax", "domain_h",
            "estimate_covers", "k_rule_points", "warned"]
    rows = [{c: r[c] for c in cols} for r in rows]
    table(refrows, out / "speed_vs_accuracy_reference.csv",
          f"Reference: Abel at {REF_NODES} nodes, checked against Abel at {REF_CHECK_NODES} nodes "
          f"and FFT at tol {ref_tol:g} (scalar = max rel. error of a, x_c/a, d, p_max; base = "
          f"max |diff| / max |ref| of the base stresses)")
    table(rows, out / "speed_vs_accuracy.csv",
          f"Speed vs accuracy (median of {repeats} warm runs; errors against the reference)")
    table(winners, out / "speed_vs_accuracy_winners.csv",
          "Fastest run of each method reaching each target error")
    _summary(rows, winners)
    try:
        _plot(rows, out)
    except Exception as exc:  # a plot must never lose the table
        print(f"plot skipped: {exc}", file=sys.stderr)
    return 0


def _summary(rows, winners):
    print("Summary (times are medians of warm runs on this machine):")
    for name in SCENES:
        d = {r["sweep"]: r for r in rows if r["scene"] == name and r["param"] == "1e-04"}
        f, a, s = d["fft tol"], d["abel tol"], d["abel scalars only"]
        print(f"  {name}: defaults (tol 1e-4): fft {f['median_ms']:.1f} ms, scalar error "
              f"{f['err_scalar']:.1e}, base {f['err_base']:.1e} (N = {f['N_or_nodes']}); "
              f"abel {a['median_ms']:.1f} ms, scalar error {a['err_scalar']:.1e}, base "
              f"{a['err_base']:.1e} ({a['N_or_nodes']} nodes; {s['median_ms']:.1f} ms without "
              f"the base-stress profile)")
        for pool in ("tol-driven", "any"):
            for err in ("scalar", "base"):
                parts = []
                for w in winners:
                    if (w["scene"], w["runs"], w["error"]) != (name, pool, err):
                        continue
                    if w["winner"] == "none":
                        parts.append(f"<={w['target']:.0e}: none")
                    elif math.isnan(w["speedup"]):
                        parts.append(f"<={w['target']:.0e}: only {w['winner']} "
                                     f"{w[w['winner'] + '_ms']:.0f} ms")
                    else:
                        parts.append(f"<={w['target']:.0e}: {w['winner']} {w['speedup']:.1f}x "
                                     f"({w['fft_ms']:.0f} vs {w['abel_ms']:.0f} ms)")
                print(f"    {err} error, {pool} runs: " + "; ".join(parts))
    cov = [r for r in rows if r["sweep"] != "abel scalars only"]
    bad = [f"{r['scene']} {r['sweep']} {r['param']}" for r in cov if not r["estimate_covers"]]
    print(f"  error_estimate >= true scalar error (or both at roundoff, < 1e-13) in "
          f"{len(cov) - len(bad)}/{len(cov)} runs"
          + (f" (not: {', '.join(bad)})" if bad else ""))


def _plot(rows, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    style = {"fft tol": ("C0", "o-"), "fft fixed N": ("C0", "s--"), "abel nodes": ("C3", "^-"),
             "abel tol": ("C3", "v:"), "abel scalars only": ("C3", "D")}
    for name, scene in SCENES.items():
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.3))
        for ax, key, title in ((axes[0], "err_scalar", "a, x_c, d, p_max (max rel. error)"),
                               (axes[1], "err_base", "base stresses (max |diff| / max |ref|)")):
            for sweep, (color, fmt) in style.items():
                rs = [r for r in rows if r["scene"] == name and r["sweep"] == sweep]
                if not rs:
                    continue
                ax.loglog([r["median_ms"] for r in rs], [r[key] for r in rs], fmt, color=color,
                          ms=4, lw=1, label=sweep)
                if sweep in ("fft tol", "abel nodes", "fft fixed N"):
                    for r in rs:
                        ax.annotate(r["param"], (r["median_ms"], r[key]), fontsize=6,
                                    xytext=(3, 2), textcoords="offset points", color=color)
            for method, color in (("fft", "C0"), ("abel", "C3")):
                d = [r for r in rows if r["scene"] == name and r["method"] == method
                     and r["sweep"].endswith("tol") and r["param"] == "1e-04"]
                if d:
                    ax.loglog(d[0]["median_ms"], d[0][key], "*", color=color, ms=14, mec="k",
                              label=f"{method} default (tol 1e-4)")
            ax.set_xlabel("wall time per solve [ms] (median of warm runs)")
            ax.set_ylabel("error against the reference")
            ax.set_title(title, fontsize=9)
            ax.grid(True, which="major", alpha=0.3)
        axes[0].legend(fontsize=7)
        fig.suptitle(f"{name} scene: P_L = {scene.load:g} N/m, mu_d = {scene.mu:g} "
                     f"(reference: Abel {REF_NODES} nodes)", fontsize=10)
        fig.tight_layout()
        fig.savefig(out / f"speed_vs_accuracy_{name}.png", dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
