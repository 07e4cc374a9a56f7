"""The sweep's engine: one scene solved into its table row (``_task``, pure: every failure a
status), scenes run in this process (``_run_serial``) or batched on a dask cluster
(``_run_dask``), ``map_tasks`` for studies whose points are more than one solve, and the
progress bar on stderr.
"""
from __future__ import annotations

import hashlib
import math
import statistics
import sys
import time

import numpy as np

from ..errors import ConvergenceError, InputError
from .cluster import connect_scheduler, have_dask, local_client
from .table import SCENE_KEYS, fill, row_of, scene_key

__all__ = ["scene_of", "solve_row", "map_tasks", "NO_WORKER_SECONDS", "NoWorkersError",
           "TASK_SECONDS", "MAX_BATCH", "MIN_TASK_SECONDS"]


# --- one scene ----------------------------------------------------------------------------------
def scene_of(params: dict):
    """The scene (``Scene`` or ``Scene3D``) of a row's parameters (``api.make_scene``)."""
    from ..api import make_scene

    return make_scene(**{k: params[k] for k in SCENE_KEYS if params[k] is not None})


def _solve(params: dict):
    from ..api import solve

    return solve(scene_of(params), model=params["model"], method=params["method"],
                 tol=params["tol"], grid_points=params["grid_points"],
                 domain_length=params["domain_length"])


def _task(params: dict, profiles: bool = False):
    """Solve one scene: (row, profiles or None).  Pure: no file, no global state but the
    per-thread FFT plans; every failure becomes a status."""
    status, message, summary, prof = "ok", "", {}, None
    try:
        r = _solve(params)
        summary = r.summary()
        if profiles:
            prof = {k: np.asarray(v).tolist() for k, v in r.profiles().items()}
            if hasattr(r, "maps"):  # 3D: the maps too (written as NPZ)
                prof = {"profiles": prof, "maps": {k: np.asarray(v) for k, v in r.maps().items()}}
    except InputError as exc:
        status, message = "input_error", str(exc)
    except ConvergenceError as exc:
        status, message = "not_converged", str(exc)
    except Exception as exc:  # noqa: BLE001 -- a bug or MemoryError: a row, not the end of the sweep
        status, message = "crashed", f"{type(exc).__name__}: {exc}"
    message = (message.splitlines() or [""])[0]
    return row_of(scene_key(params), params, status, message, summary), prof


def solve_row(params: dict) -> dict:
    """Solve the scene of ``params`` (a dict of ``OPTIONS``, missing ones defaulted) and return
    its table row (see the package docstring); never raises for a failing scene."""
    return _task(fill(params))[0]


def _crashed_row(params, exc) -> dict:
    message = (f"{type(exc).__name__}: {exc}".splitlines() or [""])[0][:300]
    return row_of(scene_key(params), params, "crashed", message, {})


# --- progress -----------------------------------------------------------------------------------
class _Progress:
    """done / total, failures, elapsed, rate, time left, on stderr (one line, redrawn on a
    terminal; a line every 10 % otherwise)."""

    def __init__(self, total: int, enabled: bool, stream=None, unit: str = "scenes"):
        self.total, self.enabled, self.unit = total, enabled and total > 0, unit
        self.stream = stream or sys.stderr
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.done = self.failed = 0
        self.t0 = time.perf_counter()
        self._last = -1.0
        self._decile = -1

    def update(self, failed: bool) -> None:
        self.done += 1
        self.failed += bool(failed)
        if not self.enabled:
            return
        now = time.perf_counter()
        if self.tty:
            if self.done == self.total or now - self._last > 0.1:
                self._last = now
                self.stream.write("\r" + self.line(now) + "\x1b[K")
                self.stream.flush()
        else:
            decile = 10 * self.done // self.total
            if decile != self._decile or self.done == self.total:
                self._decile = decile
                self.stream.write(self.line(now) + "\n")
                self.stream.flush()

    def line(self, now: float) -> str:
        el = now - self.t0
        rate = self.done / el if el > 0 else 0.0
        left = (self.total - self.done) / rate if rate > 0 else float("nan")
        w = 24
        fill = w * self.done // self.total
        return (f"[{'#' * fill}{'-' * (w - fill)}] {self.done}/{self.total} {self.unit}, "
                f"{self.failed} failed, {el:.1f} s elapsed, {rate:.3g} {self.unit}/s, "
                f"{'?' if math.isnan(left) else f'{left:.0f}'} s left")

    def close(self):
        if self.enabled and self.tty and self.done:
            self.stream.write("\n")
            self.stream.flush()



# --- engines ------------------------------------------------------------------------------------
def _run_serial(todo, profiles, on_result):
    for params in todo:
        on_result(params, *_task(params, profiles))


def _task_batch(batch: list, profiles: bool = False) -> list:
    """Solve a list of scenes in one task: [(row, profiles or None), ...]."""
    return [_task(p, profiles) for p in batch]


# Scenes are batched into tasks of about TASK_SECONDS of solving (at most MAX_BATCH scenes); at
# the end of the queue batches shrink so that the workers finish together, but not below
# MIN_TASK_SECONDS.  A task costs 5-10 ms of CPU besides the solves (3-5 ms in the process that
# runs a LocalCluster's scheduler, 2-4 ms in the worker), on the cores that solve: 400 scenes of
# 10 ms on 2 workers took 60-70 tasks (0.25 s, 32, no floor) and take ~40 (main process CPU
# 0.43 -> 0.27 s, loaded machine); the last tasks' imbalance stays below ~50 ms.
TASK_SECONDS = 0.5
MAX_BATCH = 64
MIN_TASK_SECONDS = 0.05


NO_WORKER_SECONDS = 60.0   # a cluster without any worker for this long ends the wait


class NoWorkersError(RuntimeError):
    pass


def _completions(client, ac):
    """The futures of ``ac`` as they complete (futures added meanwhile included); raises
    NoWorkersError when the cluster has had no worker for NO_WORKER_SECONDS (dask would wait
    forever: a LocalCluster whose workers keep dying may stop restarting them)."""
    last_check, idle_since = time.monotonic(), None
    while not ac.is_empty():
        ready = ac.next_batch(block=False)
        if ready:
            yield from ready
            continue
        time.sleep(0.005)
        now = time.monotonic()
        if now - last_check >= 1.0:
            last_check = now
            if client.nthreads():
                idle_since = None
            elif idle_since is None:
                idle_since = now
            elif now - idle_since > NO_WORKER_SECONDS:
                raise NoWorkersError(f"the cluster has had no worker for {NO_WORKER_SECONDS:g} s")


def _batch_size(seconds: list, left: int, threads: int) -> int:
    """Scenes in the next task: 1 until ``threads`` solve times (``seconds``) are known, then
    ~TASK_SECONDS of solving at their recent median (at most MAX_BATCH), cut to a quarter of the
    ``left`` scenes per thread at the end of the queue, but never below MIN_TASK_SECONDS."""
    if len(seconds) < threads:
        return 1
    t = max(statistics.median(seconds[-64:]), 1e-6)
    return max(1, int(MIN_TASK_SECONDS / t), min(int(TASK_SECONDS / t), MAX_BATCH, left // (2 * threads)))


def _run_dask(client, todo, profiles, on_result):
    """Submit the scenes in batches (one scene per task, two tasks per worker thread in flight,
    until solve times are known; then batches of ~TASK_SECONDS, shrinking at the end of the queue
    to MIN_TASK_SECONDS, four per thread in flight: 2D scenes of milliseconds go by tens, so
    dask's 5-10 ms of CPU per task stays small; scenes of seconds go one by one); each row is
    handed to ``on_result`` as its task returns."""
    from collections import deque

    from distributed import as_completed

    threads = max(1, sum(client.nthreads().values()))
    queue = deque(todo)
    pending = {}
    alone = deque()
    seconds = []   # solve + planning time of the scenes seen
    ac = as_completed(loop=client.loop)
    submitted = [0]

    def batch_size():
        return _batch_size(seconds, len(queue), threads)

    def submit():
        if alone:  # scenes of a batch whose worker died: one per task, to find the culprit
            batch = [alone.popleft()]
        else:
            batch = [queue.popleft() for _ in range(min(batch_size(), len(queue)))]
        key = f"spectral-contact-{submitted[0]}-{len(batch)}-scenes-{scene_key(batch[0])}"
        fut = client.submit(_task_batch, batch, profiles, key=key, pure=False, retries=0)
        pending[fut.key] = (fut, batch)
        ac.add(fut)
        submitted[0] += 1

    def handle(fut):
        _, batch = pending.pop(fut.key)
        try:
            # a finished task whose worker then died has lost its result: dask would wait
            # for a recomputation forever if no worker is left
            results = fut.result(timeout=NO_WORKER_SECONDS)
        except TimeoutError:
            fut.release()
            if not client.nthreads():  # every scene left becomes a crashed row (below)
                alone.extend(batch)
                raise NoWorkersError(f"the cluster has had no worker for {NO_WORKER_SECONDS:g} s") from None
            for params in batch:  # solved once more, one per task; lost twice: crashed
                if scene_key(params) in lost:
                    on_result(params, _crashed_row(params, RuntimeError(
                        "the result was lost twice with its worker")), None)
                else:
                    lost.add(scene_key(params))
                    alone.append(params)
                    submit()
            return
        except Exception as exc:  # noqa: BLE001 -- a dead worker (KilledWorker), a lost task
            fut.release()
            if len(batch) > 1:
                alone.extend(batch)
                for _ in batch:
                    submit()
                return
            results = [(_crashed_row(batch[0], exc), None)]
        fut.release()
        for row, _ in results:  # the times first: the next batch is sized with them
            if row["status"] == "ok":
                seconds.append(row["wall_time_s"] + row["plan_time_s"])
        while (queue or alone) and len(pending) < in_flight():
            submit()
        for params, (row, prof) in zip(batch, results):
            on_result(params, row, prof)

    lost = set()  # scenes whose finished result was lost with its worker

    def in_flight():  # 2 single scenes per thread until their times are known, then 4 batches
        return (4 if len(seconds) >= threads else 2) * threads

    try:
        while queue and len(pending) < in_flight():
            submit()
        try:
            for fut in _completions(client, ac):
                handle(fut)
        except NoWorkersError as exc:  # every scene left is a crashed row (not stored: a rerun retries)
            left = [p for _, b in pending.values() for p in b] + list(alone) + list(queue)
            alone.clear()
            queue.clear()
            for params in left:
                on_result(params, _crashed_row(params, exc), None)
    finally:
        if pending:
            client.cancel([f for f, _ in pending.values()])
    return submitted[0]



# --- studies' tasks -----------------------------------------------------------------------------
def map_tasks(func, items, *, engine: str = "auto", workers: int | None = None,
              scheduler: str | None = None, client=None, progress: bool = True,
              unit: str = "tasks") -> list:
    """``[func(item) for item in items]`` on a sweep engine, for studies whose points are more
    than one ``solve`` (no store, no table): results in the order of ``items``.

    ``func`` must be importable by the workers (a module-level function of an installed module:
    it is pickled by reference) and deterministic; ``items`` plain data.  ``engine``: "local"
    (a LocalCluster of ``workers`` processes), "serial", or "auto" (local if dask.distributed is
    installed, else serial); ``scheduler`` / ``client`` as in ``sweep``.  An exception in a task
    is raised here (the remaining tasks are cancelled), as is RuntimeError when the cluster has
    had no worker for NO_WORKER_SECONDS.  Progress bar on stderr unless
    ``progress`` is false.
    """
    items = list(items)
    if engine not in ("auto", "local", "serial"):
        raise InputError(f"engine must be 'auto', 'local' or 'serial'; got {engine!r}")
    if engine == "auto":
        engine = "local" if have_dask() else "serial"
    bar = _Progress(len(items), progress, unit=unit)
    results = [None] * len(items)
    if client is None and scheduler is None and engine == "serial":
        try:
            for i, item in enumerate(items):
                results[i] = func(item)
                bar.update(False)
        finally:
            bar.close()
        return results
    own = cluster = None
    futures, pending = [], {}
    try:
        if client is None:
            if scheduler is not None:
                client = own = connect_scheduler(scheduler)
            else:
                client, cluster = local_client(workers)
                own = client
        from distributed import as_completed

        bar.t0 = time.perf_counter()
        tag = hashlib.sha256(repr((func.__module__, func.__qualname__, time.time_ns())).encode()).hexdigest()[:12]
        pending = {}
        for i, item in enumerate(items):
            fut = client.submit(func, item, key=f"spectral-contact-map-{tag}-{i}", pure=False)
            pending[fut.key] = (fut, i)
            futures.append(fut)
        for fut in _completions(client, as_completed(futures, loop=client.loop)):
            try:  # a finished task whose worker then died has lost its result (see _run_dask)
                results[pending[fut.key][1]] = fut.result(timeout=NO_WORKER_SECONDS)
            except TimeoutError:
                raise NoWorkersError(f"a result was lost with its worker and not recomputed "
                                     f"within {NO_WORKER_SECONDS:g} s") from None
            pending.pop(fut.key)
            bar.update(False)
            fut.release()
    finally:
        bar.close()
        if futures and pending:
            client.cancel([f for f, _ in pending.values()])
        if own is not None:
            own.close()
        if cluster is not None:
            cluster.close()
    return results

