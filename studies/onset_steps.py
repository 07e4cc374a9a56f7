"""Does the onset's load-step estimate bound the load steps' true error?

    python -m studies.onset_steps [--quick] [--out DIR]

The incremental solution depends on the step size; ``load_step_error_estimate`` (each step's
share of ``error_estimate``, ``solvers.onset_core.load_step_estimates``) is 1.5 x the
difference to the same loading with half the steps (on the coarse grid).  Here, on one fixed
grid per scene, runs of N = 4, 8, 16 tangential steps (N/2 frictional loading steps) are
compared with N = 64 (32 loading steps) at their common Q/(mu P): the "true" error is the
largest relative difference of the estimate's measures (contact size, centre over the size,
indentation, peak pressure, tangential displacement over its largest value) against the
reference, times 64/(64 - N) (first order in the step: the reference's own error removed).

``onset_steps.csv``: scene, N, step, Q/(mu P), estimate, true error, their ratio.
"""
from __future__ import annotations

import time

from spectral_contact import Scene, onset
from spectral_contact.physics.scene import Scene3D
from spectral_contact.solvers.onset import _differences as line_differences
from spectral_contact.solvers.onset3d import _differences as surface_differences

from ._common import parse, progress, table
from .onset import scene_for

REF = 64


class _M:
    def __init__(self, measures):
        self.measures = measures


def rows_for(name, scene, differences, grid_points, counts, ref_steps=REF):
    ref = onset(scene, steps=ref_steps, loading_steps=ref_steps // 2, grid_points=grid_points)
    out = []
    for n in counts:
        r = onset(scene, steps=n, loading_steps=max(1, n // 2), grid_points=grid_points)
        stride = ref_steps // n
        true, _ = differences(_M(ref.measures[::stride]), _M(r.measures))
        for k, (e, t) in enumerate(zip(r.load_step_estimates, true)):
            t *= ref_steps / (ref_steps - n)
            out.append({"scene": name, "steps": n, "loading_steps": max(1, n // 2), "step": k,
                        "Q_over_muP": float(r.Q_over_muP[k]), "estimate": e, "true_error": t,
                        "ratio": e / t if t > 0 else float("inf"),
                        "grid_points": grid_points})
    return out


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/onset_steps")
    t0 = time.perf_counter()
    counts = (4, 8) if args.quick else (4, 8, 16)
    rows = rows_for("paper line (200 N/m, mu 2)", Scene(), line_differences, 2048, counts)
    progress(1, 3, "paper line", t0)
    rows += rows_for("line a_H/h 0.3, mu 1", scene_for(0.3, 1.0), line_differences, 2048,
                     counts)
    progress(2, 3, "small line", t0)
    rows += rows_for("sphere 1 N, mu 1", Scene3D(indenter="sphere", force=1.0, mu=1.0),
                     surface_differences, 64, (4, 8), ref_steps=32)
    progress(3, 3, "sphere", t0)
    table(rows, out / "onset_steps.csv", "load-step estimate against the true load-step error "
          "(relative, the estimate's measures; reference 64 steps, sphere 32)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
