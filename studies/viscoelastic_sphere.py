"""The viscoelastic sphere's cost against the elastic one at tol 1e-3, and why some speeds
need a finer grid (issue 23: "at most 3x"; ninth session).

    python -m studies.viscoelastic_sphere [--quick] [--out DIR] [--parts cost,levels]
        [--films SLS,tan0.1] [--mus 2,0] [--forces 1] [--speeds 1e-4,...]

cost    the command line's default sphere (F = 1 N, mu 2 = the default, and mu 0; tol 1e-3,
        the surfaces' default) on the SLS E_1 = E_inf and the SLS of peak loss tangent 0.1
        (tau 10 ms), 1e-4 ... 1 m/s: CPU-time ratio viscoelastic / elastic (E_inf), fastest
        of 3 warm interleaved runs, each pair in a child process
        (``viscoelastic.part_sphere_beyond_cost``, its table
        ``viscoelastic_sphere_beyond_cost_tol0.001_<films>_mu<mus>_V<speeds>.csv``).
levels  the automatic solve's levels (locator, period, grids: ``solvers.fft3d``) fixed, each
        solved on its grid and on the grid shifted by half a cell along x and y; per measure
        of the estimate (radius sqrt(A/pi), centroid x_c, indentation d, line load at y = 0,
        p_max) the error of the grid, of the shifted grid (its line load is on the row
        nearest y = 0, half a cell off it) and of their mean against the
        finest level's grid times 2 per axis, the levels' difference (the estimate) and the
        shift difference.  Which error the estimate carries, and whether the grid the elastic
        sphere stops on is within tol for the viscoelastic one (the 1 N frictionless sphere at
        1 cm/s, SLS: ``viscoelastic_sphere_levels_V0.01_mu0.csv``).
"""
from __future__ import annotations

import math
import sys
import time

from spectral_contact.api import make_scene
from spectral_contact.numerics.grid import Grid
from spectral_contact.solvers import fft3d
from spectral_contact.solvers.fft_driver import Problem

from ._common import float_list, parse, progress, table
from .viscoelastic import FILM, SLS, SPHERE_FILMS, part_sphere_beyond_cost

PARTS = ("cost", "levels")
FILMS = tuple(name for name, _ in SPHERE_FILMS)  # part_sphere_beyond_cost's
SPEEDS = (1e-4, 1e-3, 1e-2, 5e-2, 0.1, 0.2, 0.3, 1.0)
_MEASURES = ("radius", "x_c", "d", "line_load_y0", "p_max")


def _values(q: dict) -> dict:
    return {"radius": math.sqrt(max(q["area"], 0.0) / math.pi), "x_c": q["xc"],
            "d": q["indentation"], "line_load_y0": q["line_load_y0"], "p_max": q["pmax"]}


def part_levels(quick: bool, out, t0, speed=1e-2, mu=0.0, force=1.0, prony=SLS) -> list[dict]:
    """The levels of the automatic sphere solve at ``speed`` (module docstring), against the
    finest level's grid doubled per axis on the same period and centre."""
    kw = dict(indenter="sphere", force=force, mu=mu, **FILM)
    if speed:
        kw |= dict(speed=speed, prony=prony)
    prob = Problem(make_scene(**kw), "exact", 1e-3, adaptive=True)
    prob.rtol = max(1e-10, 1e-4 * prob.accept)  # as solve_fft3d
    steps = fft3d._SurfaceSolve(prob, None, None)
    steps.n0, steps.L0 = steps.locator_grid()
    L, center, widths = steps.period(steps.locate())
    shapes = steps.level_shapes(L, widths)[:2 if quick else 3]

    def measure(shape, shift: int) -> dict:
        dx, dy = (length / n for length, n in zip(L, shape))
        g = Grid.centered(shape, L, (center[0] + 0.5 * shift * dx, center[1] + 0.5 * shift * dy))
        return _values(steps.solve_level(g, None).q)

    ref = measure(tuple(2 * n for n in shapes[-1]), 0)
    scale = {"radius": ref["radius"], "x_c": ref["radius"], "d": abs(ref["d"]),
             "line_load_y0": abs(ref["line_load_y0"]), "p_max": ref["p_max"]}
    rows, prev = [], None
    for shape in shapes:
        q0, q1 = measure(shape, 0), measure(shape, 1)
        for k in _MEASURES:
            mean = 0.5 * (q0[k] + q1[k])
            rows.append({
                "speed_m_per_s": speed, "mu": mu, "force_N": force, "nx": shape[0],
                "ny": shape[1], "measure": k,
                "error_grid": abs(q0[k] - ref[k]) / scale[k],
                "error_shifted": abs(q1[k] - ref[k]) / scale[k],
                "error_mean": abs(mean - ref[k]) / scale[k],
                "shift_difference": abs(q0[k] - q1[k]) / scale[k],
                "level_difference": abs(q0[k] - prev[0][k]) / scale[k] if prev else math.nan,
                "mean_level_difference": abs(mean - prev[1][k]) / scale[k] if prev else math.nan})
        prev = (q0, {k: 0.5 * (q0[k] + q1[k]) for k in _MEASURES})
        progress(len(rows) // len(_MEASURES), len(shapes), f"V={speed:g} {shape}", t0)
    table(rows, out / f"viscoelastic_sphere_levels_V{speed:g}_mu{mu:g}.csv",
          f"Viscoelastic sphere (F = {force:g} N, mu {mu:g}, SLS, V = {speed:g} m/s, tol 1e-3): "
          f"the automatic levels fixed, grid and half-cell shifted grid, relative errors against "
          f"the finest level x 2 per axis ({2 * shapes[-1][0]} x {2 * shapes[-1][1]})")
    return rows


def main(argv=None) -> int:
    def extra(p):
        p.add_argument("--parts", default="cost,levels", help="comma list of cost, levels")
        p.add_argument("--films", default="SLS,tan0.1",
                       help="cost: the films (SLS, tan0.1, E1=3Einf, E1=10Einf)")
        p.add_argument("--mus", default="2,0", help="cost: friction coefficients (default 2,0)")
        p.add_argument("--forces", default="1", help="cost: loads [N] (default 1)")
        p.add_argument("--speeds", default=",".join(f"{v:g}" for v in SPEEDS),
                       help="cost: speeds [m/s] (--quick: the first two)")
        p.add_argument("--level-speed", default="0.01", help="levels: the speed [m/s]")

    args, out = parse(argv, __doc__.splitlines()[0], "out/viscoelastic", extra=extra)
    parts = args.parts.split(",")
    if any(p not in PARTS for p in parts):
        print(f"--parts must be a comma list of {', '.join(PARTS)}; got {args.parts!r}",
              file=sys.stderr)
        return 2
    films = [f for f in args.films.split(",") if f]
    if not films or any(f not in FILMS for f in films):
        print(f"--films must be a comma list of {', '.join(FILMS)}; got {args.films!r}",
              file=sys.stderr)
        return 2
    mus = float_list(args.mus, "--mus", "numbers >= 0", zero=True)
    forces = float_list(args.forces, "--forces", "numbers > 0")
    speeds = float_list(args.speeds, "--speeds", "numbers > 0")
    level_speed = float_list(args.level_speed, "--level-speed", "numbers >= 0", zero=True)[0]
    t0 = time.perf_counter()
    if "cost" in parts:
        part_sphere_beyond_cost(args.quick, out, t0, (1e-3,), films,
                                forces, mus, speeds[:2] if args.quick else speeds)
    if "levels" in parts:
        part_levels(args.quick, out, t0, level_speed, 0.0)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
