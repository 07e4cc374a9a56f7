"""Inverse, surfaces: a sliding sphere's base maps back to its tractions (issue 21, study part 3).

    python -m studies.inverse_maps [--quick] [--out DIR] [--seeds N] [--first-seed K]
                                   [--prior auto|contact|smooth] [--speed]

Truths: the package's own sliding-sphere solves on the paper's film (h = 2 mm, E = 2.2 MPa,
R = 130 mm, F = 1 N, sliding toward +x), on the solver's periodic grid of 160 x 160 points
(step h/8 over ~20 h: the base field has decayed to ~1e-4 of its peak at the border, so the
record is one period):

* amontons: mu = 1 (q = mu p e_x);
* strength: q = tau0 + alpha p in the contact (tau0 = 5 kPa, alpha = 0.5; steps at the edge).

Records: the base maps (view "base") or the MEMS S maps through the paper's 2D apparatus
functions (``instruments.sensor.sensor_maps``, view "sensor"; amontons only), plus white
Gaussian noise of sd = 1 % of each component's peak, one record per seed.  Per record: F, Q_x,
Q_y against the truth (z = (estimate - truth)/sigma, relative error), the share of points where
the 2-sd band holds the truth of p and q_x on the central 70 % of the contact (r < 0.7 a_eff
from the pressure centroid, a_eff = sqrt(area/pi)), over the whole contact (p > 0), outside
it, and in rings of r/a_eff; the same share for R(truth), the truth as the posterior mean sees
it (``MapInversion.resolve``: the error's resolution part removed), L2 errors of p and q_x
over the contact (relative to the truth's norm) and of R(truth), the resolution length and
the prior chosen by the evidence (contact or smooth) and the law fitted to the local pairs
(z-scores of mu, tau0, alpha against the truth, Amontons' p-value, AIC margins); the CPU time of the inversion
(time.process_time) and the machine's load.

``--speed`` (instead of the above): the issue's speed demand (a 160^2 map in under 10 s): the
amontons truth, seeds 0-2, base and sensor views, ``invert_maps`` with the default prior, each
record inverted twice in this process (the first call also pays the imports); per call the CPU
seconds (time.process_time), the load, and counts the load does not change: evaluations of the
contact prior's evidence (``ContactMapPrior._core``) and of the products U^T Gc U they needed,
evaluations of the smooth prior's evidence, and the 2D FFTs (numpy's rfft2/irfft2, counted in
planes of 160^2).  Writes inverse_maps_speed.csv.

Writes inverse_maps_records.csv (one row per record), inverse_maps_summary.csv (means over
seeds), inverse_maps.png (one record's ``MapInversion.plot()``) and inverse_maps_example.npz
(a record a new user can invert: ``spectral-contact invert DIR/inverse_maps_example.npz``).
"""
from __future__ import annotations

import os
import sys
import time

import numpy as np

from spectral_contact import solve
from spectral_contact.instruments.inverse_maps import invert_maps
from spectral_contact.instruments.sensor import sensor_maps

from ._common import parse, table, write_rows

GRID = 160


def truth(case: str):
    kw = {"amontons": {"mu": 1.0},
          "strength": {"mu": 1.0, "friction_law": "linear", "shear_strength": 5e3,
                       "shear_slope": 0.5}}[case]
    r = solve(indenter="sphere", force=1.0, grid_points=GRID, **kw)
    m = r.maps()
    S = r.scene.stress_unit
    p = m["pressure_Pa"]
    qx = r.scene.mu * p if r.shear is None else np.asarray(r.shear) * S
    return r, m, p, qx, 0.0 * p


def record(tr, view, noise, seed):
    r, m, *_ = tr
    if view == "base":
        d = [-m["base_sigma_zz_Pa"], m["base_sigma_xz_Pa"], m["base_sigma_yz_Pa"]]
    else:
        s = sensor_maps(r)
        d = [s["S_zz_Pa"], s["S_xz_Pa"], s["S_yz_Pa"]]
    rng = np.random.default_rng(seed)
    return [f + noise * np.abs(f).max() * rng.standard_normal(f.shape) for f in d]


def score(tr, inv, x, y):
    _, _, p, qx, qy = tr
    rec = inv.summary()
    dA = (x[1] - x[0]) * (y[1] - y[0])
    F, Qx = p.sum() * dA, qx.sum() * dA
    X, Y = np.meshgrid(x, y, indexing="ij")
    c = p > 0
    cx, cy = (X * p).sum() / p.sum(), (Y * p).sum() / p.sum()
    a = np.sqrt(c.sum() * dA / np.pi)
    central = c & (np.hypot(X - cx, Y - cy) < 0.7 * a)
    out = {"z_F": (rec["force_N"] - F) / rec["force_sigma_N"],
           "err_F": rec["force_N"] / F - 1.0,
           "z_Qx": (rec["tangential_force_x_N"] - Qx) / rec["tangential_force_x_sigma_N"],
           "err_Qx": rec["tangential_force_x_N"] / Qx - 1.0,
           "z_Qy": rec["tangential_force_y_N"] / rec["tangential_force_y_sigma_N"]}
    rp, rqx, _ = inv.resolve(p, qx, qy)
    r_a = np.hypot(X - cx, Y - cy) / a
    for name, f, t, s, rt in (("p", inv.pressure_Pa, p, inv.pressure_sd_Pa, rp),
                              ("qx", inv.shear_x_Pa, qx, inv.shear_x_sd_Pa, rqx)):
        inside = np.abs(f - t) <= 2 * s
        out[f"cover_central_{name}"] = float(inside[central].mean())
        out[f"cover_contact_{name}"] = float(inside[c].mean())
        out[f"cover_outside_{name}"] = float(inside[~c].mean())
        for lo, hi in ((0.0, 0.5), (0.5, 0.8), (0.8, 1.0), (1.0, 1.3)):
            ring = (r_a >= lo) & (r_a < hi)
            out[f"cover_r{lo:g}-{hi:g}_{name}"] = float(inside[ring].mean())
        out[f"L2_{name}"] = float(np.linalg.norm((f - t)[c]) / np.linalg.norm(t[c]))
        # against what the inversion can see: R(truth) (resolution, not noise)
        out[f"cover_resolved_contact_{name}"] = float((np.abs(f - rt) <= 2 * s)[c].mean())
        out[f"L2_resolution_{name}"] = float(np.linalg.norm((rt - t)[c]) / np.linalg.norm(t[c]))
    # the law from the local pairs (truth: amontons mu = 1; strength tau0 = 5 kPa, alpha = 0.5)
    laws = rec["laws"]
    am, lin = laws.get("amontons", {}), laws.get("linear", {})
    nan = float("nan")
    out["pairs"] = laws.get("pairs", 0)
    out["z_mu"] = (am["mu"] - 1.0) / am["mu_sigma"] if "mu" in am else nan
    out["p_value_amontons"] = am.get("p_value", nan)
    out["z_tau0"] = (lin["tau0_Pa"] - 5e3) / lin["tau0_Pa_sigma"] if "tau0_Pa" in lin else nan
    out["z_alpha"] = (lin["alpha"] - 0.5) / lin["alpha_sigma"] if "alpha" in lin else nan
    out["aic_amontons_minus_linear"] = (am["aic"] - lin["aic"] if "aic" in am and "aic" in lin
                                        else nan)
    ch = rec["regularisation"]["prior_choice"]
    out["prior"] = ch["chosen"]
    out["dlogev_contact_smooth"] = (ch["log_evidence"].get("contact", nan)
                                    - ch["log_evidence"]["smooth"])
    out["log_evidence_contact"] = ch["log_evidence"].get("contact", nan)
    reg = rec["regularisation"]
    out["fit_iterations"] = reg.get("optimizer_iterations", nan)
    out["fit_gradient_norm"] = reg.get("optimizer_gradient_norm", nan)
    out["fit_converged"] = float(bool(reg.get("optimizer_converged", False)))
    out["fit_step_sd"] = reg.get("optimizer_step_sd", nan)
    out["length_p_h"] = reg["length_p_h"]
    out["length_q_h"] = reg["length_q_h"]
    out["a_eff_over_h"] = float(a / rec["thickness_m"])
    out["resolution_over_h"] = rec["resolution_length_m"] / rec["thickness_m"]
    out["nu"] = rec["regularisation"]["smoothness_nu"]
    out["best_law"] = str(rec["laws"].get("best"))
    return out


def summarise(rows):
    keys = [k for k in rows[0] if k not in ("case", "view", "seed", "best_law", "prior")]
    out = []
    for case, view in sorted({(r["case"], r["view"]) for r in rows}):
        rs = [r for r in rows if r["case"] == case and r["view"] == view]
        s = {"case": case, "view": view, "records": len(rs)}
        for k in keys:
            s[k] = float(np.mean([r[k] for r in rs]))
        s["share_F_2sigma"] = float(np.mean([abs(r["z_F"]) <= 2 for r in rs]))
        s["share_Qx_2sigma"] = float(np.mean([abs(r["z_Qx"]) <= 2 for r in rs]))
        s["share_F_1pct"] = float(np.mean([abs(r["err_F"]) <= 0.01 for r in rs]))
        s["share_Qx_1pct"] = float(np.mean([abs(r["err_Qx"]) <= 0.01 for r in rs]))
        s["rms_z_F"] = float(np.sqrt(np.mean([r["z_F"] ** 2 for r in rs])))
        s["rms_z_Qx"] = float(np.sqrt(np.mean([r["z_Qx"] ** 2 for r in rs])))
        s["share_contact_prior"] = float(np.mean([r["prior"] == "contact" for r in rs]))
        s["share_best_amontons"] = float(np.mean([r["best_law"] == "amontons" for r in rs]))
        s["share_best_linear"] = float(np.mean([r["best_law"] == "linear" for r in rs]))
        s["share_mu_2sigma"] = float(np.mean([abs(r["z_mu"]) <= 2 for r in rs]))
        s["share_amontons_not_rejected"] = float(np.mean([r["p_value_amontons"] > 0.01
                                                          for r in rs]))
        s["share_tau0_alpha_2sigma"] = float(np.mean([abs(r["z_tau0"]) <= 2
                                                      and abs(r["z_alpha"]) <= 2 for r in rs]))
        s["share_amontons_loses_aic"] = float(np.mean([r["aic_amontons_minus_linear"] > 2
                                                       for r in rs]))
        out.append(s)
    return out


class _counts:
    """Counts, inside a ``with`` block, the maps inverse's evidence evaluations (contact prior:
    ``_core`` calls and the U^T Gc U products among them; smooth prior: ``evaluate``) and the 2D
    FFT planes numpy transforms (rfft2/irfft2 over two axes of a batch)."""

    def __enter__(self):
        from spectral_contact.instruments import inverse_maps_contact as ic
        from spectral_contact.instruments import inverse_maps_stationary as st

        self.c = {"contact": 0, "contact_products": 0, "contact_grams": 0, "smooth": 0,
                  "fft_planes": 0}
        self.saved = []

        def patch(obj, name, key, planes=False):
            orig = getattr(obj, name)

            def f(*a, **k):
                if planes:
                    x = np.asarray(a[0])
                    ax = k.get("axes", (-2, -1))
                    self.c[key] += x.size // (x.shape[ax[0]] * x.shape[ax[1]])
                else:
                    self.c[key] += 1
                return orig(*a, **k)

            self.saved.append((obj, name, orig))
            setattr(obj, name, f)

        patch(ic.ContactMapPrior, "_core", "contact")
        patch(ic.ContactMapPrior, "U", "contact_products")  # called once per U^T Gc U
        patch(ic.ContactMapPrior, "_gram", "contact_grams")
        patch(st._Model, "evaluate", "smooth")
        patch(np.fft, "rfft2", "fft_planes", planes=True)
        patch(np.fft, "irfft2", "fft_planes", planes=True)
        return self.c

    def __exit__(self, *exc):
        for obj, name, orig in reversed(self.saved):
            setattr(obj, name, orig)
        return False


def speed(out) -> int:
    """The speed part (module docstring, ``--speed``)."""
    tr = truth("amontons")
    x, y = tr[1]["x_m"], tr[1]["y_m"]
    rows = []
    for view in ("base", "sensor"):
        for seed in range(3):
            d = record(tr, view, 0.01, seed)
            for call in (1, 2):
                with _counts() as c:
                    c0 = time.process_time()
                    inv = invert_maps(x, y, *d, thickness=0.002, view=view)
                    cpu = time.process_time() - c0
                rows.append({"view": view, "seed": seed, "call": call, "cpu_s": cpu,
                             "load_1min": os.getloadavg()[0],
                             "prior": inv.summary()["regularisation"]["prior_choice"]["chosen"],
                             "evaluations_contact": c["contact"],
                             "products_UtGcU": c["contact_products"],
                             "grams": c["contact_grams"], "evaluations_smooth": c["smooth"],
                             "fft_planes": c["fft_planes"]})
                print(f"  speed {view} seed {seed} call {call}: cpu {cpu:.2f} s", file=sys.stderr,
                      flush=True)
    table(rows, out / "inverse_maps_speed.csv",
          f"inverse maps, speed: CPU seconds of invert_maps (default prior) on {GRID}^2 maps "
          f"(amontons, 1 % noise), each record twice in one process (call 1 of the first "
          f"record also pays the imports); counts of evidence evaluations, U^T Gc U products, "
          f"Gram matrices and 2D FFT planes")
    return 0


def main(argv=None) -> int:
    def extra(p):
        p.add_argument("--seeds", type=int, default=None,
                       help="noise seeds per case (10; --quick 2)")
        p.add_argument("--first-seed", type=int, default=0,
                       help="the first noise seed (held-out runs: e.g. 10 with --seeds 10)")
        p.add_argument("--prior", choices=("auto", "contact", "smooth"), default="auto",
                       help="the inversion's prior (auto: the higher evidence)")
        p.add_argument("--speed", action="store_true",
                       help="the speed part only (160^2 maps, seeds 0-2, base and sensor)")

    args, out = parse(argv, __doc__.splitlines()[0], "out/inverse_maps", extra=extra)
    if args.speed:
        return speed(out)
    seeds = args.seeds or (2 if args.quick else 10)
    cases = (("amontons", "base"), ("amontons", "sensor"), ("strength", "base"))
    if args.quick:
        cases = cases[:1]
    truths = {c: truth(c) for c in {c for c, _ in cases}}
    t0 = time.perf_counter()
    rows = []
    n = len(cases) * seeds
    example = None
    for case, view in cases:
        tr = truths[case]
        x, y = tr[1]["x_m"], tr[1]["y_m"]
        for seed in range(args.first_seed, args.first_seed + seeds):
            d = record(tr, view, 0.01, seed)
            c0 = time.process_time()
            inv = invert_maps(x, y, *d, thickness=0.002, view=view, prior=args.prior)
            cpu = time.process_time() - c0
            rows.append({"case": case, "view": view, "seed": seed, **score(tr, inv, x, y),
                         "cpu_s": cpu, "load_1min": os.getloadavg()[0]})
            if example is None:
                example = (inv, x, y, d)
            print(f"  [{len(rows)}/{n}] {case} {view} seed {seed}: cpu {cpu:.1f} s "
                  f"({time.perf_counter() - t0:.0f} s)", file=sys.stderr, flush=True)
    write_rows(rows, out / "inverse_maps_records.csv",
               f"inverse maps: one row per record (sliding sphere F = 1 N on the paper's film, "
               f"{GRID}^2 base or S maps, 1 % noise); z = (estimate - truth)/sigma, err relative, "
               f"cover = share of points with |estimate - truth| <= 2 sd, L2 relative to the "
               f"truth's norm over the contact; cpu_s = time.process_time of the inversion [s]")
    table(summarise(rows), out / "inverse_maps_summary.csv",
          f"inverse maps, 1 % noise, {seeds} seeds per row: means, shares within 2 sigma and "
          f"1 %, coverage (central 70 % / whole contact), L2 errors, CPU [s]")
    inv, x, y, d = example
    inv.plot().savefig(out / "inverse_maps.png", dpi=100)
    with open(out / "inverse_maps_example.npz", "wb") as fh:
        np.savez(fh, x_m=x, y_m=y, base_sigma_zz_Pa=-d[0], base_sigma_xz_Pa=d[1],
                 base_sigma_yz_Pa=d[2])
    print(f"wrote {out} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
