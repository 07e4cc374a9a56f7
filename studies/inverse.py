"""Inverse: from base stresses (or the MEMS view) back to the interface tractions (issue 21).

    python -m studies.inverse [--quick] [--out DIR] [--seeds N]
                              [--parts calibration,sweep,routes,speed,figure,noise_free]

Synthetic records on the paper's film (h = 2 mm, E = 2.2 MPa, R = 130 mm, P_L = 200 N/m) over
x in [-10, 10] mm, 401 samples (step 0.05 mm), white Gaussian noise of sd = (noise) x the peak
of each component, one record per seed:

1. calibration (1 % noise, many seeds): three truths, each with and without the apparatus
   (the paper's G_zz, G_xz):
   * amontons: the exact model's solve at mu_d = 1 (its own base stresses / sensor view);
   * strength: the exact model with q = tau0 + alpha p (tau0 = 5 kPa, alpha = 0.5), q steps at
     the contact edges;
   * mu_varying: the pressure of the mu_d = 0.5 solve with q = mu(x) p, mu(x) = 0.5 + 0.3
     (x - x_c)/a, through the film's base transfer (``inverse.base_from_tractions``).
   Every record has its own noise draw (seed 1000 case + 100 view + s).  Per record: L2 errors
   of p and q over the nodes (relative to the truth's norm), the share of nodes where the 2-sd
   band covers the truth on the central 70 % of the contact and on the whole contact, z-scores
   of P and Q ((estimate - truth)/sigma) and their relative errors, the CPU seconds.
   Positivity (``positive=True``): a third of the seeds again for amontons and strength
   (base view): the constrained mode's coverage.
2. error and coverage against the noise (0.3, 1, 3 %) and against the contact's size in film
   thicknesses (h = 1, 2, 4 mm at the same scene: a/h = 2.3, 1.2, 0.6), with/without apparatus.
3. the paper's route (P = Int S_zz dx, Q/P = Int S_xz / Int S_zz over the record) against the
   local route on the same records, and whether a shear strength is told from Amontons at the
   paper's noise: the share of seeds where Amontons loses by AIC > 2 (strength case).
4. speed: CPU seconds (``time.process_time``) of records of 401 and 10^4 samples, base and
   sensor views, the auto prior with and without the hyperparameters' propagation and the
   contact prior alone (median of warm runs; the load beside it), with the number of evidence
   evaluations and, in the same run, the CPU time of one evaluation and of an FFT pair; the
   warm-up (auto, not propagated) before each record's runs: the first row's is the
   process's first inversion (it pays the inverse's lazy imports).

5. noise_free: the three truths, both views, with no noise and 0.01 % and 0.1 % (seed 7), the
   default prior: L2, coverage, z of P and Q, the contact edges' errors against their sd; and
   noise-free base records of the amontons scene with h = 1, 4 mm, mu = 0.3, 2, load 60 N/m.

Writes inverse_noise_free.csv, inverse_calibration.csv (one row per record), inverse_summary.csv (means over seeds),
inverse_sweep.csv, inverse_routes.csv, inverse_speed.csv, inverse_example.csv (a record a new
user can invert: ``spectral-contact invert DIR/inverse_example.csv``) and inverse.png.
"""
from __future__ import annotations

import os
import sys
import time

import numpy as np

from spectral_contact import solve
from spectral_contact.instruments.inverse import base_from_tractions, invert_line
from spectral_contact.instruments.sensor import sensor_profiles

from ._common import parse, table, write_rows

X = np.arange(-10e-3, 10e-3 + 1e-9, 0.05e-3)
PARTS = ("calibration", "sweep", "routes", "speed", "figure", "noise_free")
NOISE_FREE_LEVELS = (0.0, 1e-4, 1e-3)
"""Noise levels of the ``noise_free`` part: none, 0.01 %, 0.1 % of each component's peak."""
NOISE_FREE_SCENES = ({"thickness": 0.001}, {"thickness": 0.004}, {"mu": 0.3}, {"mu": 2.0},
                     {"load": 60.0})
"""Further noise-free base records of the ``noise_free`` part: the exact model's solve at these
changes of the amontons scene (load 200 N/m, mu 1, h 2 mm)."""


def truth(case: str, thickness: float = 0.002):
    """(x_m, p, q, base sigma_zz, base sigma_xz, P, Q) of a case, on a periodic grid."""
    if case == "amontons":
        r = solve(load=200.0, mu=1.0, thickness=thickness)
        x, p, q = r.x_m, r.pressure_Pa, r.surface_shear_Pa
        szz, sxz = r.base_sigma_zz_Pa, r.base_sigma_xz_Pa
    elif case == "strength":
        r = solve(load=200.0, mu=1.0, thickness=thickness, friction_law="linear",
                  shear_strength=5e3, shear_slope=0.5)
        x, p, q = r.x_m, r.pressure_Pa, r.surface_shear_Pa
        szz, sxz = r.base_sigma_zz_Pa, r.base_sigma_xz_Pa
    else:  # mu_varying: q = mu(x) p through the film's base transfer
        r = solve(load=200.0, mu=0.5, thickness=thickness)
        x, p = r.x_m, r.pressure_Pa
        (a, b), = r.contact_intervals_m
        mu = 0.5 + 0.3 * (x - 0.5 * (a + b)) / (0.5 * (b - a))
        q = np.where(p > 0, mu * p, 0.0)
        szz, sxz = base_from_tractions(x, p, q, thickness)
    dx = x[1] - x[0]
    return x, p, q, szz, sxz, float(np.sum(p) * dx), float(np.sum(q) * dx)


def record(tr, view, noise, seed, xs=X):
    x, p, q, szz, sxz, P, Q = tr
    if view == "sensor":
        v = sensor_profiles(x, szz, sxz, periodic=True)
        zz, xz = v["S_zz_Pa"], v["S_xz_Pa"]
    else:
        zz, xz = -szz, sxz
    zz, xz = np.interp(xs, x, zz), np.interp(xs, x, xz)
    rng = np.random.default_rng(seed)
    return (zz + noise * np.abs(zz).max() * rng.standard_normal(xs.size),
            xz + noise * np.abs(xz).max() * rng.standard_normal(xs.size))


def score(tr, inv):
    x, p, q, _, _, P, Q = tr
    s = inv.summary()
    pt, qt = np.interp(inv.x_m, x, p), np.interp(inv.x_m, x, q)
    on = p > 0
    a, b = x[on].min(), x[on].max()
    c, hw = 0.5 * (a + b), 0.5 * (b - a)
    inside = (inv.x_m > a) & (inv.x_m < b)
    central = np.abs(inv.x_m - c) < 0.7 * hw
    cp = np.abs(inv.pressure_Pa - pt) <= 2 * inv.pressure_sd_Pa
    cq = np.abs(inv.shear_Pa - qt) <= 2 * inv.shear_sd_Pa
    laws = s["laws"]
    am, lin = laws.get("amontons", {}), laws.get("linear", {})
    return {"L2_p": float(np.linalg.norm(inv.pressure_Pa - pt) / np.linalg.norm(pt)),
            "L2_q": float(np.linalg.norm(inv.shear_Pa - qt) / np.linalg.norm(qt)),
            "cover_p_central": float(cp[central].mean()), "cover_q_central": float(cq[central].mean()),
            "cover_p_contact": float(cp[inside].mean()), "cover_q_contact": float(cq[inside].mean()),
            "z_P": (s["load_N_per_m"] - P) / s["load_sigma_N_per_m"],
            "z_Q": (s["tangential_load_N_per_m"] - Q) / s["tangential_load_sigma_N_per_m"],
            "err_P": s["load_N_per_m"] / P - 1.0, "err_Q": s["tangential_load_N_per_m"] / Q - 1.0,
            "resolution_mm": s["resolution_length_m"] * 1e3,
            "aic_amontons_minus_linear": (am.get("aic", np.nan) - lin.get("aic", np.nan)),
            "best_law": laws.get("best"),
            "prior": s["regularisation"].get("prior_choice", {}).get("chosen", "contact"),
            **edge_scores(s, a, b)}


def edge_scores(s, a, b):
    """The reported contact interval's edges against the truth's (a, b) [m]: errors and sd [mm]
    and z = error / sd."""
    (lo, hi), (slo, shi) = s["contact_interval_m"], s["contact_interval_sigma_m"]
    return {"edge_left_err_mm": (lo - a) * 1e3, "edge_left_sd_mm": slo * 1e3,
            "edge_right_err_mm": (hi - b) * 1e3, "edge_right_sd_mm": shi * 1e3,
            "z_edge_left": (lo - a) / slo if slo > 0 else np.nan,
            "z_edge_right": (hi - b) / shi if shi > 0 else np.nan}


class _count_evaluations:
    """Counts the evidence evaluations of the two line priors inside a ``with`` block."""

    def __enter__(self):
        from spectral_contact.instruments import inverse_evidence, inverse_prior

        self.counts = {"contact": 0, "envelope": 0}
        self.saved = []
        for cls, key in ((inverse_prior.ContactPrior, "contact"),
                         (inverse_evidence._Evidence, "envelope")):
            orig = cls.evaluate

            def ev(obj, *a, _orig=orig, _key=key, **k):
                self.counts[_key] += 1
                return _orig(obj, *a, **k)

            self.saved.append((cls, orig))
            cls.evaluate = ev
        return self.counts

    def __exit__(self, *exc):
        for cls, orig in self.saved:
            cls.evaluate = orig
        return False


def _unit_times(repeats: int = 51):
    """CPU seconds (median) of one contact-prior evidence evaluation with its gradient on 60
    nodes, and of one FFT pair of 8192 points."""
    from spectral_contact.instruments.inverse_forward import LineForward
    from spectral_contact.instruments.inverse_prior import ContactPrior
    from spectral_contact.numerics.blas_threads import single_blas_thread
    from spectral_contact.numerics.fft import get_rfft
    from spectral_contact.physics.film import Film

    x = np.linspace(-5.0, 5.0, 201)
    fwd = LineForward.build(x, Film(1.0, 0.5), step=1.0 / 16.0, span=(-1.85, 1.85))
    d = np.sqrt(np.clip(1 - x**2, 0, None))
    ev = ContactPrior(fwd, d, 0.5 * d)
    th = np.array([0.0, 0.0, 0.0, 1.0, 0.5, -3.0, 0.0, -3.0, 0.0, -7.0, -4.6, -4.6])
    f = get_rfft(8192)
    a = np.random.default_rng(0).random(8192)
    sym = np.ones(8192 // 2 + 1, complex)

    def med(fn):
        ts = []
        for _ in range(repeats):
            c0 = time.process_time()
            fn()
            ts.append(time.process_time() - c0)
        return float(np.median(ts))

    with single_blas_thread():  # as inside invert_line
        unit = med(lambda: ev.evaluate(th, grad=True))
    return unit, med(lambda: [f.apply(a, sym) for _ in range(20)]) / 20


def summarise(rows, keys):
    out = []
    groups = {}
    for r in rows:
        groups.setdefault(tuple(r[k] for k in keys), []).append(r)
    for g, rs in groups.items():
        def m(k):
            return float(np.mean([r[k] for r in rs]))

        zP = np.array([r["z_P"] for r in rs])
        zQ = np.array([r["z_Q"] for r in rs])
        zE = np.array([r[k] for r in rs for k in ("z_edge_left", "z_edge_right")])
        out.append({**dict(zip(keys, g)), "seeds": len(rs), "L2_p": m("L2_p"), "L2_q": m("L2_q"),
                    "cover_p_central": m("cover_p_central"), "cover_q_central": m("cover_q_central"),
                    "cover_p_contact": m("cover_p_contact"), "cover_q_contact": m("cover_q_contact"),
                    "zP_rms": float(np.sqrt(np.mean(zP**2))), "zQ_rms": float(np.sqrt(np.mean(zQ**2))),
                    "P_within_2sigma": float(np.mean(np.abs(zP) <= 2)),
                    "Q_within_2sigma": float(np.mean(np.abs(zQ) <= 2)),
                    "max_abs_err_P": float(max(abs(r["err_P"]) for r in rs)),
                    "max_abs_err_Q": float(max(abs(r["err_Q"]) for r in rs)),
                    "z_edges_rms": float(np.sqrt(np.nanmean(zE**2))),
                    "edges_within_2sd": float(np.mean(np.abs(zE) <= 2))})
    return out


def main(argv=None) -> int:
    def extra(p):
        p.add_argument("--seeds", type=int, default=None,
                       help="noise seeds per calibration case (10; --quick 2)")
        p.add_argument("--parts", default=",".join(PARTS),
                       help=f"comma-separated subset of {','.join(PARTS)} (default all)")

    args, out = parse(argv, __doc__.splitlines()[0], "out/inverse", extra=extra)
    parts = [s.strip() for s in args.parts.split(",") if s.strip()]
    bad = [s for s in parts if s not in PARTS]
    if bad:
        print(f"--parts: {','.join(bad)} not among {','.join(PARTS)}", file=sys.stderr)
        return 2
    seeds = args.seeds or (2 if args.quick else 10)
    t0 = time.perf_counter()
    cases = ("amontons", "strength", "mu_varying")
    truths = {c: truth(c) for c in cases}
    if "calibration" in parts:
        # 1. calibration: an independent noise draw for every record (seed 1000 case + 100 view + s)
        rows = []
        npos = max(1, seeds // 3)
        n = len(cases) * 2 * seeds + 2 * npos
        runs = [(case, view, False, s) for case in cases for view in ("base", "sensor")
                for s in range(seeds)]
        runs += [(case, "base", True, s) for case in ("amontons", "strength") for s in range(npos)]
        for case, view, positive, s in runs:
            seed = 1000 * cases.index(case) + 100 * (view == "sensor") + 50 * positive + s
            zz, xz = record(truths[case], view, 0.01, seed)
            c0 = time.process_time()
            inv = invert_line(X, zz, xz, view=view, positive=positive)
            rows.append({"case": case, "view": view, "positive": positive, "noise": 0.01,
                         "seed": seed, "cpu_s": time.process_time() - c0,
                         **score(truths[case], inv)})
            print(f"  [{len(rows)}/{n}] {case} {view}{' positive' if positive else ''} seed {seed} "
                  f"({time.perf_counter() - t0:.0f} s)", file=sys.stderr, flush=True)
        write_rows(rows, out / "inverse_calibration.csv",
                   "inverse calibration: one row per record (1 % noise, 401 samples over +-10 mm)")
        summ = summarise(rows, ("case", "view", "positive"))
        summ += summarise([dict(r, case="all", view="all") for r in rows if not r["positive"]],
                          ("case", "view", "positive"))
        table(summ, out / "inverse_summary.csv",
              f"inverse calibration, 1 % noise, {seeds} seeds per row: L2 errors, 2-sd coverage "
              f"(central 70 % / whole contact), P and Q z-scores")
    if "sweep" in parts:
        # 2. noise and feature size
        sweep = []
        s2 = 1 if args.quick else 3
        for view in ("base", "sensor"):
            for noise in ((0.01,) if args.quick else (0.003, 0.01, 0.03)):
                for seed in range(s2):
                    zz, xz = record(truths["amontons"], view, noise, 5000 + seed)
                    sweep.append({"sweep": "noise", "view": view, "noise": noise, "a_over_h": 1.17,
                                  **score(truths["amontons"], invert_line(X, zz, xz, view=view))})
            for h in ((0.001,) if args.quick else (0.001, 0.004)):
                tr = truth("amontons", h)
                a_over_h = 0.5 * (tr[0][tr[1] > 0].max() - tr[0][tr[1] > 0].min()) / h
                for seed in range(s2):
                    zz, xz = record(tr, view, 0.01, 6000 + seed)
                    sweep.append({"sweep": "thickness", "view": view, "noise": 0.01,
                                  "a_over_h": round(a_over_h, 3),
                                  **score(tr, invert_line(X, zz, xz, thickness=h, view=view))})
            print(f"  sweep {view} done ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
        write_rows(sweep, out / "inverse_sweep.csv",
                   "inverse: error and coverage against noise and a/h (amontons case)")
        table(summarise(sweep, ("sweep", "view", "noise", "a_over_h")), out / "inverse_sweep_summary.csv",
              "inverse: means over seeds against noise and contact half-width / h")
    if "noise_free" in parts:
        # 5. noise-free and nearly noise-free records, default prior (the model-error floor)
        nf = []
        for case in cases:
            for view in ("base", "sensor"):
                for noise in NOISE_FREE_LEVELS:
                    zz, xz = record(truths[case], view, noise, 7)
                    inv = invert_line(X, zz, xz, view=view)
                    nf.append({"case": case, "view": view, "noise": noise,
                               **score(truths[case], inv)})
        # the exact model's own noise-free base records at other scenes (amontons)
        for kw in NOISE_FREE_SCENES:
            r = solve(**{"load": 200.0, "mu": 1.0, **kw})
            tr = (r.x_m, r.pressure_Pa, r.surface_shear_Pa, r.base_sigma_zz_Pa,
                  r.base_sigma_xz_Pa, float(np.sum(r.pressure_Pa) * (r.x_m[1] - r.x_m[0])),
                  float(np.sum(r.surface_shear_Pa) * (r.x_m[1] - r.x_m[0])))
            zz, xz = record(tr, "base", 0.0, 7)
            inv = invert_line(X, zz, xz, thickness=r.scene.thickness)
            (a, b), = r.contact_intervals_m
            nf.append({"case": "amontons " + " ".join(f"{k}={v:g}" for k, v in kw.items()),
                       "view": "base", "noise": 0.0, **score(tr, inv),
                       **edge_scores(inv.summary(), a, b)})
        table(nf, out / "inverse_noise_free.csv",
              "inverse, default prior, noise-free and 0.01 / 0.1 % noise records (seed 7): L2, "
              "coverage, z of P and Q, the contact edges' errors and sd")
    if "routes" in parts:
        # 3. routes: the paper's two integrals against the local route (sensor view, 1 % noise)
        routes = []
        for ci, case in enumerate(cases):
            x, p, q, szz, sxz, P, Q = truths[case]
            for s in range(min(seeds, 5)):
                seed = 1000 * ci + 100 + s  # the calibration's sensor records
                zz, xz = record(truths[case], "sensor", 0.01, seed)
                Pi, Qi = float(np.trapezoid(zz, X)), float(np.trapezoid(xz, X))
                inv = invert_line(X, zz, xz, view="sensor")
                s = inv.summary()
                routes.append({"case": case, "seed": seed, "P_true": P, "Q_over_P_true": Q / P,
                               "P_integral_err": Pi / P - 1, "Q_over_P_integral_err": (Qi / Pi) / (Q / P) - 1,
                               "P_local_err": s["load_N_per_m"] / P - 1,
                               "P_local_sigma_rel": s["load_sigma_N_per_m"] / P,
                               "Q_over_P_local_err": s["Q_over_P"] / (Q / P) - 1,
                               "Q_over_P_local_sigma_rel": s["Q_over_P_sigma"] / (Q / P),
                               "best_law": s["laws"].get("best"),
                               "aic_amontons_minus_linear": s["laws"]["amontons"]["aic"]
                               - s["laws"]["linear"]["aic"]})
        table(routes, out / "inverse_routes.csv",
              "paper's route (integrals over the +-10 mm record) vs the local route (sensor view, 1 % "
              "noise)")
    if "speed" in parts:
        # 4. speed: CPU time of the solve (time.process_time) for 401 and 10^4 samples, the
        # evidence evaluations it made (a count the machine's load does not change), and the
        # CPU time of one evaluation of the contact prior's evidence with its gradient on 60
        # nodes (the unit of the work) and of an FFT pair of 8192 points, timed in the same run
        from spectral_contact.numerics.blas_threads import blas_thread_counts

        # the BLAS threads of this process outside the inversion (which holds one: issue 21)
        blas = "/".join(map(str, blas_thread_counts())) or "not found"
        speed = []
        for view in ("base", "sensor"):
            for ns in (401, 10_000):
                xs = np.linspace(-10e-3, 10e-3, ns)
                zz, xz = record(truths["amontons"], view, 0.01, 0, xs)
                c0 = time.process_time()  # the first of the run is the process's first inversion
                invert_line(xs, zz, xz, view=view, hyper=False)
                warm = time.process_time() - c0
                for prior, hyper in (("auto", True), ("auto", False), ("contact", True)):
                    ts = []
                    for _ in range(1 if args.quick else 3):
                        with _count_evaluations() as counts:
                            c0 = time.process_time()
                            invert_line(xs, zz, xz, view=view, prior=prior, hyper=hyper)
                            ts.append(time.process_time() - c0)
                    unit, pair = _unit_times()
                    speed.append({"view": view, "samples": ns, "prior": prior,
                                  "hyper_propagated": hyper,
                                  "median_cpu_s": float(np.median(ts)),
                                  "evaluations_contact": counts["contact"],
                                  "evaluations_envelope": counts["envelope"],
                                  "evaluation_cpu_ms": unit * 1e3, "fft_pair_cpu_us": pair * 1e6,
                                  "load_1min": os.getloadavg()[0], "cores": os.cpu_count(),
                                  "blas_threads_outside": blas,
                                  "warmup_cpu_s": warm})
                    print(f"  speed {view} {ns} {prior} hyper={hyper}: "
                          f"{speed[-1]['median_cpu_s']:.2f} s", file=sys.stderr, flush=True)
        table(speed, out / "inverse_speed.csv",
              "inverse: CPU seconds of one inversion (median of warm runs; process_time, one "
              "thread), the evidence evaluations it made (contact and envelope priors), and in "
              "the same run the CPU time of one contact-prior evaluation with gradient (60 "
              "nodes) and of an FFT pair (8192 points); the inversion holds one BLAS thread "
              "(blas_threads_outside: this process's count outside it); warmup_cpu_s: the "
              "record's first inversion (the first row's: the process's first)")
    if "figure" in parts:
        # example record for a new user (strength case, sensor-free, 1 % noise)
        x, p, q, szz, sxz, P, Q = truths["strength"]
        rng = np.random.default_rng(0)
        bz, bx = np.interp(X, x, szz), np.interp(X, x, sxz)
        write_rows([{"x_m": float(a), "base_sigma_zz_Pa": float(b), "base_sigma_xz_Pa": float(c)}
                    for a, b, c in zip(X, bz + 0.01 * np.abs(bz).max() * rng.standard_normal(X.size),
                                       bx + 0.01 * np.abs(bx).max() * rng.standard_normal(X.size))],
                   out / "inverse_example.csv")
        # figure: one inversion of each case (sensor view), truth over the bands
        from matplotlib.figure import Figure

        fig = Figure(figsize=(12, 7), layout="constrained")
        axes = fig.subplots(2, 3)
        for j, case in enumerate(cases):
            x, p, q, *_ = truths[case]
            zz, xz = record(truths[case], "sensor", 0.01, 0)
            inv = invert_line(X, zz, xz, view="sensor")
            ax = axes[0, j]
            for f, sd, t, c, lab in ((inv.pressure_Pa, inv.pressure_sd_Pa, p, "C0", "p"),
                                     (inv.shear_Pa, inv.shear_sd_Pa, q, "C1", "q")):
                ax.fill_between(inv.x_m * 1e3, (f - 2 * sd) / 1e3, (f + 2 * sd) / 1e3, color=c,
                                alpha=0.3)
                ax.plot(inv.x_m * 1e3, f / 1e3, c + "-", label=f"{lab} posterior mean, 2 sd")
                ax.plot(x * 1e3, t / 1e3, "k--", lw=0.8)
            ax.set_xlim(-5, 6)
            ax.set_title(f"{case} (sensor view, 1 % noise); truth dashed", fontsize=9)
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("kPa")
            ax.legend(fontsize=7)
            ax = axes[1, j]
            ok = np.isfinite(inv.mu_local)
            ax.fill_between(inv.x_m[ok] * 1e3, inv.mu_local[ok] - 2 * inv.mu_local_sd[ok],
                            inv.mu_local[ok] + 2 * inv.mu_local_sd[ok], color="C2", alpha=0.3)
            ax.plot(inv.x_m[ok] * 1e3, inv.mu_local[ok], "C2.-", label="q/p (p > 3 sd), 2 sd")
            on = p > 0
            ax.plot(x[on] * 1e3, q[on] / p[on], "k--", lw=0.8, label="truth")
            ax.set_xlim(-5, 6)
            ax.set_ylim(0, 2)
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("mu_local")
            ax.legend(fontsize=7)
        fig.savefig(out / "inverse.png", dpi=110)
        print(f"(written {out / 'inverse.png'}; {time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
