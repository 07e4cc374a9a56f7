"""The onset of sliding on the film: the stick zone against Cattaneo-Mindlin over a/h, the
tangential stiffness, what the base (and the MEMS) see before gross sliding, and what the
normal loading and the step size change.

    python -m studies.onset [--quick] [--out DIR]

1. ``onset_stick.csv``: the paper's film (E = 2.2 MPa, R = 130 mm, h = 2 mm), Hertz half-widths
   a_H/h = 0.1, 0.3, 1, 3 (P = 2 pi (a_H/h)^2), mu = 1, 20 steps, tol 1e-3: per step the stick
   zone (half-width c and centre, over the contact's a; its offset from the contact centre),
   Cattaneo-Mindlin's c/a = sqrt(1 - Q/(mu P)), the contact's a and centre, the indenter's
   tangential displacement and the secant / tangent stiffness dQ/d(delta) over the first
   step's.
2. ``onset_signature.csv``: the paper's scene (P_L = 200 N/m, mu = 2): per step the peaks of
   the base stresses and of the MEMS view (S = G (*) sigma through the paper's apparatus
   functions), their positions, and the base shear's centroid.
3. ``onset_loading.csv``: the paper's scene and a/h = 0.3: frictional against frictionless
   normal loading, and the load-step sizes (loading steps 5-40, tangential steps 10-40) at
   Q/(mu P) = 0.5: what the history changes, against the grid's error estimate.
4. ``onset_speed.csv``: 20 steps of the paper's scene at the default tol: wall time (median of
   warm runs), FFT pairs, active-set and GMRES iterations per level, with the machine's load.

Figures: onset_stick.png (stick zone and stiffness against Q/(mu P)), onset_paper.png (the
paper's scene: ``OnsetResult.plot`` with the MEMS view).
"""
from __future__ import annotations

import math
import os
import sys
import time

import numpy as np

from spectral_contact import Scene, onset

from ._common import median_time, parse, progress, table

FILM = {"young": 2.2e6, "thickness": 0.002, "radius": 0.130}


def scene_for(s: float, mu: float) -> Scene:
    """The paper's film with the line load whose Hertz half-width is s film thicknesses."""
    base = Scene(mu=mu, **FILM)
    return base.with_(load=2.0 * math.pi * s * s * base.stress_unit * base.length_unit)


def stick_rows(r, s) -> list[dict]:
    rows = []
    ms = r.measures
    d0 = None
    for k in range(1, r.n_steps + 1):
        m = ms[k]
        qr = float(r.Q_over_muP[k])
        c = 0.5 * (m["stick_hi"] - m["stick_lo"]) if m["stick_nodes"] > 1 else 0.0
        xc = 0.5 * (m["stick_hi"] + m["stick_lo"])
        dq = r.scene.mu * r.scene.P / r.n_steps  # Q step (dimensionless)
        tangent = dq / (m["delta"] - ms[k - 1]["delta"])
        if d0 is None:
            d0 = tangent
        rows.append({
            "aH_over_h": s, "step": k, "Q_over_muP": qr,
            "a_h": m["a"], "contact_center_h": m["c"],
            "stick_half_width_over_a": c / m["a"],
            "cattaneo_over_a": math.sqrt(max(1.0 - qr, 0.0)),
            "stick_center_offset_over_a": (xc - m["c"]) / m["a"],
            "stick_nodes": m["stick_nodes"],
            "delta": m["delta"],
            "tangent_stiffness_rel": tangent / d0,
            "secant_stiffness_rel": (qr * r.scene.mu * r.scene.P / m["delta"]) / d0
            if m["delta"] else math.nan,
            "error_estimate": r.error_estimates[k],
            "stick_error_estimate": r.stick_error_estimates[k],
        })
    return rows


def _peak(x, f):
    j = int(np.argmax(np.abs(f)))
    return float(f[j]), float(x[j])


def signature_rows(r, sensor) -> list[dict]:
    sc = r.scene
    h, sU = sc.length_unit, sc.stress_unit
    x = r.x * h
    rows = []
    for k in range(r.n_steps + 1):
        zz, xz = -r.base_sigma_zz[k] * sU, r.base_sigma_xz[k] * sU
        Szz, Sxz = sensor["S_zz_Pa"][k], sensor["S_xz_Pa"][k]
        pz, xz_ = _peak(x, zz)
        px, xx = _peak(x, xz)
        ps, xs = _peak(x, Szz)
        pt, xt = _peak(x, Sxz)
        w = np.abs(xz)
        rows.append({
            "step": k, "Q_over_muP": float(r.Q_over_muP[k]),
            "base_szz_peak_Pa": pz, "base_szz_peak_x_mm": xz_ * 1e3,
            "base_sxz_peak_Pa": px, "base_sxz_peak_x_mm": xx * 1e3,
            "base_sxz_min_Pa": float(xz.min()),
            "base_sxz_centroid_mm": float((x * xz).sum() / xz.sum()) * 1e3 if abs(xz.sum()) >
            1e-9 * w.sum() else math.nan,
            "S_zz_peak_Pa": ps, "S_zz_peak_x_mm": xs * 1e3,
            "S_xz_peak_Pa": pt, "S_xz_peak_x_mm": xt * 1e3,
            "S_xz_min_Pa": float(Sxz.min()),
            "stick_x_min_mm": r.measures[k]["stick_lo"] * h * 1e3,
            "stick_x_max_mm": r.measures[k]["stick_hi"] * h * 1e3,
        })
    return rows


def loading_rows(quick: bool) -> list[dict]:
    cases = [("paper", Scene())] + ([] if quick else [("aH/h=0.3", scene_for(0.3, 1.0))])
    variants = [("frictional", 10, 20), ("frictionless", 10, 20)]
    if not quick:
        variants += [("frictional", 5, 20), ("frictional", 20, 20), ("frictional", 40, 20),
                     ("frictional", 10, 10), ("frictional", 10, 40)]
    rows = []
    for name, sc in cases:
        ref = None
        for loading, ls, steps in variants:
            r = onset(sc, steps=steps, loading=loading, loading_steps=ls,
                      tol=1e-2 if quick else 1e-3)
            k = steps // 2
            m = r.measures[k]
            if ref is None:
                ref = m
            a = ref["a"]
            rows.append({
                "scene": name, "loading": loading, "loading_steps": ls, "steps": steps,
                "Q_over_muP": float(r.Q_over_muP[k]), "grid_points": r.grid.n,
                "stick_lo_over_a": m["stick_lo"] / a, "stick_hi_over_a": m["stick_hi"] / a,
                "a_h": m["a"], "d": m["d"], "delta": m["delta"],
                "dstick_lo_over_a": (m["stick_lo"] - ref["stick_lo"]) / a,
                "dstick_hi_over_a": (m["stick_hi"] - ref["stick_hi"]) / a,
                "dd_rel": m["d"] / ref["d"] - 1.0, "ddelta_rel": m["delta"] / ref["delta"] - 1.0,
                "loaded_max_q_over_mu_p_max": float(np.abs(r.shear[0]).max()
                                                    / (abs(sc.mu) * r.pressure[0].max())),
                "error_estimate": r.error_estimates[k],
            })
    return rows


def speed_rows(quick: bool) -> list[dict]:
    repeats = 1 if quick else 5
    load = os.getloadavg()[0]
    tol = 1e-2 if quick else None  # (None: onset's default, 1e-3)
    r = onset(Scene(), tol=tol)  # warm (plans, symbols)
    t = median_time(lambda: onset(Scene(), tol=tol), repeats)
    cpu = []  # this process's CPU time (single-threaded: its solving time, less the waits of
    for _ in range(repeats):  # a shared machine)
        c0 = time.process_time()
        onset(Scene(), tol=tol)
        cpu.append(time.process_time() - c0)
    c = r.counters
    # one matrix-vector product's transforms (p and q through the 2 x 2 symbol: two FFT pairs
    # in one batched plan) on the final grid, timed in this run: the time in units of it
    from spectral_contact.numerics.partial_slip import PartialSlipOperator

    op = PartialSlipOperator(r.grid)
    buf = op._plan[0]

    def pair():
        buf[0] = r.pressure[-1]
        buf[1] = r.shear[-1]
        op.transform(op.M)

    t_pair = median_time(lambda: [pair() for _ in range(200)], 5, warm=True) / 200
    return [{"scene": "paper (200 N/m, mu 2)", "steps": r.n_steps, "loading_steps":
             r.loading_steps, "tol": r.tol, "grid_points": r.grid.n,
             "fft_pairs": c["fft_pairs"], "active_set_iterations": c["iterations"],
             "gmres_iterations": c["krylov_iterations"], "median_wall_s": t,
             "median_cpu_s": float(np.median(cpu)), "min_cpu_s": min(cpu), "max_cpu_s": max(cpu),
             "steady_solve_s": r.steady.wall_time_s, "repeats": repeats,
             "load_average_1min": load, "error_estimate": max(r.error_estimates),
             "matvec_transform_us": t_pair * 1e6,
             "wall_over_matvec_transform": t / t_pair}]


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/onset")
    t0 = time.perf_counter()
    sizes = (0.3, 1.0) if args.quick else (0.1, 0.3, 1.0, 3.0)
    steps = 8 if args.quick else 20
    tol = 1e-2 if args.quick else 1e-3
    rows = []
    for i, s in enumerate(sizes):
        r = onset(scene_for(s, 1.0), steps=steps, tol=tol)
        rows += stick_rows(r, s)
        progress(i + 1, len(sizes), f"a_H/h = {s:g}: N = {r.grid.n}", t0)
    table(rows, out / "onset_stick.csv", "stick zone vs Cattaneo-Mindlin on the paper's film, "
          "mu = 1 (lengths in h; delta in h^2/2R; stiffness over the first step's)")
    _plot_stick(rows, out / "onset_stick.png")

    from spectral_contact.cli.onset import _sensor

    r = onset(Scene(), steps=steps, tol=tol)
    sensor = _sensor(r)
    table(signature_rows(r, sensor), out / "onset_signature.csv",
          "paper's scene: base stresses and MEMS view per step (Pa, mm from the apex)")
    fig = r.plot(sensor=sensor)
    fig.savefig(out / "onset_paper.png", dpi=110)
    progress(1, 3, "signature", t0)
    table(loading_rows(args.quick), out / "onset_loading.csv",
          "normal loading (frictional / frictionless) and step sizes at Q/(mu P) = 0.5 "
          "(differences against the first row of the scene; lengths over a)")
    progress(2, 3, "loading", t0)
    table(speed_rows(args.quick), out / "onset_speed.csv",
          "20 steps of the paper's scene at the default tol (wall s: median of warm runs on a "
          "shared machine; load average beside it)")
    progress(3, 3, "speed", t0)
    return 0


def _plot_stick(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    qs = np.linspace(0, 1, 101)
    axes[0].plot(qs, np.sqrt(1 - qs), "k--", lw=1, label="Cattaneo-Mindlin")
    for s in sorted({r["aH_over_h"] for r in rows}):
        sel = [r for r in rows if r["aH_over_h"] == s]
        q = [r["Q_over_muP"] for r in sel]
        axes[0].plot(q, [r["stick_half_width_over_a"] for r in sel], "o-", ms=3,
                     label=f"a_H/h = {s:g}")
        axes[1].plot(q, [r["stick_center_offset_over_a"] for r in sel], "o-", ms=3,
                     label=f"a_H/h = {s:g}")
        axes[2].plot(q, [r["tangent_stiffness_rel"] for r in sel], "o-", ms=3,
                     label=f"a_H/h = {s:g}")
    axes[0].set_ylabel("stick half-width c / a")
    axes[1].set_ylabel("stick-zone centre - contact centre, over a")
    axes[2].set_ylabel("tangent stiffness dQ/d(delta), over the first step's")
    for ax in axes:
        ax.set_xlabel("Q / (mu P)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("onset of sliding on the paper's film (mu = 1)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
