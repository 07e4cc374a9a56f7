"""The paper's scene (``solve()``: FFT, tol 1e-4), warm: time, CPU time, FFT pairs, true error.

    python -m studies.speed_paper_scene [--quick] [--out DIR] [--runs N] [--before ROOT]

Medians of N (default 21, --quick 11) warm runs of ``spectral_contact.solve()`` in this process:
wall time (time.perf_counter) and CPU time (time.process_time), the FFT pairs, and the true error
(the solver's metric: max relative difference of a, x_c (over a), d, p_max) against the Abel
method at tol 1e-10, with the solver's error estimate beside it.  ``--before ROOT`` also loads
the package under ROOT/spectral_contact (another checkout, e.g. ``git worktree add /tmp/b main``)
under another name and interleaves its runs with this one's, alternating which goes first (the
same load on a shared machine for both: the ratio is the figure to quote).  On a loaded machine
the absolute times are not the targets' (issue 13: <= 3 ms on a quiet core); rerun quiet.
Writes speed_paper_scene.csv.
"""
from __future__ import annotations

import argparse
import gc
import importlib.util
import statistics
import sys
import time
from pathlib import Path

import spectral_contact

from ._common import table


def load_other(root: str, name: str = "spectral_contact_before"):
    """The package under ROOT/spectral_contact, imported as ``name`` (relative imports inside it
    resolve within it)."""
    pkg = Path(root) / "spectral_contact"
    spec = importlib.util.spec_from_file_location(name, pkg / "__init__.py",
                                                  submodule_search_locations=[str(pkg)])
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


def error(r, ref) -> float:
    a = abs(ref.half_width)
    return max(abs(r.half_width - ref.half_width) / a, abs(r.center - ref.center) / a,
               abs(r.indentation - ref.indentation) / abs(ref.indentation),
               abs(r.max_pressure - ref.max_pressure) / ref.max_pressure)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="11 runs")
    p.add_argument("--runs", type=int, default=None, help="warm runs per version (>= 11)")
    p.add_argument("--before", default=None, help="root of another checkout to compare with")
    p.add_argument("--out", default="out/speed_paper_scene")
    args = p.parse_args(argv)
    runs = args.runs or (11 if args.quick else 21)
    if runs < 11:
        print(f"--runs must be >= 11 (got {runs})", file=sys.stderr)
        return 2
    versions = {"this": spectral_contact}
    if args.before:
        versions["before"] = load_other(args.before)
    ref = spectral_contact.solve(method="abel", tol=1e-10)
    wall = {k: [] for k in versions}
    cpu = {k: [] for k in versions}
    last = {}
    for m in versions.values():  # warm: plans, caches
        m.solve()
        m.solve()
    gc.disable()
    order = list(versions.items())
    try:
        for _ in range(runs):
            for k, m in order:  # interleaved
                c0, t0 = time.process_time(), time.perf_counter()
                last[k] = m.solve()
                wall[k].append(time.perf_counter() - t0)
                cpu[k].append(time.process_time() - c0)
            order.reverse()  # each version first in every other run: no position effect
    finally:
        gc.enable()
    rows = []
    for k in versions:
        r = last[k]
        rows.append({"version": k, "runs": runs,
                     "wall_ms": 1e3 * statistics.median(wall[k]),
                     "cpu_ms": 1e3 * statistics.median(cpu[k]),
                     "fft_pairs": r.info["fft_pairs"], "grid_points": r.grid_points,
                     "levels": len(r.info["levels"]),
                     "error_estimate": r.error_estimate, "true_error": error(r, ref),
                     "ratio": r.error_estimate / max(error(r, ref), 1e-300)})
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    table(rows, out / "speed_paper_scene.csv",
          "paper scene, solve() (FFT, tol 1e-4), warm medians; true error against abel tol 1e-10")
    if "before" in wall:
        per_run = statistics.median(a / b for a, b in zip(cpu["this"], cpu["before"]))
        print(f"this / before: wall {rows[0]['wall_ms'] / rows[1]['wall_ms']:.3f}, "
              f"cpu {rows[0]['cpu_ms'] / rows[1]['cpu_ms']:.3f} (median of the runs' own "
              f"ratios {per_run:.3f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
