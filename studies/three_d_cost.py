"""Cost of the 3D solver: time, iterations and memory against grid size, in FFT pairs.

    python -m studies.three_d_cost [--quick] [--out DIR]

The sliding sphere of the speed target (F = 1 N, R = 130 mm on the paper's film: a ~ 1.3 h,
mu = 1).  (1) The automatic solve at tol 1e-3 (warm: plans made); (2) fixed grids 128^2 ...
2048^2 on the automatic solve's periods, each solve cold (from the Hertz guess), timed as the
median of warm runs, with one FFT pair (rfft2 + irfft2 with a symbol) of the same shape timed in
the same process, the active-set and GMRES iterations and the peak memory (tracemalloc) of one
solve.  Then (issue 25) the public ``solve`` on fixed grids 256^2 ... 2048^2 (30 mm period, as
the speed target states it), timed the same way (rows "solve(), fixed grid").  Writes
three_d_cost.csv and three_d_cost.png.  The peers on surfaces are studies.peers' case E.

``benchmark_targets`` is what studies.benchmark runs for issue 25: the public solve at 512^2,
1024^2, 2048^2 (<= 70 FFT-pair times of its grid), the finest grid's GMRES iterations and
active-set steps flat in N, the paper's finite cylinder at its default tol (<= 60 pair times
of 1024^2), one 4096^2 solve in a fresh process (its time and peak RSS) and the surface peers
at 1024^2 (studies.peers.surface_comparison; >= 5x tamaas with the same symbol).
"""
from __future__ import annotations

import sys
import time
import tracemalloc

import numpy as np

from spectral_contact import solve
from spectral_contact.numerics.contact import solve_contact
from spectral_contact.numerics.fft import get_rfft
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.indenters import Sphere

from ._common import median_time, parse, progress, table

SCENE = dict(indenter="sphere", force=1.0, mu=1.0, young=2.2e6, radius=0.130, thickness=0.002)


def fft_pair_time(shape, repeats: int = 11) -> float:
    f = get_rfft(shape)
    a = np.random.default_rng(0).random(shape)
    sym = np.ones(shape[:-1] + (shape[-1] // 2 + 1,), complex)
    return median_time(lambda: f.apply(a, sym), repeats, warm=True)


def _peers_note() -> str:
    missing = []
    for name in ("tamaas", "ContactMechanics"):
        try:
            __import__(name)
        except ImportError:
            missing.append(name)
    return ("peers not installed: " + ", ".join(missing)) if missing else "peers installed"


# --- issue 25: the public solve on fixed grids, the finite cylinder, 4096^2 (benchmark targets) --
SLIDING = dict(indenter="sphere", force=1.0, mu=1.0, domain_length=0.03)  # 30 mm period
TARGET_PAIRS = 70.0      # fixed-grid sliding sphere through solve(): FFT-pair times of its grid
TARGET_CYLINDER = 60.0   # the paper's finite cylinder at its default tol: pair times of 1024^2
TARGET_FLAT_GMRES = 1.5  # finest-grid GMRES iterations: largest N over smallest N, at most (the
# ratio issue 10 set; measured 17, 17, 18, 19 at 256^2 ... 2048^2 with the release look-ahead,
# numerics.contact._released_tensile; 24 at 2048^2 before it: a third active-set step of 5
# GMRES iterations for 2 nodes that the first step's release turned tensile)
TARGET_FLAT_STEPS = 1    # and finest-grid active-set steps
BIG_N = 4096


def _pair_shape_time(shape, repeats: int = 7) -> float:
    return fft_pair_time(tuple(shape), repeats)


def interleaved(fn, shape, repeats: int) -> tuple[float, float, float, object]:
    """Medians of ``repeats`` warm calls of fn() and of one FFT pair of ``shape`` timed between
    them (interleaved: both see the same load), the median CPU time of fn, and its last result."""
    res = fn()
    f = get_rfft(tuple(shape))
    a = np.random.default_rng(0).random(tuple(shape))
    sym = np.ones(tuple(shape)[:-1] + (shape[-1] // 2 + 1,), complex)
    f.apply(a, sym)
    ts, cs, ps = [], [], []
    for _ in range(repeats):
        for _ in range(3):
            t = time.perf_counter()
            f.apply(a, sym)
            ps.append(time.perf_counter() - t)
        c, t = time.process_time(), time.perf_counter()
        res = fn()
        ts.append(time.perf_counter() - t)
        cs.append(time.process_time() - c)
    return float(np.median(ts)), float(np.median(ps)), float(np.median(cs)), res


def public_fixed_rows(ns, repeats: int) -> list[dict]:
    """The fixed-grid sliding sphere (mu 1, 1 N, 30 mm period) through the public ``solve`` at
    each N x N: median wall time over the median FFT pair of the same grid (interleaved), the
    whole solve's FFT pairs and the finest grid's own active-set steps and GMRES iterations."""
    rows = []
    for n in ns:
        t, pair, cpu, r = interleaved(lambda n=n: solve(grid_points=n, **SLIDING), (n, n),
                                      repeats if n <= 1024 else max(1, repeats // 2))
        rows.append({"case": "solve(), fixed grid, sliding sphere", "nx": n, "ny": n,
                     "solve_s": t, "solve_cpu_s": cpu, "fft_pair_ms": 1e3 * pair,
                     "solve_in_fft_pairs": t / pair, "fft_pairs": r.counters["transforms"],
                     "active_set_its": r.info["final_level_active_set_iterations"],
                     "gmres_its": r.info["final_level_krylov_iterations"],
                     "final_level_fft_pairs": r.info["final_level_fft_pairs"],
                     "all_active_set_its": r.counters["iterations"],
                     "all_gmres_its": r.counters["linear_iterations"],
                     "error_estimate": r.error_estimate})
    return rows


def phases(n: int, repeats: int = 3, log=print) -> dict:
    """Where the public fixed-grid solve of the sliding sphere (SLIDING, n x n) spends its time:
    the contact solve of each grid, the output fields, the nested first sets, the contact
    measures and the rest, in FFT-pair times of n x n (the solve's median of ``repeats`` warm
    runs interleaved with the pair; each phase's time from the last run).  Times the phases by
    wrapping those functions for the duration of the call (restored after)."""
    import spectral_contact.numerics.contact as contact_mod
    import spectral_contact.solvers.fft3d as fft3d_mod

    acc: dict = {}
    saved = []

    def wrap(mod, name, key):
        orig = getattr(mod, name)
        saved.append((mod, name, orig))

        def timed(*a, **k):
            t = time.perf_counter()
            out = orig(*a, **k)
            label = key(out) if callable(key) else key
            acc[label] = acc.get(label, 0.0) + time.perf_counter() - t
            return out
        setattr(mod, name, timed)

    wrap(contact_mod, "solve_complementarity",
         lambda out: f"contact solve {out.grid.shape[0]}^2 ({out.fft_pairs} FFT pairs)")
    wrap(fft3d_mod, "_output_fields", "output fields")
    wrap(fft3d_mod, "_measure", "contact measures")
    wrap(fft3d_mod, "nested_guess", "nested first set of the finest grid")
    wrap(contact_mod, "nested_guess", "nested first sets of the chain")
    try:
        solve(grid_points=n, **SLIDING)
        f = get_rfft((n, n))
        a = np.random.default_rng(0).random((n, n))
        sym = np.ones((n, n // 2 + 1), complex)
        totals, pairs = [], []
        for _ in range(repeats):
            acc.clear()
            for _ in range(3):
                t = time.perf_counter()
                f.apply(a, sym)
                pairs.append(time.perf_counter() - t)
            t = time.perf_counter()
            r = solve(grid_points=n, **SLIDING)
            totals.append(time.perf_counter() - t)
    finally:
        for mod, name, orig in saved:
            setattr(mod, name, orig)
    pair = float(np.median(pairs))
    out = {k: v / pair for k, v in acc.items()}
    out["rest"] = (totals[-1] - sum(acc.values())) / pair
    out["whole solve (median)"] = float(np.median(totals)) / pair
    if log:
        log(f"{n}^2: {out['whole solve (median)']:.1f} FFT-pair times, {r.counters['transforms']} "
            "FFT pairs; " + "; ".join(f"{k} {v:.1f}" for k, v in out.items()
                                     if k != "whole solve (median)"))
    return out


def cylinder_row(repeats: int) -> dict:
    """The paper's finite cylinder (its default scene) at its default tol, timed against one
    FFT pair of 1024^2 (the issue's unit), interleaved."""
    t, pair, cpu, r = interleaved(lambda: solve(indenter="cylinder"), (1024, 1024), repeats)
    return {"case": "solve(), finite cylinder, default tol", "nx": r.grid_points[0],
            "ny": r.grid_points[1], "solve_s": t, "solve_cpu_s": cpu, "fft_pair_ms": 1e3 * pair,
            "solve_in_fft_pairs": t / pair, "fft_pairs": r.counters["transforms"],
            "active_set_its": r.info["final_level_active_set_iterations"],
            "gmres_its": r.info["final_level_krylov_iterations"],
            "final_level_fft_pairs": r.info["final_level_fft_pairs"],
            "all_active_set_its": r.counters["iterations"],
            "all_gmres_its": r.counters["linear_iterations"], "error_estimate": r.error_estimate}


_BIG = """
import json, resource, time
from spectral_contact import solve
kw = dict(grid_points={n}, indenter="sphere", force=1.0, mu=1.0, domain_length=0.03)
t = time.perf_counter(); r = solve(**kw); dt = time.perf_counter() - t
print(json.dumps({{"solve_s": dt, "plan_s": r.plan_time_s, "fft_pairs": r.counters["transforms"],
    "active_set_its": r.info["final_level_active_set_iterations"],
    "gmres_its": r.info["final_level_krylov_iterations"],
    "peak_rss_GB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20}}))
"""


def big_row(n: int = BIG_N) -> dict:
    """One cold solve of the sliding sphere on n x n in a fresh process (its own peak RSS,
    ``resource.getrusage``; plans included in the process, not in solve_s)."""
    import json
    import os
    import subprocess

    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", _BIG.format(n=n)], capture_output=True, text=True,
                         env=env, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1]) | {"nx": n, "ny": n}


def benchmark_targets(out, quick: bool = False) -> list[dict]:
    """Issue 25's targets in studies.benchmark's format (target, measured, limit, unit, status),
    the measured rows written to benchmark_3d.csv in ``out``.  Quick: 256^2 and 512^2 only."""
    ns = (256, 512) if quick else (512, 1024, 2048)
    rows = public_fixed_rows(ns, 3 if quick else 5)
    cyl = None if quick else cylinder_row(3)
    big = None if quick else big_row()
    table(rows + ([cyl] if cyl else []), out / "benchmark_3d.csv",
          "Issue 25: the public solve on fixed grids (sliding sphere mu 1, 1 N, 30 mm period) and "
          "the finite cylinder at its default tol; medians of warm runs interleaved with one FFT "
          "pair (cylinder: of 1024^2)")

    def target(name, measured, limit, unit, status=None):
        if status is None:
            status = "met" if measured <= limit else "not met"
        return {"target": name, "measured": measured, "limit": limit, "unit": unit,
                "status": status}

    t = [target(f"3D fixed grid {r['nx']}^2, sliding sphere through solve(): solve time",
                r["solve_in_fft_pairs"], TARGET_PAIRS, "FFT-pair times") for r in rows
         if r["nx"] >= 512]  # (the grids; 256^2 is in the CSV)
    first, last = rows[0], rows[-1]
    t.append(target(f"3D finest-grid GMRES iterations, {last['nx']}^2 over {first['nx']}^2",
                    last["gmres_its"] / first["gmres_its"], TARGET_FLAT_GMRES, "ratio"))
    t.append(target(f"3D finest-grid active-set steps, {last['nx']}^2 minus {first['nx']}^2",
                    last["active_set_its"] - first["active_set_its"], TARGET_FLAT_STEPS, "steps"))
    t.append(target("3D finite cylinder, default tol: solve time", cyl["solve_in_fft_pairs"]
                    if cyl else float("nan"), TARGET_CYLINDER, "FFT-pair times of 1024^2",
                    None if cyl else "not measured (quick)"))
    if big:
        from spectral_contact.solvers.fft3d import _available_memory

        t.append(target(f"3D fixed grid {BIG_N}^2: peak memory (solve {big['solve_s']:.1f} s; "
                        f"{big['fft_pairs']} FFT pairs)", big["peak_rss_GB"],
                        _available_memory() / 2**30, "GB (limit: available now)"))
    else:
        t.append(target(f"3D fixed grid {BIG_N}^2: peak memory", float("nan"), float("nan"), "GB",
                        "not measured (quick)"))
    if not quick:
        from .peers import surface_comparison, surface_targets

        peers = surface_comparison((10,), repeats=3, operators=("film",))
        table(peers, out / "benchmark_peers_surface.csv",
              "Issue 25: frictionless sphere, film operator, 1024^2, each solver at the loosest "
              "tolerance giving p within 1e-6 p_max of ours at rtol 1e-13; medians of 3 "
              "interleaved warm runs")
        t += surface_targets(peers)
    return t


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/three_d_cost")
    exps = (7, 8) if args.quick else (7, 8, 9, 10, 11)
    repeats = 3 if args.quick else 5
    t0 = time.perf_counter()
    rows = []
    auto = solve(tol=1e-3, **SCENE)
    t_auto = median_time(lambda: solve(tol=1e-3, **SCENE), repeats, warm=False)
    n_auto = auto.grid_points
    pair_auto = fft_pair_time(tuple(n_auto))
    rows.append({"case": "auto tol=1e-3", "nx": n_auto[0], "ny": n_auto[1],
                 "solve_s": t_auto, "fft_pair_ms": 1e3 * pair_auto,
                 "solve_in_fft_pairs": t_auto / pair_auto,
                 "fft_pairs": auto.counters["transforms"],
                 "active_set_its": auto.counters["iterations"],
                 "gmres_its": auto.counters["linear_iterations"], "coarse_active_set_its": 0,
                 "coarse_gmres_its": 0, "peak_MB": float("nan"),
                 "error_estimate": auto.error_estimate})
    L = auto.domain_length
    center = (0.5 * (auto.measures["x_min"] + auto.measures["x_max"]), 0.0)
    ind = [Sphere(0.0, auto.scene.P)]
    for i, e in enumerate(exps, 1):
        n = 2**e
        progress(i, len(exps), f"{n} x {n}", t0)
        g = Grid.centered((n, n), L, center)
        tracemalloc.start()
        sol = solve_contact(g, SCENE["mu"], ind)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        t = median_time(lambda g=g: solve_contact(g, SCENE["mu"], ind), repeats, warm=False)
        pair = fft_pair_time((n, n))
        rows.append({"case": "fixed, no guess", "nx": n, "ny": n, "solve_s": t,
                     "fft_pair_ms": 1e3 * pair, "solve_in_fft_pairs": t / pair,
                     "fft_pairs": sol.fft_pairs, "active_set_its": sol.iterations,
                     "gmres_its": sol.krylov_iterations,
                     "coarse_active_set_its": sol.coarse_iterations,
                     "coarse_gmres_its": sol.coarse_krylov_iterations, "peak_MB": peak / 2**20,
                     "error_estimate": float("nan")})
    for r in public_fixed_rows((256, 512) if args.quick else (256, 512, 1024, 2048), repeats):
        rows.append({k: r.get(k, float("nan")) for k in rows[0]} | {"case": r["case"]})
    table(rows, out / "three_d_cost.csv",
          f"3D cost, sliding sphere a ~ 1.3 h, mu = 1 (medians of {repeats} runs; {_peers_note()})")
    fixed = [r for r in rows if r["case"].startswith("fixed, no guess")]
    base = fixed[0]
    for r in fixed:
        r["its_ratio"] = r["gmres_its"] / base["gmres_its"]
    print("GMRES iterations relative to 128^2: " +
          ", ".join(f"{r['nx']}^2: {r['its_ratio']:.2f}" for r in fixed))
    _plot(fixed, out / "three_d_cost.png")
    return 0


def _plot(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = [r["nx"] for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    axes[0].loglog(n, [r["solve_s"] for r in rows], "o-", label="solve (no first guess)")
    axes[0].loglog(n, [r["fft_pair_ms"] / 1e3 for r in rows], "s--", label="one FFT pair")
    axes[0].set_ylabel("wall time [s]")
    axes[0].legend(fontsize=8)
    axes[1].semilogx(n, [r["gmres_its"] for r in rows], "o-", label="GMRES iterations (finest grid)")
    axes[1].semilogx(n, [r["active_set_its"] for r in rows], "s-", label="active-set iterations (finest)")
    axes[1].semilogx(n, [r["coarse_gmres_its"] for r in rows], "^:", label="GMRES on the coarser grids")
    axes[1].set_ylabel("iterations")
    axes[1].legend(fontsize=8)
    for ax in axes:
        ax.set_xscale("log", base=2)
        ax.set_xlabel("grid points per axis (N x N)")
        ax.grid(alpha=0.3)
    fig.suptitle("3D solver cost: sliding sphere, a ~ 1.3 h, mu = 1", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
