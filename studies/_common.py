"""Shared plumbing of the studies: arguments, output folder, progress, table + CSV."""
from __future__ import annotations

import argparse
import csv
import json
import statistics
import sys
import time
from pathlib import Path


def float_list(text: str, option: str, what: str, zero: bool = False) -> tuple:
    """'0.8,1' -> (0.8, 1.0); one line naming ``option`` and exit 2 unless each is a finite
    number > 0 (>= 0 with ``zero``); ``what``: how the message names them."""
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if not values or not all((0.0 <= v if zero else 0.0 < v) and v < float("inf")
                             for v in values):
        print(f"{option} must be a comma list of {what}; got {text!r}", file=sys.stderr)
        raise SystemExit(2)
    return values


def parse(argv, description: str, default_out: str, engine: bool = False, extra=None):
    """Arguments --quick, --out; with ``engine`` also --workers N / --serial (studies whose
    points run through ``spectral_contact.sweep.map_tasks``); ``extra(parser)`` adds a study's
    own."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--quick", action="store_true", help="small version (under a minute), for CI")
    p.add_argument("--out", default=default_out, help=f"output folder (default {default_out})")
    if extra is not None:
        extra(p)
    if engine:
        g = p.add_mutually_exclusive_group()
        g.add_argument("--workers", type=int, default=None,
                       help="dask LocalCluster worker processes (default: the cores; serial "
                            "without dask.distributed)")
        g.add_argument("--serial", action="store_true", help="run every point in this process")
    args = p.parse_args(argv)
    if engine and args.workers is not None and args.workers < 1:
        print(f"--workers must be >= 1; got {args.workers}", file=sys.stderr)
        raise SystemExit(2)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    return args, out


def run_points(args, module: str, func: str, items, unit: str) -> list:
    """``[module.func(item) for item in items]`` through ``spectral_contact.sweep.map_tasks``
    (its progress bar on stderr), in the order of ``items``.

    The engine: --serial, or --quick without --workers, runs in this process (a LocalCluster's
    start-up would cost more than a quick study's solves, and keeps the test suite fast);
    otherwise a dask LocalCluster of --workers processes (default the cores; in this process
    without dask.distributed).  The function is looked up in the importable module (pickled by
    reference, also when the study runs as ``python -m studies.NAME``, i.e. as __main__); the
    results do not depend on the engine (each point is one deterministic function call).
    """
    import importlib

    from spectral_contact.sweep import map_tasks

    fn = getattr(importlib.import_module(module), func)
    serial = args.serial or (args.quick and args.workers is None)
    return map_tasks(fn, list(items), engine="serial" if serial else "auto",
                     workers=args.workers, unit=unit)


def progress(i: int, n: int, label: str, t0: float) -> None:
    print(f"  [{i}/{n}] {label}  ({time.perf_counter() - t0:.1f} s)", file=sys.stderr, flush=True)


def write_rows(rows: list[dict], path: Path, title: str | None = None) -> None:
    """Rows as a plain CSV (one header row, no comments: ``pandas.read_csv(path)`` and
    ``numpy.genfromtxt(path, delimiter=',', names=True)`` open it as it is; numpy does not read
    quotes, so commas inside text cells are written as ';'); the title, which says the units
    (h, E h/6R, ... unless the column name has an SI suffix), goes to ``NAME.meta.json``."""
    cols = list(rows[0])
    with path.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=cols)
        w.writeheader()
        w.writerows([{k: v.replace(",", ";") if isinstance(v, str) else v for k, v in r.items()}
                     for r in rows])
    if title:
        meta = path.with_name(path.stem + ".meta.json")
        meta.write_text(json.dumps({"title": title, "columns": cols, "units": UNITS_NOTE}, indent=2)
                        + "\n", encoding="utf-8")


UNITS_NOTE = ("unless a column name ends in an SI unit (_m, _mm, _Pa, _s, ...): lengths in film "
              "thicknesses h, stresses in E h / 6R, displacements in h^2 / 2R, loads "
              "P = 6 P_L R / (E h^2); errors relative")


def table(rows: list[dict], path: Path, title: str) -> None:
    """Print rows as an aligned table and write them as CSV (``write_rows``)."""
    cols = list(rows[0])
    write_rows(rows, path, title)

    def fmt(v):
        return f"{v:.4g}" if isinstance(v, float) else str(v)

    width = {c: max(len(c), *(len(fmt(r[c])) for r in rows)) for c in cols}
    print(title)
    print("  ".join(c.rjust(width[c]) for c in cols))
    for r in rows:
        print("  ".join(fmt(r[c]).rjust(width[c]) for c in cols))
    print(f"(written {path})")


def median_time(fn, repeats: int, warm: bool = False) -> float:
    """Median wall time [s] of ``repeats`` calls of fn(); one untimed call first if ``warm``."""
    if warm:
        fn()
    ts = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts)
