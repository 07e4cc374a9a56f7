"""Does the default sphere's onset estimate bound its true error?  Against finer references.

    python -m studies.onset_reference [--quick] [--out DIR]

``onset(indenter="sphere", force=1.0, mu=1.0, steps=20)`` at its defaults (20 loading and 20
tangential steps, tol 1e-2: 256^2 points, its estimate 1.5 x the 128^2 / 256^2 difference +
the load steps' share on 128^2 + the periodic images' bound), then the same loading on the same
domain (``solvers.onset3d.loading_runner``): on twice the points per axis (the grid's
reference), with 4 x the steps (80 + 80: the load steps' reference) and both (the full
reference; not with ``--quick``).  Per step the "true" error is the largest relative difference
of the estimate's measures (contact radius, centroid over the radius, indentation, peak
pressure, tangential displacement over its largest value) against a reference, at the common
Q/(mu P); the references' own errors are not removed.

``onset_reference.csv``: step, Q/(mu P), the estimate and its load-step share, the true errors
against the three references, estimate / true error.
"""
from __future__ import annotations

import time

from spectral_contact import onset
from spectral_contact.physics.scene import Scene3D
from spectral_contact.solvers.onset3d import _differences, loading_runner

from ._common import parse, progress, table

STEPS, FINER = 20, 4


class _M:
    def __init__(self, measures):
        self.measures = measures


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/onset_reference")
    t0 = time.perf_counter()
    scene = Scene3D(indenter="sphere", force=1.0, mu=1.0)
    r = onset(scene, steps=STEPS)
    n = r.grid.shape[0]
    path = list(r.Q_over_muP[1:])
    fine_path = [k / (FINER * STEPS) for k in range(1, FINER * STEPS + 1)]
    run = loading_runner(scene, path, r.tol)[0]
    refs = {"grid": (2 * n, path, STEPS), "steps": (n, fine_path, FINER * STEPS)}
    if not args.quick:
        refs["both"] = (2 * n, fine_path, FINER * STEPS)
    true = {}
    for i, (name, (npts, p, ls)) in enumerate(refs.items()):
        ref = run(npts, p, ls)
        stride = len(p) // STEPS
        true[name] = _differences(_M(r.measures), _M(ref.measures[::stride]))[0]
        progress(i + 1, len(refs), f"{name}: {npts}^2, {ls} + {len(p)} steps", t0)
    rows = []
    for k, q in enumerate(r.Q_over_muP):
        e = r.error_estimates[k]
        row = {"step": k, "Q_over_muP": float(q), "grid_points": n, "estimate": e,
               "load_step_estimate": r.load_step_estimates[k]}
        for name, t in true.items():
            row[f"true_{name}"] = t[k]
        t = true.get("both", [a + b for a, b in zip(true["grid"], true["steps"])])[k]
        row["estimate_over_true"] = e / t if t > 0 else float("inf")
        rows.append(row)
    table(rows, out / "onset_reference.csv", "the default sphere's estimate against the true "
          "error (references: 2 x the points, 4 x the steps, both)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
