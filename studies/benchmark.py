"""Speed of the spectral solver: solve time and iterations against N, in FFT pairs.

    python -m studies.benchmark [--quick] [--out DIR]

For the paper's scene (P_L = 200 N/m, mu_d = 2): the automatic solve at tol 1e-4, then fixed
grids N = 2^12 ... 2^22 on the automatic period.  Each time is the median of >= 5 warm runs
(plans made beforehand, not timed); beside it, the median time of one pyfftw rfft/irfft pair of
the same N measured in the same process, so the cost reads as FFT pairs per solve.  Then the
start-up: wall time of fresh processes (median of 11) for the interpreter alone,
``import spectral_contact``, and ``spectral-contact solve`` until its summary is printed (the
first result a user sees; one run with --quick).  Writes benchmark.csv, benchmark_startup.csv
and benchmark.png.

Then the speed targets of issue 13 that the run measures, each printed against its limit, met
or not, and written to benchmark_targets.csv: the paper's scene at tol 1e-4 (time, and its true
error against the Abel method at tol 1e-10), the Abel method at tol 1e-8 (time), fixed grids
from 2^16 up in FFT-pair times (full run only), the error estimate on the verification sweep
of studies.error_estimate (never below the true error, median ratio; --quick: its 6-run version),
and >= 10x faster than the peers (frictionless, fixed grids 2^12, 2^14, 2^16 at equal pressure
accuracy; 2^12 with --quick; "not measured (peer not installed)" without them:
``studies.peers.benchmark_peers``, detail in benchmark_peers.csv).
Times are medians of >= 11 warm runs; the median CPU time is measured beside the wall time: a
wall/CPU ratio above 1.15 means the machine was busy, and the run says the figures must be
remade on a quiet machine.
"""
from __future__ import annotations

import subprocess
import sys
import time

import numpy as np

from spectral_contact import PAPER_SCENE, solve
from spectral_contact.numerics.contact import solve_contact
from spectral_contact.numerics.fft import get_rfft
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.indenters import Cylinder

from . import three_d_cost
from ._common import median_time, parse, progress, table
from .peers import benchmark_peers

TARGET_REPEATS = 11        # medians of >= 11 warm runs for the targets
TARGET_PAPER_MS = 3.0      # the paper's scene, FFT, tol 1e-4
TARGET_ABEL_MS = 10.0      # the Abel method, tol 1e-8
TARGET_FIXED_PAIRS = 80.0  # fixed grids, cold start, from 2^16 up: FFT-pair times per solve
TARGET_FIXED_MS = {20: 1000.0, 22: 6000.0}  # fixed grids 2^20 (about 1 s), 2^22 (< 6 s) [ms]
BUSY_RATIO = 1.15          # wall / CPU time above this: the machine was busy


def _median_time(fn, repeats: int) -> float:
    return median_time(fn, repeats, warm=True)  # warm: plans, caches


def wall_and_cpu(fn, repeats: int) -> tuple[float, float]:
    """Medians of the wall and CPU (process) times [s] of ``repeats`` warm calls of fn()."""
    fn()
    wall, cpu = [], []
    for _ in range(repeats):
        c, t = time.process_time(), time.perf_counter()
        fn()
        wall.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    return float(np.median(wall)), float(np.median(cpu))


def true_error(r, ref) -> float:
    """Largest relative error of (a, x_c, d, p_max) of ``r`` against ``ref`` (x_c relative to a),
    as the tolerance defines it."""
    a = ref.half_width
    return max(abs(r.half_width - a) / a, abs(r.center - ref.center) / a,
               abs(r.indentation - ref.indentation) / abs(ref.indentation),
               abs(r.max_pressure - ref.max_pressure) / ref.max_pressure)


def _target(name, measured, limit, unit, status=None):
    if status is None:
        status = "met" if measured <= limit else "not met"
    return {"target": name, "measured": measured, "limit": limit, "unit": unit, "status": status}


def targets(scene, rows: list[dict], out, quick: bool = False) -> list[dict]:
    """Issue 13's targets measured in this run, printed against their limits and written."""
    auto = rows[0]
    ref = solve(scene, method="abel", tol=1e-10)
    err = true_error(solve(scene, tol=1e-4), ref)
    abel_wall, abel_cpu = wall_and_cpu(lambda: solve(scene, method="abel", tol=1e-8),
                                       TARGET_REPEATS)
    big = [r_ for r_ in rows[1:] if r_["N"] >= 2**16]
    out_rows = [
        _target("paper scene, fft, tol 1e-4: solve time", auto["solve_ms"], TARGET_PAPER_MS, "ms"),
        _target("paper scene, fft, tol 1e-4: true error vs abel tol 1e-10", err, 1e-4, "relative"),
        _target("abel, tol 1e-8: solve time", 1e3 * abel_wall, TARGET_ABEL_MS, "ms"),
        _target("fixed grids >= 2^16, cold start: solve time",
                max(r_["solve_in_fft_pairs"] for r_ in big) if big else float("nan"),
                TARGET_FIXED_PAIRS, "FFT-pair times", None if big else "not measured (quick)"),
    ]
    for e, limit in TARGET_FIXED_MS.items():  # the absolute targets (full run)
        ms = [r_["solve_ms"] for r_ in rows[1:] if r_["N"] == 2**e]
        out_rows.append(_target(f"fixed grid 2^{e}, cold start: solve time", ms[0] if ms else
                                float("nan"), limit, "ms", None if ms else "not measured (quick)"))
    out_rows += three_d_cost.benchmark_targets(out, quick)  # issue 25: surfaces
    out_rows += estimate_targets(quick)
    out_rows += benchmark_peers(out, quick, TARGET_REPEATS)  # ">= 10x the peers" (studies/peers.py)
    table(out_rows, out / "benchmark_targets.csv",
          f"Issue 13 targets (medians of {TARGET_REPEATS} warm runs; FFT pair at N = {auto['N']}: "
          f"{auto['fft_pair_us']:.1f} us in this run)")
    ratio = max(auto["solve_ms"] / auto["solve_cpu_ms"], abel_wall / abel_cpu)
    print(f"wall / CPU time: {ratio:.2f} (abel tol 1e-8 CPU {1e3 * abel_cpu:.2f} ms, paper scene "
          f"CPU {auto['solve_cpu_ms']:.2f} ms)")
    if ratio > BUSY_RATIO:
        print(f"the machine was busy (wall/CPU {ratio:.2f} > {BUSY_RATIO}): rerun on a quiet "
              f"machine for the figures")
    return out_rows


def estimate_targets(quick: bool) -> list[dict]:
    """The error estimate against the true error on studies.error_estimate's verification sweep
    (a/h 0.05 ... 22, mu_d 0 ... 10, tol 1e-2 ... 1e-5, against the Abel method; --quick: its
    6-run version), in this process."""
    from argparse import Namespace

    from . import error_estimate

    rows = error_estimate.sweep_rows(Namespace(serial=True, quick=True, workers=None),
                                     error_estimate.QUICK if quick else error_estimate.FULL)
    s = error_estimate.summary(rows)
    tight = [r["ratio"] for r in rows if r["status"] == "ok" and r["tol"] <= 1e-4]
    where = f"verification sweep, {s['runs']} runs"
    out = [_target(f"error estimate below the true error ({where})", s["below"] + s["failed"], 0,
                   "runs (incl. failed)"),
           _target(f"true error / tol, largest ({where})", s["true_over_tol_max"], 1.0, "ratio"),
           _target(f"error estimate / true error, median ({where})", s["ratio_median"], 3.0,
                   "ratio")]
    if tight:
        out.append(_target(f"error estimate / true error, median at tol <= 1e-4 ({len(tight)} runs)",
                           float(np.median(tight)), 3.0, "ratio"))
    return out


def fft_pair_time(n: int, repeats: int = 21) -> float:
    f = get_rfft(n)
    a = np.random.default_rng(0).random(n)
    sym = np.ones(n // 2 + 1, complex)
    return _median_time(lambda: f.apply(a, sym), repeats)


STARTUP_CASES = (
    ("interpreter alone (python -c pass)", ["-c", "pass"]),
    ("import spectral_contact", ["-c", "import spectral_contact"]),
    ("spectral-contact solve (first result)", ["-m", "spectral_contact.cli.main", "solve"]),
)


def startup_times(repeats: int) -> list[dict]:
    """Wall time of fresh processes (one untimed run first: disk caches), median and minimum."""
    rows = []
    for label, argv in STARTUP_CASES:
        cmd = [sys.executable, *argv]
        subprocess.run(cmd, check=True, capture_output=True)
        ts = []
        for _ in range(repeats):
            t = time.perf_counter()
            subprocess.run(cmd, check=True, capture_output=True)
            ts.append(time.perf_counter() - t)
        rows.append({"case": label, "median_ms": 1e3 * float(np.median(ts)),
                     "min_ms": 1e3 * min(ts), "repeats": repeats})
    return rows


def plot(fixed: list[dict], path) -> None:
    """Time per solve and per FFT pair, and the finest grid's iterations, against N."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        N = np.array([r_["N"] for r_ in fixed], float)
        fig, ax = plt.subplots(1, 2, figsize=(9, 3.5))
        ax[0].loglog(N, [r_["solve_ms"] for r_ in fixed], "o-", label="solve (cold start)")
        ax[0].loglog(N, [r_["fft_pair_us"] / 1e3 for r_ in fixed], "s-", label="one FFT pair")
        ref = fixed[0]["solve_ms"] * N * np.log(N) / (N[0] * np.log(N[0]))
        ax[0].loglog(N, ref, "k:", label="N log N")
        ax[0].set_ylabel("wall time [ms] (median of warm runs)")
        ax[0].set_title("time per solve and per FFT pair", fontsize=9)
        ax[0].legend(fontsize=8)
        ax[1].semilogx(N, [r_["gmres_its"] for r_ in fixed], "o-", label="GMRES iterations")
        ax[1].semilogx(N, [r_["active_set_its"] for r_ in fixed], "s-", label="active-set iterations")
        ax[1].set_ylabel("iterations per solve")
        ax[1].set_title("iterations on the finest grid (from 2^14: after the nested start)", fontsize=9)
        ax[1].set_ylim(bottom=0)
        ax[1].legend(fontsize=8)
        for a in ax:  # grid sizes as 2^k
            a.set_xscale("log", base=2)
            a.set_xticks(N, [f"$2^{{{int(round(np.log2(n)))}}}$" for n in N])
            a.minorticks_off()
            a.set_xlabel("grid points N")
        fig.tight_layout()
        fig.savefig(path, dpi=110)
        plt.close(fig)
    except Exception as exc:  # a plot must never lose the table
        print(f"plot skipped: {exc}", file=sys.stderr)


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/benchmark")
    scene = PAPER_SCENE
    repeats = 5
    exps = range(12, 15) if args.quick else range(12, 23)
    rows = []
    t0 = time.perf_counter()
    # the automatic solve
    r = solve(scene, tol=1e-4)
    t_auto, cpu_auto = wall_and_cpu(lambda: solve(scene, tol=1e-4), TARGET_REPEATS)
    pair = fft_pair_time(r.grid_points)
    rows.append({"case": "auto tol=1e-4", "N": r.grid_points, "solve_ms": 1e3 * t_auto,
                 "solve_cpu_ms": 1e3 * cpu_auto,
                 "fft_pair_us": 1e6 * pair, "fft_pairs": r.info["fft_pairs"],
                 "solve_in_fft_pairs": t_auto / pair, "active_set_its": r.iterations,
                 "gmres_its": r.info["final_level_krylov_iterations"],
                 "error_estimate": r.error_estimate})
    L = r.domain_length
    grid_center = r.center
    indenter = [Cylinder(0.0, scene.P)]
    for i, e in enumerate(exps, 1):
        n = 2**e
        g = Grid.centered(n, L, grid_center)
        sol = solve_contact(g, scene.mu, indenter)  # cold start from the Hertz guess
        reps = repeats if e <= 18 else 3
        t = _median_time(lambda: solve_contact(g, scene.mu, indenter), reps)
        pair = fft_pair_time(n, 11 if e <= 18 else 5)
        rows.append({"case": f"fixed N=2^{e}", "N": n, "solve_ms": 1e3 * t, "solve_cpu_ms": float("nan"),
                     "fft_pair_us": 1e6 * pair, "fft_pairs": sol.fft_pairs,
                     "solve_in_fft_pairs": t / pair, "active_set_its": sol.iterations,
                     "gmres_its": sol.krylov_iterations, "error_estimate": float("nan")})
        progress(i, len(exps), f"N = 2^{e}: {1e3 * t:.1f} ms", t0)
    table(rows, out / "benchmark.csv",
          f"Paper scene (P_L = {scene.load:g} N/m, mu_d = {scene.mu:g}), period {L:.2f} h; "
          f"medians of warm runs")
    table(startup_times(1 if args.quick else 11), out / "benchmark_startup.csv",
          "Start-up: wall time of fresh processes [ms] (quote only from a quiet machine)")
    base = rows[1]
    last = rows[-1]
    print(f"GMRES iterations at N = {last['N']}: {last['gmres_its']} vs {base['gmres_its']} at "
          f"N = {base['N']} (ratio {last['gmres_its'] / base['gmres_its']:.2f}); "
          f"active-set iterations {last['active_set_its']} vs {base['active_set_its']}")
    targets(scene, rows, out, args.quick)
    plot(rows[1:], out / "benchmark.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
