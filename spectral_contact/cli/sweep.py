"""The ``sweep`` subcommand: the Cartesian product of scene options on a dask engine.

    spectral-contact sweep --load 20:380:40 --mu 0.3,1,2,3 --out results/ [--workers N |
        --scheduler tcp://HOST:PORT | --serial] [--spec FILE.toml] [--profiles] [--json]

``register(subparsers)`` adds it to the main parser (``cli.main``).  A bad specification (an empty
range, a step <= 0, an unknown option or value, an unreachable scheduler, a missing extra) raises
InputError before any scene is solved (one line, exit 2, nothing written).  Failing scenes are
rows of the table with their status; the command exits 0 once the table is written.  Ctrl-C
exits 130 and keeps every finished scene (rerun the same command to resume).
"""
from __future__ import annotations

import json
import sys

from ..errors import InputError

__all__ = ["register"]


def register(subparsers) -> None:
    """Add ``sweep`` to an argparse subparsers object."""
    from ..sweep import OPTIONS

    p = subparsers.add_parser(
        "sweep", help="solve the Cartesian product of option values (dask engine), one table",
        description="Each option takes a value, a comma list (0.3,1,2) or ranges start:stop:step "
                    "(stop included), SI units; a negative first value needs '=' (--mu=-1,1). "
                    "Writes OUT/summary.csv (+ .parquet with pyarrow) and stores each scene in "
                    "OUT/scenes/ as it finishes: rerunning solves only what is missing.")
    for name, (_kind, _default, unit, text) in OPTIONS.items():  # physics.options' help
        h = f"{','.join(unit)}: {text}" if isinstance(unit, tuple) else text
        p.add_argument(f"--{name.replace('_', '-')}", dest=name, metavar="VALUES", default=None,
                       help=h)
    p.add_argument("--spec", metavar="FILE.toml", default=None,
                   help="options in a TOML file (option = value, list or \"start:stop:step\"); "
                        "options on the command line override it")
    p.add_argument("--out", metavar="DIR", required=True, help="results directory (created)")
    eng = p.add_mutually_exclusive_group()
    eng.add_argument("--workers", type=int, default=None,
                     help="worker processes of a local dask cluster (default: the cores; at most 2 "
                          "per core)")
    eng.add_argument("--scheduler", metavar="tcp://HOST:PORT", default=None,
                     help="a running dask scheduler instead of a local cluster")
    p.add_argument("--scheduler-timeout", type=float, default=10.0, metavar="S",
                   help="seconds to wait for --scheduler before giving up (default 10)")
    eng.add_argument("--serial", action="store_true", help="solve in this process (debugging)")
    p.add_argument("--profiles", action="store_true", help="write OUT/profiles/<key>.csv per scene")
    p.add_argument("--json", action="store_true", help="print one JSON object; no progress bar")
    p.add_argument("--plot", metavar="FILE.png", default=None,
                   help="plot a table column (--plot-y) against an option (--plot-x), one curve "
                        "per value of another option (--plot-group); the ok scenes only")
    p.add_argument("--plot-y", metavar="COLUMN", default="max_pressure_Pa",
                   help="the quantity plotted: a numeric column of summary.csv (default "
                        "max_pressure_Pa)")
    p.add_argument("--plot-x", metavar="OPTION", default=None,
                   help="the abscissa: an option (default: the first option with several values)")
    p.add_argument("--plot-group", metavar="OPTION", default=None,
                   help="one curve per value of this option (default: the second option with "
                        "several values, if any)")
    p.set_defaults(func=_cmd_sweep)


def _plot_axes(args, varying, columns):
    """(x, group) of --plot as table columns (``load`` -> ``load_N_per_m``), checked before any
    work (InputError naming the option); --plot-x/--plot-group take an option or its column."""
    from ..sweep import OPTIONS, column, option_of

    x = args.plot_x if args.plot_x else (varying[0] if varying else None)
    if x is None:
        raise InputError("--plot needs an option with several values (e.g. --load 50:400:50) or "
                         "--plot-x OPTION")
    x = option_of(x) or x
    g = args.plot_group if args.plot_group else next((k for k in varying if k != x), None)
    g = g if g is None else option_of(g) or g
    for opt, v in (("--plot-x", x), ("--plot-group", g)):
        if v is not None and v not in OPTIONS:
            raise InputError(f"{opt} {v}: not an option of sweep (one of "
                             f"{', '.join(o.replace('_', '-') for o in OPTIONS)}, or its column)")
    if g == x:
        raise InputError(f"--plot-group {g} is also --plot-x: give two different options")
    if args.plot_y not in columns:
        raise InputError(f"--plot-y {args.plot_y}: not a column of the table (e.g. "
                         f"max_pressure_Pa, half_width_m, indentation_m, Q_over_P)")
    return column(x), g if g is None else column(g)


def _plot_sweep(df, path, y, x, g):
    """One curve of y against x per value of g (ok scenes), markers at the scenes."""
    import pandas as pd
    from matplotlib.figure import Figure

    ok = df[df["status"] == "ok"].copy()
    ok[y] = pd.to_numeric(ok[y], errors="coerce")
    fig = Figure(figsize=(7, 4.5), layout="constrained")
    ax = fig.subplots()
    groups = [(None, ok)] if g is None else list(ok.groupby(g, sort=True))
    for value, part in groups:
        part = part.sort_values(x)
        ax.plot(part[x], part[y], "o-", ms=4, label=None if g is None else f"{g} = {value:g}"
                if isinstance(value, float) else f"{g} = {value}")
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    n_bad = int((df["status"] != "ok").sum())
    ax.set_title(f"{y} against {x}" + (f", by {g}" if g else "") +
                 (f" ({n_bad} failed scenes not shown)" if n_bad else ""), fontsize=11)
    if g is not None:
        ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.savefig(path, dpi=120)


def _check_spec_not_an_output(spec, out) -> None:
    """--spec must not be one of the files the sweep writes (OUT/summary.*, OUT/scenes/,
    OUT/profiles/): it is read, they are replaced."""
    if spec is None:
        return
    import os

    from .files import _identity

    for name in ("summary.csv", "summary.parquet"):
        if _identity(spec) & _identity(os.path.join(out, name)):
            raise InputError(f"--spec {spec} is {os.path.join(out, name)}, which the sweep "
                             f"writes: give another path")
    real, base = os.path.realpath(spec), os.path.realpath(out)
    for sub in ("scenes", "profiles"):
        if os.path.commonpath([real, os.path.join(base, sub)]) == os.path.join(base, sub):
            raise InputError(f"--spec {spec} is inside {os.path.join(out, sub)}, which the sweep "
                             f"writes: give another path")


def _cmd_sweep(args) -> int:
    from ..sweep import OPTIONS, STATUSES, WORKERS_PER_CORE, max_workers, sweep

    if args.workers is not None and not 1 <= args.workers <= max_workers():
        raise InputError(f"--workers must be in [1, {max_workers()}] ({WORKERS_PER_CORE} per "
                         f"usable core); got {args.workers}")
    if not args.out.strip():
        raise InputError("--out: empty folder name")
    _check_spec_not_an_output(args.spec, args.out)
    if not args.scheduler_timeout > 0:
        raise InputError(f"--scheduler-timeout must be > 0 s; got {args.scheduler_timeout}")
    options = {k: getattr(args, k) for k in OPTIONS if getattr(args, k) is not None}
    plot_axes = None
    if args.plot is not None:  # checked before any work
        from ..sweep import parse_values, plan, table_columns
        from .files import check_outputs, check_plot_path

        check_outputs(inputs={"--spec": args.spec}, **{"--plot": args.plot})
        check_plot_path(args.plot)
        plan(args.spec, **options)  # the specification's own errors first
        given = dict(options)
        if args.spec:
            from ..sweep import read_spec

            given = {**read_spec(args.spec), **given}
        varying = [k for k in OPTIONS if k in given and len(parse_values(k, given[k])) > 1]
        plot_axes = _plot_axes(args, varying, table_columns())
    info = {}
    try:
        df = sweep(args.spec, out=args.out, engine="serial" if args.serial else "local",
                   workers=args.workers, scheduler=args.scheduler,
                   scheduler_timeout=args.scheduler_timeout, profiles=args.profiles,
                   progress=not args.json, info=info, **options)
    except KeyboardInterrupt:
        print(f"interrupted: finished scenes are kept in {args.out}/scenes; rerun the same "
              "command to resume", file=sys.stderr)
        return 130
    from pathlib import Path

    out = Path(args.out)
    parquet = out / "summary.parquet"
    rec = {"scenes": info["scenes"], "reused": info["reused"], "solved": info["solved"],
           "statuses": info["statuses"], "engine": info["engine"],
           "elapsed_s": info["elapsed_s"], "summary_csv": str(out / "summary.csv"),
           "summary_parquet": str(parquet) if parquet.is_file() else None,
           "profiles": str(out / "profiles") if args.profiles else None}
    if plot_axes is not None:
        from .files import Outputs

        with Outputs() as outs:
            _plot_sweep(df, outs.path(args.plot), args.plot_y, *plot_axes)
        rec["plot"] = args.plot
    if args.json:
        print(json.dumps(rec, indent=2))
    else:
        counts = ", ".join(f"{info['statuses'][s]} {s}" for s in STATUSES if info["statuses"][s])
        print(f"{len(df)} scenes: {counts} ({info['reused']} reused, {info['solved']} solved"
              f"{', ' + info['engine'] if info['solved'] else ''}, {info['elapsed_s']:.1f} s); "
              f"wrote {rec['summary_csv']}" + (f" and {parquet}" if rec["summary_parquet"] else ""))
    return 0
