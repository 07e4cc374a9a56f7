"""The onset of sliding's speed: the issue's targets, 20 steps of the paper's line scene under
1 s of solving and a sphere's 20 steps at 256^2 under 10 s.

    python -m studies.onset_speed [--quick] [--out DIR]

Per case: ``spectral_contact.onset`` at its defaults (20 tangential steps, 20 frictional loading
steps, tol 1e-2; the grid from the estimate), the median, minimum and maximum of this process's
CPU time over warm runs (single-threaded: the solving time, less a shared machine's waits) and
the wall time's median; the counters (FFT pairs: one real transform pair of one field, forward
and back; active-set and GMRES iterations); one FFT pair of the final grid timed in the same run
(the partial-slip operator's batched transform of its 1 + D fields, over 1 + D; a surface's on
the last state's band of contact rows, as the solver runs it) and the CPU time in units of it;
the load average (``os.getloadavg``) before and after.  The line is also run at tol 1e-3
(flagged: the load steps' share).  ``--quick``: one warm run each, the sphere on a fixed
128^2 grid.

``onset_speed.csv``.
"""
from __future__ import annotations

import os
import statistics
import time

import numpy as np

from spectral_contact import Scene, onset

from ._common import parse, progress, table


def _pair_time(r) -> float:
    """One FFT pair (one field) on ``r``'s final grid: the operator's batched transform of its
    1 + D fields (the last step's tractions; a surface's on their band of rows), median of
    5 x 50, over 1 + D."""
    from spectral_contact.numerics.partial_slip import PartialSlipOperator

    op = PartialSlipOperator(r.grid)
    buf = op._plan[0].reshape(op.m, -1)
    s = r.states[-1]
    rows = op.band(np.flatnonzero(s.contact)) if op.ndim == 2 else None
    ts = []
    for _ in range(6):
        buf[0] = s.p
        buf[1:] = s.q.reshape(op.m - 1, -1)
        t = time.process_time()
        for _ in range(50):
            op.transform(op.M, rows)
        ts.append((time.process_time() - t) / 50)
    return statistics.median(ts[1:]) / op.m


def case(name: str, fn, repeats: int) -> dict:
    load0 = os.getloadavg()[0]
    r = fn()  # warm (plans, symbols)
    cpu, wall = [], []
    for _ in range(repeats):
        c, w = time.process_time(), time.perf_counter()
        r = fn()
        cpu.append(time.process_time() - c)
        wall.append(time.perf_counter() - w)
    pair = _pair_time(r)
    c = r.counters
    cpu_med = statistics.median(cpu)
    shape = r.grid.shape
    return {"case": name, "grid_points": "x".join(str(n) for n in shape), "steps": r.n_steps,
            "loading_steps": r.loading_steps, "tol": r.tol,
            "tolerance_met": r.tolerance_met, "error_estimate": max(r.error_estimates),
            "load_step_error_estimate": max(r.load_step_estimates),
            "fft_pairs": c["fft_pairs"], "active_set_iterations": c["iterations"],
            "gmres_iterations": c["krylov_iterations"], "repeats": repeats,
            "median_cpu_s": cpu_med, "min_cpu_s": min(cpu), "max_cpu_s": max(cpu),
            "median_wall_s": statistics.median(wall), "fft_pair_us": pair * 1e6,
            "cpu_over_fft_pair": cpu_med / pair,
            "fft_share_of_cpu": c["fft_pairs"] * pair / cpu_med,
            "load_average_before": load0, "load_average_after": os.getloadavg()[0]}


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/onset_speed")
    t0 = time.perf_counter()
    repeats = 1 if args.quick else 3
    sphere = {"indenter": "sphere", "force": 1.0, "mu": 1.0, "steps": 20}
    if args.quick:
        sphere["grid_points"] = 128
    cases = [("paper line (200 N/m, mu 2), defaults", lambda: onset(Scene(), steps=20)),
             ("paper line, tol 1e-3", lambda: onset(Scene(), steps=20, tol=1e-3)),
             ("sphere 1 N, mu 1, defaults" + (" (128^2 fixed)" if args.quick else ""),
              lambda: onset(**sphere))]
    rows = []
    for i, (name, fn) in enumerate(cases):
        rows.append(case(name, fn, repeats))
        progress(i + 1, len(cases), name, t0)
    table(rows, out / "onset_speed.csv", "onset speed: CPU medians of warm runs, counters, one "
          "FFT pair timed in the same run, load average")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
