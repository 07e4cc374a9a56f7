"""``sweep(...)``: the scenes planned and checked, the stored ones reused, the rest solved on an
engine, the table returned and written (see the package docstring)."""
from __future__ import annotations

import sys
import time

from ..errors import InputError
from .cluster import (
    WORKERS_PER_CORE,
    check_workers,
    connect_scheduler,
    default_workers,
    local_client,
    max_workers,
    need_dask,
)
from .engine import _Progress, _run_dask, _run_serial
from .store import Store, write_profile_index, write_tables
from .table import EXTRA, STATUSES, plan, scene_key, table_columns

__all__ = ["sweep"]


def _need_pandas():
    try:
        import pandas
    except ModuleNotFoundError:
        raise InputError(f"the sweep returns a pandas table: {EXTRA}") from None
    return pandas


def sweep(spec=None, *, out=None, engine: str = "local", workers: int | None = None,
          scheduler: str | None = None, scheduler_timeout: float = 10.0, client=None, profiles: bool = False,
          progress: bool = True, on_row=None, info: dict | None = None, **options):
    """Solve the Cartesian product of the options' values; return the table (pandas DataFrame).

    Parameters
    ----------
    spec : path of a TOML file or dict, optional
        Options (``OPTIONS``); keyword ``options`` override it.
    out : path, optional
        Results directory: scene store (resumable), summary.csv/.parquet, profiles.  None: keep
        nothing (no resume).
    engine : {"local", "serial"}
        "local": a dask LocalCluster of ``workers`` processes (default: the machine's cores);
        "serial": this process.  Ignored when ``scheduler`` or ``client`` is given.
    scheduler : str, optional
        Address of a running dask scheduler ("tcp://HOST:PORT").
    scheduler_timeout : float
        Seconds to wait for the scheduler (and for a first worker) before raising InputError.
        Every worker must run this package version.
    client : distributed.Client, optional
        An existing client (left open).
    profiles : bool
        Also write each solved scene's profiles to ``out/profiles/<key>.csv``.
    progress : bool
        Progress bar and reuse note on stderr.
    on_row : callable, optional
        Called with each row as it finishes (after it is stored).
    info : dict, optional
        Filled with counts: scenes, reused, solved, statuses, engine, dask_tasks (scenes are
        batched into tasks of ~TASK_SECONDS), elapsed_s.
    **options
        ``OPTIONS``: indenter, load, force, mu, young, radius, thickness, length, radius_x,
        radius_y, speed, prony, model, method, tol, grid_points, domain_length: a value, a list,
        or a string of comma lists / start:stop:step ranges (SI); prony: Prony series
        ("E1,tau1,..."), several separated by ';' or in a list.

    Returns
    -------
    pandas.DataFrame
        One row per scene (see the package docstring for the columns).

    Raises
    ------
    InputError
        A bad specification (empty range, step <= 0, unknown option or value, unreachable
        scheduler, missing extra), before any scene is solved.
    """
    pd = _need_pandas()
    todo_all = plan(spec, **options)
    _check_engine(engine, workers)
    store = Store(out, profiles)
    if profiles and out is None:
        raise InputError("--profiles needs --out DIR")
    keys = [scene_key(p) for p in todo_all]
    rows, todo = _reuse(store, keys, todo_all)
    reused, total = len(rows), len(rows) + len(todo)
    t0 = time.perf_counter()
    name, client, own = _engine(todo, engine, workers, client, scheduler, scheduler_timeout)
    bar = _Progress(len(todo), progress)

    def on_result(params, row, prof):
        store.save(row, params, prof)
        rows[row["key"]] = row
        bar.update(row["status"] != "ok")
        if on_row is not None:
            on_row(row)

    tasks, cluster = 0, None
    try:
        store.prepare()  # issue 24: a folder that cannot be made fails before the header
        if todo and name.startswith("LocalCluster"):
            client, cluster = local_client(workers)
            own = client
        if progress and out is not None:
            print(f"sweep: {total} scenes, {reused} reused from {store.scenes}, {len(todo)} to "
                  f"solve" + (f" ({name})" if todo else ""), file=sys.stderr)
        bar.t0 = time.perf_counter()  # the rate and time left count solves, not start-up
        if todo and name == "serial":
            _run_serial(todo, profiles, on_result)
        elif todo:
            tasks = _run_dask(client, todo, profiles, on_result)
    finally:
        bar.close()
        if own is not None:
            own.close()
        if cluster is not None:
            cluster.close()
    df = pd.DataFrame([rows[k] for k in dict.fromkeys(keys)], columns=table_columns())
    if out is not None:
        write_tables(df, store.out)
        if profiles:
            write_profile_index(df, store.prof)
    if info is not None:
        counts = df["status"].value_counts()
        info.update({"scenes": total, "reused": reused, "solved": len(todo), "engine": name,
                     "dask_tasks": tasks,
                     "statuses": {s: int(counts.get(s, 0)) for s in STATUSES},
                     "elapsed_s": time.perf_counter() - t0})
    return df


def _check_engine(engine, workers) -> None:
    if engine not in ("local", "serial"):
        raise InputError(f"engine must be 'local' or 'serial'; got {engine!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or not 1 <= workers <= max_workers()):
        raise InputError(f"--workers must be an integer in [1, {max_workers()}] ({WORKERS_PER_CORE} "
                         f"per usable core); got {workers!r}")


def _reuse(store, keys, todo_all):
    """(rows reused from the store by key, the scenes left to solve, each once)."""
    rows = {}
    for k, p in zip(keys, todo_all):
        if k not in rows:
            row = store.load(k, p)
            if row is not None:
                rows[k] = row
    todo, seen = [], set(rows)
    for k, p in zip(keys, todo_all):
        if k not in seen:
            seen.add(k)
            todo.append(p)
    return rows, todo


def _engine(todo, engine, workers, client, scheduler, timeout):
    """(name, client, client owned here) of the engine, checked before anything is written: a
    missing extra, an unreachable scheduler.  A LocalCluster is started later (name only)."""
    if not todo:
        return "serial", client, None
    if client is not None:
        check_workers(client, "client", timeout)
        return "client", client, None
    if scheduler is not None:
        client = connect_scheduler(scheduler, timeout)
        try:
            check_workers(client, f"--scheduler {scheduler}", timeout)
        except BaseException:
            client.close()
            raise
        return f"scheduler {scheduler}", client, client
    if engine == "local":
        need_dask()
        return f"LocalCluster({workers or default_workers()} workers)", None, None
    return "serial", None, None
