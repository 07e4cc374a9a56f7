"""The edges' grid-to-grid noise of a line solve, and the collocation's edge error it is (issue 23:
why a viscoelastic line's a, x_c were noisier from grid to grid than an elastic one's).

    python -m studies.edge_noise [--quick] [--out DIR] [--parts sweep,fit,wide,figure]

Every solve here is on a fixed grid over a fixed period (``solve(grid_points=N,
domain_length=L)``), its edge fits recorded as the solver makes them: the fitted offset t (cells
beyond the last contact node) and the edge, on the grid and on the grid shifted by half a cell,
with the lattice correction off (``solvers.fft._lattice_edges``); the corrected edge is the fit
less dx ``numerics.edges.lattice_error(t)``, as the solver makes it.  The error of an edge is
against a fine reference on the same period (2^17 - 2^19 points: 16-64 times finer), whose own
edges are corrected the same way (outward, in cells of the coarse grid).  theta: where the
reference edge falls in the coarse grid's cell (outward from the node below it).

sweep   the paper's scene (P_L = 200 N/m, mu 2) and frictionless lines of Hertz half-width a_H/h
        1, 0.1 (``studies.viscoelastic.load_for``); the relaxed elastic film (E_inf), the glassy
        one (2 E_inf) and the SLS film (``studies.viscoelastic.SLS``) at 1e-3, 0.1, 10 m/s;
        N = N0 (1 + k/16), k = 0 ... 32 (N0 2048, 4096, 16384); plus a_H/h 1 relaxed at N0 =
        512, 1024, 16384 (dx/a 5e-4 - 5e-2).  edge_noise_sweep.csv (one row per edge fit) and
        edge_noise_summary.csv (per case: raw and corrected error rms / max, by edge; the
        averaged a and x_c's rms).
fit     the lattice error's series from the canonical scene (a_H/h 1, relaxed film, mu 0; the
        reference corrected with the series and refitted, twice), against the one in
        ``numerics.edges``.
side    which side of the noise: on a_H/h 1 (relaxed, mu 0), the 4-node fit applied to the
        fine solution's gap (2^17 points) sampled at the coarse grid's nodes, against the same
        fit on the coarse solution's own gap (N = 4096 ... 8192): edge_noise_side.csv.
wide    where the correction holds: wide contacts on the thin film (a_H/h 3, 30, and 10 at mu
        10) at dx/h up to 0.3, and a compressible film (nu 0.3) at mu 0, 0.5, 2 (the edge's
        exponent moves with friction there): edge_noise_wide.csv.
figure  edge_noise.png: the raw error against theta and against t, the corrected error.
"""
from __future__ import annotations

import math
import sys
import time

import numpy as np

from spectral_contact import solve
from spectral_contact.numerics.edges import LATTICE_ERROR_COEFFICIENTS, contact_runs, lattice_error
from spectral_contact.solvers import fft as fft_solver

from ._common import parse, progress, table, write_rows
from .viscoelastic import FILM, SLS, load_for

# (scene name, load [N/m], mu, period [h], N0, reference N)
SCENES = {"paper": (200.0, 2.0, 22.0, 2048, 2**17), "aH/h=1": (load_for(1.0), 0.0, 21.9, 4096, 2**17),
          "aH/h=0.1": (load_for(0.1), 0.0, 21.1, 16384, 2**19)}
FILMS = [("relaxed", 0.0), ("glassy", 0.0), ("sls", 1e-3), ("sls", 0.1), ("sls", 10.0)]
RESOLUTION = [("aH/h=1", 512), ("aH/h=1", 1024), ("aH/h=1", 16384)]  # relaxed, other dx/a
CANONICAL = ("aH/h=1", "relaxed", 0.0, 4096)
WIDE = [  # (name, load, mu, poisson, period, N0)
    ("aH/h=3", load_for(3.0), 0.0, 0.5, 22.503, 256),
    ("aH/h=30", load_for(30.0), 0.0, 0.5, 31.938, 256),
    ("aH/h=30", load_for(30.0), 0.0, 0.5, 31.938, 2048),
    ("aH/h=10 mu 10", load_for(10.0), 10.0, 0.5, 34.884, 128),
    ("aH/h=10 mu 10", load_for(10.0), 10.0, 0.5, 34.884, 1024),
    ("paper nu 0.3 mu 0", 200.0, 0.0, 0.3, 22.0, 2048),
    ("paper nu 0.3 mu 0.5", 200.0, 0.5, 0.3, 22.0, 2048),
    ("paper nu 0.3 mu 2", 200.0, 2.0, 0.3, 22.0, 2048),
]
WIDE_REF = 2**17


def _film(name: str, V: float, poisson: float = 0.5) -> dict:
    f = dict(FILM, poisson=poisson)
    if name == "glassy":
        f["young"] = 2.0 * FILM["young"]
    if name == "sls":
        f.update(speed=V, prony=SLS)
    return f


class _Recorder:
    """The line solver's edge fits, raw (the lattice correction off): per fit call the edges
    and the offsets t of the (single) contact run's right and left edges; per level average
    the last two fits (the grid's and the shifted grid's)."""

    def __init__(self):
        self.fits, self.levels = [], []

    def __enter__(self):
        self._fit, self._avg, self._lat = (fft_solver.fit_edges, fft_solver._average,
                                           fft_solver._lattice_edges)

        def fit(x, dx, gap, pressure, active, trailing=None, lattice=False):
            e = self._fit(x, dx, gap, pressure, active, trailing, False)
            runs = contact_runs(active)
            if len(runs) == 1 and len(e) == 1:
                (first, last), ((left, right),) = runs[0], e
                self.fits.append({"dx": dx, "right": right, "left": left,
                                  "tR": (right - x[last]) / dx, "tL": (x[first] - left) / dx})
            else:
                self.fits.append(None)
            return e

        def avg(q0, q1):
            self.levels.append((self.fits[-2], self.fits[-1]))
            return self._avg(q0, q1)

        fft_solver.fit_edges, fft_solver._average = fit, avg
        fft_solver._lattice_edges = lambda prob, exponential=False: False
        return self

    def __exit__(self, *exc):
        fft_solver.fit_edges, fft_solver._average, fft_solver._lattice_edges = (
            self._fit, self._avg, self._lat)


def fixed(load, mu, film: dict, N: int, L: float) -> dict:
    """One fixed-grid solve (N points over L film thicknesses): its final level's two raw fits
    and the averaged measures (the solver's a, x_c are the corrected ones: recomputed here)."""
    with _Recorder() as rec:
        r = solve(load=load, mu=mu, tol=1e-4, grid_points=N,
                  domain_length=L * film["thickness"], **film)
    f0, f1 = rec.levels[-1]
    if f0 is None or f1 is None:
        raise RuntimeError(f"N = {N}: not one contact run")
    return {"N": N, "dx": L / N, "fits": (f0, f1), "result": r}


def _corrected(f: dict) -> tuple[float, float]:
    """(left, right) of a raw fit less the lattice error."""
    dx = f["dx"]
    return f["left"] + dx * lattice_error(f["tL"]), f["right"] - dx * lattice_error(f["tR"])


def _edges(sol, corrected: bool) -> tuple[float, float]:
    """(left, right) of a solve, the mean of its grid's and shifted grid's fits."""
    pairs = [_corrected(f) if corrected else (f["left"], f["right"]) for f in sol["fits"]]
    return 0.5 * (pairs[0][0] + pairs[1][0]), 0.5 * (pairs[0][1] + pairs[1][1])


def _frac(v: float) -> float:
    return v - math.floor(v)


def case_rows(name: str, load, mu, film: dict, L: float, sizes, n_ref: int, tag: str) -> tuple:
    """The edge rows of one case (every size, both grids, both edges) and the reference."""
    ref = fixed(load, mu, film, n_ref, L)
    lr, rr = _edges(ref, corrected=True)
    a_ref, c_ref = 0.5 * (rr - lr), 0.5 * (rr + lr)
    rows = []
    for N in sizes:
        sol = fixed(load, mu, film, N, L)
        dx = sol["dx"]
        avg = {}
        for corr in (False, True):
            left, right = _edges(sol, corr)
            avg[corr] = ((0.5 * (right - left) - a_ref) / a_ref, (0.5 * (right + left) - c_ref) / a_ref)
        for grid, f in enumerate(sol["fits"]):
            shift = 0.5 * grid  # the shifted grid's nodes sit half a cell to the right
            for side, e, e_ref, t in (("right", f["right"], rr, f["tR"]),
                                      ("left", f["left"], lr, f["tL"])):
                sign = 1.0 if side == "right" else -1.0
                theta = _frac(rr / dx - shift) if side == "right" else _frac(-lr / dx + shift)
                raw = sign * (e - e_ref) / dx
                rows.append({
                    "case": tag, "scene": name, "N": N, "dx_over_a": dx / a_ref, "dx_h": dx,
                    "grid": "shifted" if grid else "grid", "edge": side, "theta": theta,
                    "t_fit": t, "error_raw_cells": raw,
                    "error_corrected_cells": raw - lattice_error(t),
                    "a_error_raw": avg[False][0], "xc_error_raw": avg[False][1],
                    "a_error_corrected": avg[True][0], "xc_error_corrected": avg[True][1]})
    return rows, (a_ref, c_ref)


def _sizes(n0: int, quick: bool) -> list[int]:
    ks = range(0, 33, 8) if quick else range(33)
    return sorted({(n0 + n0 * k // 16) // 2 * 2 for k in ks})


def summarize(rows) -> list[dict]:
    """Per case: raw and corrected rms / max of the edge errors (cells), each edge, and the
    half-cell-averaged a, x_c errors (relative to a)."""
    out = []
    for tag in dict.fromkeys(r["case"] for r in rows):
        rs = [r for r in rows if r["case"] == tag]
        row = {"case": tag, "fits": len(rs),
               "dx_over_a": f"{min(r['dx_over_a'] for r in rs):.1e}-{max(r['dx_over_a'] for r in rs):.1e}"}
        for kind in ("raw", "corrected"):
            for side in ("right", "left"):
                e = np.array([r[f"error_{kind}_cells"] for r in rs if r["edge"] == side])
                row[f"{side}_{kind}_rms"] = float(np.sqrt(np.mean(e * e)))
                row[f"{side}_{kind}_max"] = float(np.max(np.abs(e)))
            per_n = {r["N"]: r for r in rs}.values()
            for q in ("a", "xc"):
                e = np.array([r[f"{q}_error_{kind}"] for r in per_n])
                row[f"{q}_{kind}_rms"] = float(np.sqrt(np.mean(e * e)))
        out.append(row)
    return out


def part_sweep(quick: bool, out, t0) -> list[dict]:
    rows = []
    cases = [(s, f, V) for s in SCENES for f, V in FILMS]
    if quick:
        cases = [("aH/h=1", "relaxed", 0.0), ("aH/h=1", "sls", 10.0)]
    for i, (s, f, V) in enumerate(cases):
        load, mu, L, n0, n_ref = SCENES[s]
        tag = f"{s} {f}" + (f" {V:g} m/s" if f == "sls" else "")
        rows += case_rows(s, load, mu, _film(f, V), L, _sizes(n0, quick), n_ref, tag)[0]
        progress(i + 1, len(cases), tag, t0)
    if not quick:
        for s, n0 in RESOLUTION:
            load, mu, L, _, n_ref = SCENES[s]
            rows += case_rows(s, load, mu, _film("relaxed", 0.0), L, _sizes(n0, False), n_ref,
                              f"{s} relaxed N0={n0}")[0]
    write_rows(rows, out / "edge_noise_sweep.csv", "edge fits against a 16-64x finer reference on "
               "the same period (errors in cells of the coarse grid, outward; a, x_c relative "
               "to a)")
    summary = summarize(rows)
    table(summary, out / "edge_noise_summary.csv", "the edges' error, raw and less the lattice "
          "error (cells), and the averaged a, x_c (relative)")
    return rows


def part_fit(quick: bool, out, t0) -> None:
    """The series from the canonical scene, the reference corrected by it and refitted."""
    s, f, V, n0 = CANONICAL
    load, mu, L, _, n_ref = SCENES[s]
    film = _film(f, V)
    ref = fixed(load, mu, film, n_ref, L)
    sols = [fixed(load, mu, film, N, L) for N in _sizes(n0, quick)]
    cheb = np.polynomial.chebyshev.Chebyshev
    g = None
    for it in range(3):
        if g is None:
            lr, rr = _edges(ref, corrected=False)
        else:
            fr = ref["fits"]
            dxr = ref["dx"]
            rr = np.mean([f_["right"] - dxr * g(f_["tR"]) for f_ in fr])
            lr = np.mean([f_["left"] + dxr * g(f_["tL"]) for f_ in fr])
        t, e = [], []
        for sol in sols:
            dx = sol["dx"]
            for f_ in sol["fits"]:
                t += [f_["tR"], f_["tL"]]
                e += [(f_["right"] - rr) / dx, -(f_["left"] - lr) / dx]
        g = cheb.fit(np.array(t), np.array(e), 4, domain=[-0.25, 1.0])
        res = np.array(e) - g(np.array(t))
        print(f"fit {it}: coefficients {np.round(g.coef, 5).tolist()}, residual rms "
              f"{np.sqrt(np.mean(res ** 2)):.2e} cells over {len(t)} fits", file=sys.stderr)
    print(f"numerics.edges.LATTICE_ERROR_COEFFICIENTS: {list(LATTICE_ERROR_COEFFICIENTS)}; "
          f"max difference from this fit over t in [-0.17, 0.88]: "
          f"{max(abs(g(u) - lattice_error(u)) for u in np.linspace(-0.17, 0.88, 106)):.1e} cells",
          file=sys.stderr)


def part_wide(quick: bool, out, t0) -> None:
    rows = []
    for i, (name, load, mu, nu, L, n0) in enumerate(WIDE[:2] if quick else WIDE):
        tag = f"{name} N0={n0}"
        rs, _ = case_rows(name, load, mu, _film("relaxed", 0.0, nu), L, _sizes(n0, quick),
                          WIDE_REF, tag)
        for lo, hi in ((0.0, 0.04), (0.04, 0.06), (0.06, 0.09), (0.09, 0.13), (0.13, 0.18),
                       (0.18, 0.3)):
            sel = [r for r in rs if lo <= r["dx_h"] < hi]
            if not sel:
                continue
            raw = np.array([r["error_raw_cells"] for r in sel])
            cor = np.array([r["error_corrected_cells"] for r in sel])
            rows.append({"case": tag, "poisson": nu, "mu": mu, "dx_h": f"{lo:g}-{hi:g}",
                         "fits": len(sel), "raw_rms": float(np.sqrt(np.mean(raw ** 2))),
                         "raw_max": float(np.max(np.abs(raw))),
                         "corrected_rms": float(np.sqrt(np.mean(cor ** 2))),
                         "corrected_max": float(np.max(np.abs(cor)))})
        progress(i + 1, len(WIDE), tag, t0)
    table(rows, out / "edge_noise_wide.csv", "the lattice correction's range: edge errors (cells) "
          "by dx/h, raw and corrected")


def part_figure(rows, out) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(16, 5))
    for tag in dict.fromkeys(r["case"] for r in rows):
        rs = [r for r in rows if r["case"] == tag and "N0" not in tag]
        if not rs:
            continue
        ax[0].plot([r["theta"] for r in rs], [r["error_raw_cells"] for r in rs], ".", ms=2,
                   label=tag)
        ax[1].plot([r["t_fit"] for r in rs], [r["error_raw_cells"] for r in rs], ".", ms=2)
        ax[2].plot([r["t_fit"] for r in rs], [r["error_corrected_cells"] for r in rs], ".", ms=2)
    u = np.linspace(-0.17, 0.88, 200)
    ax[1].plot(u, [lattice_error(v) for v in u], "k-", lw=1, label="lattice_error(t)")
    ax[0].set_xlabel("theta: the edge's position in its cell")
    ax[1].set_xlabel("t: the fitted offset beyond the last contact node (cells)")
    ax[2].set_xlabel("t (cells)")
    ax[0].set_ylabel("edge error / dx (outward), raw fit")
    ax[2].set_ylabel("edge error / dx, fit less lattice_error(t)")
    ax[0].legend(fontsize=6)
    ax[1].legend(fontsize=8)
    for a in ax:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "edge_noise.png", dpi=110)


def part_side(quick: bool, out, t0) -> None:
    """The fit on the continuum's gap (the fine solution's, interpolated) at the coarse nodes
    against the fit on the coarse solution's gap: which one carries the error."""
    from spectral_contact.numerics.contact import solve_contact
    from spectral_contact.numerics.edges import _quadratic_fit_root, fit_edges
    from spectral_contact.numerics.grid import Grid
    from spectral_contact.physics.scene import Scene

    load, mu, L, n0, n_ref = SCENES["aH/h=1"]
    scene = Scene(load=load, mu=mu, **FILM)
    film, ind = scene.core_film(), [scene.indenter_object()]

    def contact(n):
        g = Grid.centered(n, L, 0.0)
        return g, solve_contact(g, mu, ind, film=film, rtol=1e-10, accept=1e-8)

    gf, sf = contact(n_ref)
    (_, r_ref), = fit_edges(gf.x, gf.dx, sf.gap, sf.pressure, sf.active, None, True)
    rows = []
    for n in _sizes(n0, quick)[:17]:
        g, s_ = contact(n)
        last = int(np.flatnonzero(s_.active).max())
        xs = g.x[last] + g.dx * np.arange(7)
        cont = np.interp(xs, gf.x, sf.gap)
        t_disc = _quadratic_fit_root(*(max(v, 0.0) ** (2 / 3) for v in s_.gap[last + 2:last + 6]))
        t_cont = _quadratic_fit_root(*(max(v, 0.0) ** (2 / 3) for v in cont[2:6]))
        dep = (s_.gap[last + 1:last + 6] - cont[1:6]) / cont[1:6]
        rows.append({"N": n, "t_fit": t_disc,
                     "error_discrete_gap_cells": (g.x[last] + t_disc * g.dx - r_ref) / g.dx,
                     "error_continuum_gap_cells": (g.x[last] + t_cont * g.dx - r_ref) / g.dx,
                     **{f"gap_departure_node{k + 1}": float(dep[k]) for k in range(5)}})
    table(rows, out / "edge_noise_side.csv", "the right edge's fit on the coarse solution's gap "
          "and on the fine solution's gap at the same nodes (cells); the coarse gap's relative "
          "departure from the fine one at nodes 1-5 outside")


PARTS = ("sweep", "fit", "side", "wide", "figure")


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/edge_noise", extra=lambda p: p.add_argument(
        "--parts", default=",".join(PARTS), help=f"comma-separated, of {', '.join(PARTS)}"))
    parts = [p for p in args.parts.split(",") if p]
    bad = [p for p in parts if p not in PARTS]
    if bad:
        print(f"--parts must be among {', '.join(PARTS)}; got {', '.join(bad)}", file=sys.stderr)
        return 2
    t0 = time.perf_counter()
    rows = part_sweep(args.quick, out, t0) if ("sweep" in parts or "figure" in parts) else []
    if "fit" in parts:
        part_fit(args.quick, out, t0)
    if "side" in parts:
        part_side(args.quick, out, t0)
    if "wide" in parts:
        part_wide(args.quick, out, t0)
    if "figure" in parts:
        part_figure(rows, out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
