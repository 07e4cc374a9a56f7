"""Long domains: cost against N up to 2^22, FFT planning, and trains of many cylinders.

    python -m studies.large_domain [--quick] [--out DIR]

1. Cost against N (paper scene: P = Scene().P, mu_d = 2).  The grid spacing is fixed
   (dx = h/64, 159 points across the contact) and the period grows with N (L = N dx, 16 h to
   65536 h): the contact, its resolution and the solution are the same at every N (images are
   below 1e-9 from N = 2^11 on), so the growth in time and memory is the cost of the domain
   alone, which is what a long domain with many contacts pays.  (Refining a fixed period is
   studies/benchmark.)  Cold start from the Hertz guess, FFTW_ESTIMATE plans made beforehand;
   the first solve (which also builds the film's symbols) is run under tracemalloc for the peak
   of memory allocated through Python/numpy (FFTW's own plan memory is not seen: ru_maxrss
   is given beside it), later solves untraced for the time.
2. FFT planning, shown apart: plan time and the time of one rfft/irfft pair with FFTW_ESTIMATE
   and with FFTW_MEASURE (wisdom forgotten before each), the MEASURE re-plan from wisdom, and the
   warm solve time with measured plans (minima over interleaved repeats).  The wisdom file
   goes to DIR, not ~/.cache.
3. Many cylinders on one domain (mu_d = 2, dx = h/32, apexes on nodes):
   a. a finite train of M equal cylinders (paper's load each) at apex spacing s, 30 h of free film
      beyond each end: contact width of every cylinder against its isolated value, and the
      middle one against the infinite periodic train (one cylinder on period s);
   b. M = 4 ... 64 at s = 6 h: iterations and time per cylinder;
   c. unequal cylinders (curvature c_i = R/R_i, own loads), widely (25 h) and closely (6 h)
      spaced, against each one's isolated solve (and the isolated solve of the front door
      solve(Scene(radius=R/c_i, load=...)) as a check of the curvature scaling).

Writes large_domain_cost.csv, large_domain_planning.csv, large_domain_train.csv,
large_domain_train_size.csv, large_domain_unequal.csv and large_domain.png.
"""
from __future__ import annotations

import math
import resource
import sys
import time
import tracemalloc

import numpy as np
import pyfftw

from spectral_contact import ConvergenceError, Scene, solve
from spectral_contact.numerics import fft as fftmod
from spectral_contact.numerics.contact import solve_contact
from spectral_contact.numerics.edges import fit_edges
from spectral_contact.numerics.fft import RealFFT, get_rfft
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.film import DECAY_RATE
from spectral_contact.physics.indenters import Cylinder

from ._common import median_time, parse, progress, table
from .stability import short

NAN = float("nan")
MU = 2.0


def _rss_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: KiB


def _median_time(fn, repeats: int) -> float:
    return median_time(fn, repeats)


def pair_time(f, n: int, repeats: int) -> float:
    a = np.random.default_rng(0).random(n)
    sym = np.ones(n // 2 + 1, complex)
    f.apply(a, sym)
    return _median_time(lambda: f.apply(a, sym), repeats)


def windows(sol):
    """(a, x_c relative to the apex) of each indenter's contact, in indenter order."""
    edges = fit_edges(sol.grid.x, sol.grid.dx, sol.gap, sol.pressure, sol.active)
    out = []
    for left, right in edges:
        mid = 0.5 * (left + right)
        out.append((mid, 0.5 * (right - left)))
    return out


def per_indenter(sol, indenters):
    """a_i, x_c,i - apex_i and d_i of each indenter (runs matched to the nearest apex)."""
    apex = np.array([ind.apex for ind in indenters])
    a = np.full(len(indenters), NAN)
    c = np.full(len(indenters), NAN)
    for mid, half in windows(sol):
        L = sol.grid.length
        rel = (mid - apex + 0.5 * L) % L - 0.5 * L
        m = int(np.argmin(np.abs(rel)))
        if not np.isnan(a[m]):  # two runs on one indenter: keep the envelope
            lo = min(c[m] + apex[m] - a[m], mid - half)
            hi = max(c[m] + apex[m] + a[m], mid + half)
            a[m], c[m] = 0.5 * (hi - lo), 0.5 * (hi + lo) - apex[m]
        else:
            a[m], c[m] = half, rel[m]
    return a, c, np.asarray(sol.indentations, float)


# --- 1. cost against N ---------------------------------------------------------------------------
def cost_sweep(scene, exps, t0):
    dx = 1.0 / 64
    ind = [Cylinder(0.0, scene.P)]
    rows = []
    for i, e in enumerate(exps, 1):
        n = 2**e
        g = Grid.centered(n, n * dx, 0.0)  # a node on the apex at every N
        f = get_rfft(n)  # plan (FFTW_ESTIMATE), not timed in the solve
        pair = pair_time(f, n, 11 if e <= 18 else 3)
        tracemalloc.start()
        t = time.perf_counter()
        sol = solve_contact(g, MU, ind)
        first = time.perf_counter() - t
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        reps = 3 if e <= 16 else 1
        warm = _median_time(lambda: solve_contact(g, MU, ind), reps)
        (_, a), = windows(sol)
        rows.append({"N": n, "L": n * dx, "plan_ms": 1e3 * f.plan_time_s,
                     "first_solve_s": first, "solve_s": warm, "fft_pair_ms": 1e3 * pair,
                     "fft_pairs": sol.fft_pairs, "solve_in_fft_pairs": warm / pair,
                     "active_set_its": sol.iterations, "gmres_its": sol.krylov_iterations,
                     "peak_MiB": peak / 2**20, "peak_bytes_per_point": peak / n,
                     "maxrss_MiB": _rss_mib(), "a": a})
        progress(i, len(exps), f"N = 2^{e}: {warm:.3f} s, peak {peak / 2**20:.0f} MiB", t0)
    a_last = rows[-1]["a"]
    for r in rows:
        r["a_minus_a_last"] = abs(r["a"] - a_last)
    return rows


# --- 2. planning ---------------------------------------------------------------------------------
def _min_times(fns, rounds: int, inner: int):
    """Minimum time of each callable over interleaved rounds (robust to a shared machine)."""
    best = [float("inf")] * len(fns)
    for _ in range(rounds):
        for j, fn in enumerate(fns):
            for _ in range(inner):
                t = time.perf_counter()
                fn()
                best[j] = min(best[j], time.perf_counter() - t)
    return best


def planning_sweep(scene, exps, out, t0):
    """ESTIMATE vs MEASURE: plan times, transform times and warm solve times (minimum over
    interleaved repeats: the machine may be shared, and the minimum is the least disturbed)."""
    dx = 1.0 / 64
    ind = [Cylinder(0.0, scene.P)]
    saved = fftmod.WISDOM_FILE
    fftmod.WISDOM_FILE = out / "fftw_wisdom"  # keep the user's wisdom untouched
    rows = []

    def use(effort, wisdom, n):
        """Make the solver's cached plan for n with this effort (wisdom only for MEASURE: an
        ESTIMATE plan would pick measured plans up from wisdom)."""
        pyfftw.forget_wisdom()
        if wisdom is not None:
            pyfftw.import_wisdom(wisdom)
        fftmod.set_planner_effort(effort)
        fftmod.clear_plans()
        get_rfft(n)

    try:
        for i, e in enumerate(exps, 1):
            n = 2**e
            inner = 5 if e <= 16 else 2
            pyfftw.forget_wisdom()
            fe = RealFFT(n, "FFTW_ESTIMATE")
            pyfftw.forget_wisdom()
            fm = RealFFT(n, "FFTW_MEASURE")
            wisdom = pyfftw.export_wisdom()
            pyfftw.forget_wisdom()
            pyfftw.import_wisdom(wisdom)
            fw = RealFFT(n, "FFTW_MEASURE")
            a = np.random.default_rng(0).random(n)
            sym = np.ones(n // 2 + 1, complex)
            pe, pm = _min_times([lambda: fe.apply(a, sym), lambda: fm.apply(a, sym)], 3, 3 * inner)
            # the solver with its default plans and with measured plans (from the wisdom above)
            g = Grid.centered(n, n * dx, 0.0)
            s_est = s_meas = float("inf")
            for _ in range(3):
                use("FFTW_ESTIMATE", None, n)
                s_est = min(s_est, *_min_times([lambda: solve_contact(g, MU, ind)], 1, inner))
                use("FFTW_MEASURE", wisdom, n)
                s_meas = min(s_meas, *_min_times([lambda: solve_contact(g, MU, ind)], 1, inner))
            saved_per_solve = s_est - s_meas
            rows.append({"N": n, "estimate_plan_ms": 1e3 * fe.plan_time_s,
                         "measure_plan_s": fm.plan_time_s,
                         "wisdom_replan_ms": 1e3 * fw.plan_time_s,
                         "estimate_pair_us": 1e6 * pe, "measure_pair_us": 1e6 * pm,
                         "pair_speedup": pe / pm, "solve_estimate_ms": 1e3 * s_est,
                         "solve_measure_ms": 1e3 * s_meas, "solve_speedup": s_est / s_meas,
                         "break_even_solves": (fm.plan_time_s / saved_per_solve
                                               if saved_per_solve > 0 else NAN)})
            progress(i, len(exps), f"planning N = 2^{e}: MEASURE {fm.plan_time_s:.2f} s", t0)
    finally:
        fftmod.set_planner_effort("FFTW_ESTIMATE")
        fftmod.clear_plans()
        pyfftw.forget_wisdom()
        fftmod.WISDOM_FILE = saved
    return rows


# --- 3. trains -----------------------------------------------------------------------------------
DX_TRAIN = 1.0 / 32
FREE = 30.0  # free film beyond each end of a train [h]


def _train_grid(span: float) -> Grid:
    n = 1 << math.ceil(math.log2((span + 2 * FREE) / DX_TRAIN))
    return Grid.centered(n, n * DX_TRAIN, 0.0)


def isolated(P, curvature=1.0):
    g = Grid.centered(2048, 2048 * DX_TRAIN, 0.0)  # 64 h
    ind = [Cylinder(0.0, P, curvature)]
    sol = solve_contact(g, MU, ind)
    dt = _median_time(lambda: solve_contact(g, MU, ind), 3)  # warm
    a, c, d = per_indenter(sol, ind)
    return {"a": a[0], "c": c[0], "d": d[0], "time_s": dt, "its": sol.iterations,
            "gmres": sol.krylov_iterations}


def periodic_cell(P, s):
    """One cylinder on period s: the infinite periodic train."""
    n = round(s / DX_TRAIN)
    sol = solve_contact(Grid.centered(n, n * DX_TRAIN, 0.0), MU, [Cylinder(0.0, P)])
    a, c, d = per_indenter(sol, [Cylinder(0.0, P)])
    return a[0], d[0]


def train_sweep(scene, M, spacings, t0):
    P = scene.P
    iso = isolated(P)
    rows, profiles = [], {}
    for i, s in enumerate(spacings, 1):
        inds = [Cylinder((k - M // 2) * s, P) for k in range(M)]
        g = _train_grid((M - 1) * s)
        row = {"M": M, "spacing": s, "gap_iso": s - 2 * iso["a"], "N": g.n, "L": g.length,
               "status": "ok"}
        try:
            t = time.perf_counter()
            sol = solve_contact(g, MU, inds)
            dt = time.perf_counter() - t
            a, c, d = per_indenter(sol, inds)
            a_per, d_per = periodic_cell(P, s)
            mid = M // 2
            row.update({"its": sol.iterations, "gmres": sol.krylov_iterations, "time_s": dt,
                        "time_per_cyl_s": dt / M, "iso_time_s": iso["time_s"],
                        "a_first_rel": a[0] / iso["a"] - 1, "a_mid_rel": a[mid] / iso["a"] - 1,
                        "a_last_rel": a[-1] / iso["a"] - 1,
                        "a_periodic_rel": a_per / iso["a"] - 1,
                        "mid_vs_periodic": a[mid] / a_per - 1,
                        "xc_mid_shift": c[mid] - iso["c"],
                        "d_first_rel": d[0] / iso["d"] - 1, "d_mid_rel": d[mid] / iso["d"] - 1,
                        "d_last_rel": d[-1] / iso["d"] - 1,
                        "predicted": math.exp(-DECAY_RATE * (s - 2 * iso["a"]))})
            profiles[s] = a / iso["a"] - 1
        except (ConvergenceError, ValueError) as exc:
            row["status"] = short(exc)
        rows.append(row)
        progress(i, len(spacings), f"train of {M}, spacing {s:g} h", t0)
    return rows, profiles, iso


def periodic_check(scene, M, s):
    """M equal cylinders on period M s must reproduce one cylinder on period s exactly."""
    P = scene.P
    n = round(s / DX_TRAIN)
    inds = [Cylinder((k - M // 2) * s, P) for k in range(M)]
    sol = solve_contact(Grid.centered(M * n, M * n * DX_TRAIN, 0.0), MU, inds)
    a, _, d = per_indenter(sol, inds)
    a1, d1 = periodic_cell(P, s)
    return float(np.max(np.abs(a - a1))), float(np.max(np.abs(d - d1)))


def train_size_sweep(scene, Ms, s, t0):
    P = scene.P
    iso = isolated(P)
    rows = []
    for i, M in enumerate(Ms, 1):
        inds = [Cylinder((k - M // 2) * s, P) for k in range(M)]
        g = _train_grid((M - 1) * s)
        sol = solve_contact(g, MU, inds)  # warms plans and symbols
        dt = _median_time(lambda: solve_contact(g, MU, inds), 3)
        rows.append({"M": M, "spacing": s, "N": g.n, "L": g.length, "its": sol.iterations,
                     "gmres": sol.krylov_iterations, "fft_pairs": sol.fft_pairs, "time_s": dt,
                     "time_per_cyl_ms": 1e3 * dt / M, "isolated_ms": 1e3 * iso["time_s"],
                     "isolated_gmres": iso["gmres"]})
        progress(i, len(Ms), f"train size M = {M}", t0)
    return rows


def unequal_sweep(scene, curv, loads_rel, spacings, t0):
    P = scene.P
    M = len(curv)
    rows = []
    isos = [isolated(P * lr, c) for c, lr in zip(curv, loads_rel)]
    for k, (c, lr) in enumerate(zip(curv, loads_rel)):
        # the front door's isolated solve of the same cylinder: radius R/c, own load
        sc = scene.with_(radius=scene.radius / c,
                         load=P * lr * scene.young * scene.thickness**2 / (6 * scene.radius))
        r = solve(sc, tol=1e-5)
        rows.append({"cyl": k, "curvature": c, "R_mm": 1e3 * sc.radius, "load_rel": lr,
                     "P": P * lr, "a_iso": isos[k]["a"], "a_front_door": r.half_width,
                     "iso_vs_front_door": isos[k]["a"] / r.half_width - 1})
    profiles, times = {}, {}
    for j, s in enumerate(spacings, 1):
        inds = [Cylinder((k - M // 2) * s, P * lr, c) for k, (c, lr) in
                enumerate(zip(curv, loads_rel))]
        g = _train_grid((M - 1) * s)
        try:
            t = time.perf_counter()
            sol = solve_contact(g, MU, inds)
            dt = time.perf_counter() - t
            a, cc, d = per_indenter(sol, inds)
            for k in range(M):
                rows[k][f"a_rel_s{s:g}"] = a[k] / isos[k]["a"] - 1
                rows[k][f"d_rel_s{s:g}"] = d[k] / isos[k]["d"] - 1
            times[s] = (dt, g.n)
            profiles[s] = (sol.grid.x, sol.pressure)
        except (ConvergenceError, ValueError) as exc:
            for k in range(M):
                rows[k][f"a_rel_s{s:g}"] = NAN
                rows[k][f"d_rel_s{s:g}"] = NAN
            print(f"unequal train at spacing {s}: {exc}", file=sys.stderr)
        progress(j, len(spacings), f"unequal train, spacing {s:g} h", t0)
    return rows, profiles, times, sum(i["time_s"] for i in isos)


# --- figure --------------------------------------------------------------------------------------
def plot(path, cost, plan, train, tprof, tsize, uneq, uprof):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 4, figsize=(19, 8.5))
    N = np.array([r["N"] for r in cost], float)
    a = ax[0, 0]
    a.loglog(N, [r["solve_s"] for r in cost], "o-", ms=3, label="solve (warm, cold start)")
    a.loglog(N, [r["first_solve_s"] for r in cost], "s-", ms=3,
             label="first solve (+ symbols, traced)")
    a.loglog(N, [1e-3 * r["fft_pair_ms"] for r in cost], "^-", ms=3, label="one FFT pair")
    a.loglog(N, [1e-3 * r["plan_ms"] for r in cost], "v-", ms=3, label="ESTIMATE plan")
    j = min(len(cost) - 1, 4)
    ref = cost[j]["solve_s"] * N * np.log(N) / (N[j] * np.log(N[j]))
    a.loglog(N, ref, "k:", label="N log N")
    a.set_xlabel("N (dx = h/64, L = N dx)")
    a.set_ylabel("time [s]")
    a.legend(fontsize=7)
    a.set_title("1. cost against N (paper scene, mu = 2)")
    a = ax[0, 1]
    a.semilogx(N, [r["gmres_its"] for r in cost], "o-", ms=3, label="GMRES its")
    a.semilogx(N, [10 * r["active_set_its"] for r in cost], "s-", ms=3, label="10 x active-set its")
    a.set_ylim(bottom=0)
    a.set_xlabel("N")
    a.set_ylabel("iterations")
    b = a.twinx()
    b.loglog(N, [r["peak_MiB"] for r in cost], "r^-", ms=3, label="peak traced memory [MiB]")
    b.loglog(N, [r["maxrss_MiB"] for r in cost], "mv:", ms=3, label="max RSS [MiB]")
    b.set_ylabel("MiB")
    h1, l1 = a.get_legend_handles_labels()
    h2, l2 = b.get_legend_handles_labels()
    a.legend(h1 + h2, l1 + l2, fontsize=7, loc="center left")
    a.set_title("1b. iterations and memory")
    a = ax[0, 2]
    Np = np.array([r["N"] for r in plan], float)
    a.loglog(Np, [1e-3 * r["estimate_plan_ms"] for r in plan], "o-", ms=3, label="ESTIMATE plan")
    a.loglog(Np, [r["measure_plan_s"] for r in plan], "s-", ms=3, label="MEASURE plan")
    a.loglog(Np, [1e-3 * r["wisdom_replan_ms"] for r in plan], "^-", ms=3,
             label="MEASURE re-plan from wisdom")
    a.loglog(Np, [1e-6 * r["estimate_pair_us"] for r in plan], "o--", ms=3,
             label="FFT pair, ESTIMATE plan")
    a.loglog(Np, [1e-6 * r["measure_pair_us"] for r in plan], "s--", ms=3,
             label="FFT pair, MEASURE plan")
    a.set_xlabel("N")
    a.set_ylabel("time [s]")
    a.legend(fontsize=7)
    a.set_title("2. FFTW planning")
    a = ax[0, 3]
    for s, prof in sorted(tprof.items()):
        a.plot(np.arange(len(prof)), prof, "o-", ms=3, label=f"s = {s:g} h")
    a.axhline(0, color="k", lw=0.5)
    a.set_xlabel("cylinder index in the train (sliding toward +x)")
    a.set_ylabel("a_i / a_isolated - 1")
    a.legend(fontsize=6, ncol=3, loc="lower center")
    a.set_title(f"3a. train of {train[0]['M']} equal cylinders")
    a = ax[1, 0]
    ok = [r for r in train if r["status"] == "ok"]
    s = np.array([r["spacing"] for r in ok])
    for key, lab in (("a_mid_rel", "a, middle"), ("a_first_rel", "a, first"),
                     ("a_last_rel", "a, last"), ("a_periodic_rel", "a, infinite train"),
                     ("d_mid_rel", "d, middle")):
        a.semilogy(s, [abs(r[key]) for r in ok], "o-", ms=3, label=f"|{lab} / isolated - 1|")
    a.semilogy(s, [r["predicted"] for r in ok], "k:", label="exp(-0.739 (s - 2a))")
    for r in train:
        if r["status"] != "ok":
            a.plot(r["spacing"], 1.0, "rx", ms=10)
    a.set_xlabel("apex spacing s [h]")
    a.legend(fontsize=7)
    a.set_title("3a. neighbour interaction through the film")
    a = ax[1, 1]
    Ms = [r["M"] for r in tsize]
    a.semilogx(Ms, [r["time_per_cyl_ms"] for r in tsize], "o-", ms=3, base=2,
               label="train: time per cylinder")
    a.semilogx(Ms, [r["isolated_ms"] for r in tsize], "k--", base=2,
               label="isolated cylinder (64 h, N = 2048)")
    a.set_xlabel(f"cylinders M (spacing {tsize[0]['spacing']:g} h)")
    a.set_ylabel("ms")
    a.set_ylim(bottom=0)
    b = a.twinx()
    b.semilogx(Ms, [r["gmres"] for r in tsize], "rs:", ms=3, base=2, label="GMRES its")
    b.set_ylabel("GMRES iterations")
    h1, l1 = a.get_legend_handles_labels()
    h2, l2 = b.get_legend_handles_labels()
    a.legend(h1 + h2, l1 + l2, fontsize=7)
    a.set_title("3b. train size")
    a = ax[1, 2]
    k = np.arange(len(uneq))
    cols = [c for c in uneq[0] if c.startswith("a_rel_s")]
    for i, c in enumerate(cols):
        big = max(abs(r[c]) for r in uneq)
        a.bar(k + (i - 0.5) * 0.4, [r[c] for r in uneq], 0.4,
              label=f"spacing {c[7:]} h (max |.| = {big:.1e})")
    a.set_xticks(k, [f"c={r['curvature']:g}\nP={r['load_rel']:g}" for r in uneq], fontsize=6)
    a.set_ylabel("a_i / a_i,isolated - 1")
    a.legend(fontsize=7)
    a.set_title("3c. unequal radii and loads")
    a = ax[1, 3]
    for s, (x, p) in sorted(uprof.items()):
        a.plot(x, p, lw=0.8, label=f"spacing {s:g} h")
    a.set_xlabel("x [h]")
    a.set_ylabel("p [E h / 6R]")
    a.legend(fontsize=7)
    a.set_title("3c. pressure, unequal train")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/large_domain")
    scene = Scene()
    t0 = time.perf_counter()
    if args.quick:
        cost_exps, plan_exps = range(10, 15), [10, 12]
        M, spacings, Ms = 4, [3.0, 6.0, 12.0], [2, 4]
        curv, loads = [1.0, 0.5, 2.0, 4.0], [1.0, 2.0, 0.5, 3.0]
    else:
        cost_exps, plan_exps = range(10, 23), range(10, 19)
        M = 32
        spacings = [2.75, 3.0, 3.5, 4.0, 5.0, 6.0, 7.0, 8.0, 10.0, 12.0, 14.0, 16.0, 20.0]
        Ms = [4, 8, 16, 32, 64]
        curv = [1.0, 0.5, 2.0, 1.0, 4.0, 0.7, 1.5, 1.0]
        loads = [1.0, 2.0, 0.5, 1.5, 3.0, 0.5, 2.0, 0.4]  # P_i/c_i all different

    cost = cost_sweep(scene, list(cost_exps), t0)
    table(cost, out / "large_domain_cost.csv",
          f"1. Cost against N: paper scene (P = {scene.P:.4g}, mu_d = {MU:g}), dx = h/64 fixed, "
          f"L = N dx; cold start; times in s unless named")
    plan = planning_sweep(scene, list(plan_exps), out, t0)
    table(plan, out / "large_domain_planning.csv",
          "2. FFTW planning: ESTIMATE vs MEASURE (wisdom forgotten before each plan), re-plan "
          "from wisdom; solve_* = warm solve of 1. with each kind of plan; times are minima over "
          "interleaved repeats; break_even_solves = MEASURE plan time / time saved per solve")
    train, tprof, iso = train_sweep(scene, M, spacings, t0)
    table(train, out / "large_domain_train.csv",
          f"3a. Finite train of {M} equal cylinders (mu_d = {MU:g}, dx = h/32), apex spacing s; "
          f"isolated a = {iso['a']:.5f} h, d = {iso['d']:.5f}; *_rel = train / isolated - 1; "
          f"a_periodic = one cylinder on period s")
    da, dd = periodic_check(scene, M, spacings[len(spacings) // 2])
    print(f"periodic check: {M} cylinders on period {M} s vs one on period s "
          f"(s = {spacings[len(spacings) // 2]:g}): max |da| = {da:.1e}, max |dd| = {dd:.1e}")
    tsize = train_size_sweep(scene, Ms, 6.0, t0)
    table(tsize, out / "large_domain_train_size.csv",
          "3b. Train size: M equal cylinders at spacing 6 h (median of 3 warm solves)")
    uneq, uprof, utimes, t_iso = unequal_sweep(scene, curv, loads, [25.0, 6.0], t0)
    table(uneq, out / "large_domain_unequal.csv",
          "3c. Unequal cylinders: curvature c = R/R_i, load P_i = load_rel P; a_iso = alone on "
          "the same dx; a_front_door = solve(Scene(radius=R/c, load=...)) at tol 1e-5; "
          "a_rel / d_rel at each spacing = train / isolated - 1")
    print(f"unequal train of {len(curv)}: " + ", ".join(
        f"spacing {s:g} h: {dt:.3f} s on N = {n}" for s, (dt, n) in utimes.items())
        + f"; the {len(curv)} isolated solves (N = 2048 each): {t_iso:.3f} s in all")
    try:
        plot(out / "large_domain.png", cost, plan, train, tprof, tsize, uneq, uprof)
    except Exception as exc:  # a plot must never lose the tables
        print(f"plot skipped: {exc}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
