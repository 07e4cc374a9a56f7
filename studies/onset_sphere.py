"""The stick zone of a sphere on the paper's film under a growing tangential load, against
Mindlin's circle c = a (1 - Q/(mu P))^(1/3).

    python -m studies.onset_sphere [--quick] [--sizes 0.3,1,2] [--steps N] [--out DIR]

The reference: Mindlin (1949), J. Appl. Mech. 16, 259; Johnson, Contact Mechanics (1985),
sect. 7.2 (eq. 7.44): a half-space, the slip assumed along Q; at nu = 1/2 the normal and
tangential problems decouple on a half-space and the stick zone stays a circle centred on the
contact (Munisamy, Hills & Nowell 1994 found the exact, solved-direction one nearly circular).
On the bonded film they couple.  Spheres of Hertz radius a_H/h = 0.3, 1 (and 2) on the paper's
film (E = 2.2 MPa, R = 130 mm, h = 2 mm), mu = 1, 10 frictional loading steps, N tangential
steps, tol 1e-2 (the grid from ``onset``'s estimate): per step the stick zone's area, its
radius sqrt(area/pi) over the contact radius a (sub-grid, ``measure_contact_2d``), its
ellipticity (sqrt of the x and y second moments' ratio of its nodes: > 1 longer along Q), its
centroid's offset from the pressure centroid along x (over a), and Mindlin's c/a.

``onset_sphere.csv``; ``onset_sphere.png`` (stick radius over a against Q/(mu P)).
"""
from __future__ import annotations

import math
import time

import numpy as np

from spectral_contact import onset
from spectral_contact.physics.scene import Scene3D

from ._common import parse, progress, table

FILM = {"young": 2.2e6, "thickness": 0.002, "radius": 0.130}


def sphere_for(s: float) -> Scene3D:
    """The paper's film with the sphere force whose Hertz radius is s film thicknesses
    (a^3 = 3 P R / (4 E*), E* = E / (1 - nu^2) = 4 E / 3 at nu = 1/2)."""
    a = s * FILM["thickness"]
    force = 4.0 * (4.0 * FILM["young"] / 3.0) * a ** 3 / (3.0 * FILM["radius"])
    return Scene3D(indenter="sphere", force=force, mu=1.0, **FILM)


def rows_for(s: float, steps: int) -> list[dict]:
    r = onset(sphere_for(s), steps=steps)
    g = r.grid
    x, y = (np.broadcast_to(c, g.shape) for c in g.coordinates())
    rows = []
    for k, m in enumerate(r.measures):
        stick = r.states[k].stick.reshape(g.shape)
        a = m["radius"]
        ell = off = math.nan
        if stick.sum() > 2:
            xs, ys = x[stick], y[stick]
            ell = math.sqrt(xs.var() / ys.var()) if ys.var() > 0 else math.nan
            off = (xs.mean() - m["xc"]) / a
        q = float(r.Q_over_muP[k])
        rows.append({"a_H_over_h": s, "step": k, "Q_over_muP": q, "grid_points": g.shape[0],
                     "contact_radius_over_h": a, "stick_area_over_h2": m["stick_area"],
                     "stick_radius_over_a": m["stick_radius"] / a,
                     "mindlin_c_over_a": (1.0 - q) ** (1.0 / 3.0),
                     "ellipticity_x_over_y": ell, "stick_offset_over_a": off,
                     "error_estimate": r.error_estimates[k],
                     "stick_error_estimate": r.stick_error_estimates[k],
                     "load_step_error_estimate": r.load_step_estimates[k]})
    return rows


def _options(p):
    p.add_argument("--sizes", default=None,
                   help="a_H/h values, comma-separated (default 0.3,1,2; --quick 0.3,1)")
    p.add_argument("--steps", type=int, default=None,
                   help="tangential steps (default 10; --quick 5)")


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/onset_sphere", extra=_options)
    t0 = time.perf_counter()
    sizes = (0.3, 1.0) if args.quick else (0.3, 1.0, 2.0)
    if args.sizes:
        sizes = tuple(float(v) for v in args.sizes.split(","))
    steps = args.steps or (5 if args.quick else 10)
    rows = []
    for i, s in enumerate(sizes):
        rows += rows_for(s, steps)
        progress(i + 1, len(sizes), f"a_H/h = {s:g}", t0)
    table(rows, out / "onset_sphere.csv", "a sphere's stick zone against Mindlin's circle on "
          "the paper's film, mu = 1 (lengths over the contact radius a)")
    _plot(rows, out / "onset_sphere.png")
    return 0


def _plot(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6, 4), layout="constrained")
    ax = fig.subplots()
    q = np.linspace(0, 1, 101)
    ax.plot(q, (1 - q) ** (1 / 3), "k--", lw=1, label="Mindlin (1 - Q/muP)^(1/3)")
    for s in sorted({r["a_H_over_h"] for r in rows}):
        sel = [r for r in rows if r["a_H_over_h"] == s and r["step"] > 0]
        ax.plot([r["Q_over_muP"] for r in sel], [r["stick_radius_over_a"] for r in sel], "o-",
                ms=3, label=f"a_H/h = {s:g}")
    ax.set_xlabel("Q / (mu P)")
    ax.set_ylabel("stick radius sqrt(A/pi) / a")
    ax.legend(fontsize=7)
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    raise SystemExit(main())
