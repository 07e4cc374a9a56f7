"""Cost of the 3D solver: time, iterations and memory against grid size, in FFT pairs.

    python -m studies.three_d_cost [--quick] [--out DIR]

The sliding sphere of the speed target (F = 1 N, R = 130 mm on the paper's film: a ~ 1.3 h,
mu = 1).  (1) The automatic solve at tol 1e-3 (warm: plans made); (2) fixed grids 128^2 ...
2048^2 on the automatic solve's periods, each solve cold (from the Hertz guess), timed as the
median of warm runs, with one FFT pair (rfft2 + irfft2 with a symbol) of the same shape timed in
the same process, the active-set and GMRES iterations and the peak memory (tracemalloc) of one
solve.  Peers (tamaas, ContactMechanics) are timed on the frictionless scene when installed;
they are optional, as in 2D.  Writes three_d_cost.csv and three_d_cost.png.
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
                 "gmres_its": auto.counters["linear_iterations"], "peak_MB": float("nan"),
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
        rows.append({"case": "fixed, cold", "nx": n, "ny": n, "solve_s": t,
                     "fft_pair_ms": 1e3 * pair, "solve_in_fft_pairs": t / pair,
                     "fft_pairs": sol.fft_pairs, "active_set_its": sol.iterations,
                     "gmres_its": sol.krylov_iterations, "peak_MB": peak / 2**20,
                     "error_estimate": float("nan")})
    table(rows, out / "three_d_cost.csv",
          f"3D cost, sliding sphere a ~ 1.3 h, mu = 1 (medians of {repeats} runs; {_peers_note()})")
    fixed = [r for r in rows if r["case"].startswith("fixed")]
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
    axes[0].loglog(n, [r["solve_s"] for r in rows], "o-", label="solve (cold start)")
    axes[0].loglog(n, [r["fft_pair_ms"] / 1e3 for r in rows], "s--", label="one FFT pair")
    axes[0].set_ylabel("wall time [s]")
    axes[0].legend(fontsize=8)
    axes[1].semilogx(n, [r["gmres_its"] for r in rows], "o-", label="GMRES iterations")
    axes[1].semilogx(n, [r["active_set_its"] for r in rows], "s-", label="active-set iterations")
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
