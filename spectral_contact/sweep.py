"""Sweeps: the Cartesian product of scene options, solved once each, on a dask.distributed engine.

    >>> from spectral_contact import sweep
    >>> df = sweep(load="20:380:40", mu=[0.3, 1, 2, 3], out="results")   # a pandas DataFrame

Values (SI, the units of ``solve``): a number, a list, a comma list "0.3,1,2,3" or a range
"start:stop:step" (stop included when it falls on the step; values are start + i step rounded to
12 significant digits), or comma lists of those.  ``OPTIONS`` lists the options and defaults.

Engines: ``engine="serial"`` solves in this process; ``engine="local"`` (default) starts a dask
LocalCluster of ``workers`` processes (default: the machine's cores), one thread each, with
OpenBLAS/OpenMP/MKL pinned to one thread through the workers' environment, and dask settings
``DASK_CONFIG`` that spare the cores (no statistical profiler in the workers, slower event-loop
tick and system/memory monitors, glibc's own malloc thresholds instead of the nannies'
MALLOC_TRIM_THRESHOLD_=65536; set only around the cluster's creation); ``scheduler=
"tcp://HOST:PORT"`` uses a running dask cluster with its own configuration (its workers should be
started with ``--nthreads 1`` and ``OPENBLAS_NUM_THREADS=1``, and a dask config file with the
worker and nanny keys of ``DASK_CONFIG``: see README).  Tasks carry plain dicts of parameters; each
worker process plans its own FFTs (``numerics.fft`` keeps plans per thread) and nothing but the
parameter dict and the result row cross the wire.

Results are identical bit for bit between the engines: a scene's row depends only on its
parameters (the solver is deterministic; FFTW's default ESTIMATE planner chooses its algorithm
from the size alone), except the timing columns ``TIMING_COLUMNS``.  With
SPECTRAL_CONTACT_FFTW=measure, plans are chosen by timing, so two processes may round differently
(~1e-16 relative); the same holds across machines with different SIMD units.  The serial engine
runs under this process's BLAS threading: set OPENBLAS_NUM_THREADS=1 before Python starts, as
the workers do (OpenBLAS splits long dot products between threads, from 10^4 points on).

Table (one row per scene, in the order of the Cartesian product, the first option varying
slowest): ``key``, the options (``OPTIONS``, defaults filled in), ``status`` ("ok",
"input_error", "not_converged", "crashed"), ``message`` (the error's first line, "" when ok),
then every JSON key of ``solve``'s summaries (``result.JSON_KEYS``, then the 3D ones of
``result.JSON_KEYS_3D``, ``length_m``, ``radius_x_m``, ``radius_y_m``, ``auto_reason``); those whose
name is also an option's ("model", "method", "mu", "grid_points", "indenter") are prefixed
``solved_`` (with model="auto", ``solved_model`` is the model chosen).  A failed scene has empty
summary columns, a line's row empty 3D columns and the reverse (3D ``grid_points`` and
``domain_length_m`` are [x, y] lists; text in Parquet).  Defaults per indenter: a line's load
200 N/m and tol 1e-4; a 3D indenter's force 1 N, tol left to ``solve`` (empty column).

Store (``out`` given): every finished scene is written at once to ``out/scenes/<key>.json``
(temporary file then rename), ``key`` a hash of the sorted parameters and the package version; a
rerun reuses every stored scene and solves only the missing ones, so Ctrl-C loses at most the
scenes in flight.  "crashed" scenes (an unexpected exception, a dead worker) are not stored: a
rerun retries them.  At the end: ``out/summary.csv`` (one header row, no quotes:
``pandas.read_csv`` and ``numpy.genfromtxt(..., names=True, dtype=str)`` open it; commas in text cells
become ';', lists JSON with ';' for ','), ``out/summary.parquet`` if pyarrow is installed, and
with ``profiles=True`` the profiles of each solved scene in ``out/profiles/<key>.csv``
(``result.PROFILE_COLUMNS``; 3D: the y = 0 line) and, for 3D scenes, their maps in
``out/profiles/<key>.npz`` (``result.MAP_KEYS``); ``out/profiles/index.csv`` says which file
holds which scene (file names, the options that vary, the status).

Needs the optional extra ``pip install 'spectral_contact[sweep]'`` (pandas; dask.distributed for
the local and external engines).
"""
from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .errors import ConvergenceError, InputError
from .physics import options as _table

__all__ = ["sweep", "OPTIONS", "TIMING_COLUMNS", "STATUSES", "parse_values", "read_spec",
           "scenes", "scene_key", "scene_of", "solve_row", "table_columns", "connect_scheduler", "local_client",
           "DASK_CONFIG", "check_workers", "map_tasks"]

STATUSES = ("ok", "input_error", "not_converged", "crashed")
TIMING_COLUMNS = ("wall_time_s", "plan_time_s")
EXTRA = "pip install 'spectral_contact[sweep]'"

def _options() -> dict:
    """name -> (type, default, unit or choices, help) of the options with ``sweep=True`` in the
    one declaration (``physics.options``), in its order (the column order).  A scene option
    that only one kind of indenter takes defaults to None here: filled per indenter by ``scenes``
    (``_fill``: a line's load, a 3D indenter's force) or left to ``solve``."""
    out = {}
    for o in _table.OPTIONS:
        if o.sweep:
            d = o.default if o.scenes in ("both", "solve") else None
            out[o.name] = (o.kind, d, o.choices if o.kind is str else o.unit, o.cli_help())
    return out


OPTIONS = _options()
_SCENE_KEYS = tuple(k for k in OPTIONS if _table.option(k).scenes != "solve")
_LINE_DEFAULTS = {"load": _table.default("load"), "tol": 1e-4}
_3D_DEFAULTS = {"force": _table.default("force")}


def _fill(p: dict) -> dict:
    """Defaults that depend on the indenter (a line's load and tol, a 3D indenter's force)."""
    for k, v in (_LINE_DEFAULTS if p["indenter"] == "line" else _3D_DEFAULTS).items():
        if p[k] is None:
            p[k] = v
    return p


# --- specifications -----------------------------------------------------------------------------
def _number(name: str, text: str, kind):
    try:
        v = int(text) if kind is int else float(text)
    except (TypeError, ValueError):
        what = "an integer" if kind is int else "a number"
        raise InputError(f"--{_flag(name)}: {text!r} is not {what} (values: v1,v2,... or "
                         f"start:stop:step)") from None
    if kind is float and not math.isfinite(v):
        raise InputError(f"--{_flag(name)}: values must be finite; got {text!r}")
    return v


def _flag(name: str) -> str:
    return name.replace("_", "-")


def _range(name: str, text: str, kind) -> list:
    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(f"--{_flag(name)}: a range is start:stop:step; got {text!r}")
    start, stop, step = (_number(name, p.strip(), kind) for p in parts)
    if step <= 0:
        raise InputError(f"--{_flag(name)}: the step of {text!r} must be > 0; got {step:g}")
    if stop < start:
        raise InputError(f"--{_flag(name)}: empty range {text!r} (stop < start)")
    n = int(math.floor((stop - start) / step * (1 + 1e-12) + 1e-9)) + 1
    if n > 1_000_000:
        raise InputError(f"--{_flag(name)}: {text!r} has {n} values (at most 1000000)")
    if kind is int:
        return [start + i * step for i in range(n)]
    return [float(f"{start + i * step:.12g}") for i in range(n)]


def parse_values(name: str, value) -> list:
    """The list of values of option ``name`` from a spec: a scalar, a list, or a string of comma
    separated numbers / choices / start:stop:step ranges.  Raises InputError naming the option."""
    if name not in OPTIONS:
        raise InputError(f"unknown option {name!r} (accepted: {', '.join(OPTIONS)})")
    kind, _, choices, _ = OPTIONS[name]
    items = value if isinstance(value, (list, tuple)) else [value]
    out = []
    for item in items:
        if isinstance(item, str):
            pieces = [p.strip() for p in item.split(",")]
            if not all(pieces):
                raise InputError(f"--{_flag(name)}: empty value in {item!r}")
        else:
            pieces = [item]
        for p in pieces:
            if kind is str:
                if not isinstance(p, str) or p not in choices:
                    raise InputError(f"--{_flag(name)}: {p!r} is not one of {', '.join(choices)}")
                out.append(p)
            elif isinstance(p, str) and ":" in p:
                out.extend(_range(name, p, kind))
            elif p is None and OPTIONS[name][1] is None:
                out.append(None)
            elif isinstance(p, bool):
                raise InputError(f"--{_flag(name)}: {p!r} is not a number")
            elif kind is int and isinstance(p, float) and not p.is_integer():
                raise InputError(f"--{_flag(name)}: {p!r} is not an integer")
            else:
                out.append(_number(name, p, kind))
    if not out:
        raise InputError(f"--{_flag(name)}: no values")
    seen, unique = set(), []
    for v in out:  # a value given twice is one scene
        if v not in seen:
            seen.add(v)
            unique.append(v)
    return unique


def read_spec(path) -> dict:
    """The options of a TOML spec file (top-level keys = option names, values as in
    ``parse_values``: numbers, lists, or strings such as "20:380:40")."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10: the same parser as the tomli package
        try:
            import tomli as tomllib
        except ModuleNotFoundError:
            raise InputError("--spec needs Python >= 3.11 (tomllib) or the tomli package") from None
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except OSError as exc:
        raise InputError(f"--spec {path}: {exc.strerror or exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"--spec {path}: not valid TOML ({exc})") from None
    for k, v in data.items():
        if k not in OPTIONS:
            raise InputError(f"--spec {path}: unknown option {k!r} (accepted: {', '.join(OPTIONS)})")
        if isinstance(v, dict):
            raise InputError(f"--spec {path}: option {k!r} must be a value or a list, not a table")
    return data


def scenes(options: dict) -> list[dict]:
    """The Cartesian product of the options' values, defaults filled in: a list of parameter
    dicts (plain Python values) in ``OPTIONS`` order, the first given option varying slowest."""
    unknown = [k for k in options if k not in OPTIONS]
    if unknown:
        raise InputError(f"unknown option {unknown[0]!r} (accepted: {', '.join(OPTIONS)})")
    given = {k: parse_values(k, v) for k, v in options.items() if v is not None}
    check_product(given)  # issue 24: before enumerating
    names = list(given)
    rows = []
    for combo in itertools.product(*(given[n] for n in names)):
        p = {k: OPTIONS[k][1] for k in OPTIONS}
        p.update(zip(names, combo))
        rows.append(_fill({k: p[k] for k in OPTIONS}))
    return rows


def _version() -> str:
    from ._version import __version__

    return __version__


def scene_key(params: dict, version: str | None = None) -> str:
    """The store key of a scene: sha256 of its sorted parameters and the package version."""
    text = json.dumps({"params": params, "version": version or _version()}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


# --- one scene ----------------------------------------------------------------------------------
def _summary_keys():
    """Every JSON key of ``solve``'s summaries, line then 3D, in order."""
    from .result import JSON_KEYS, JSON_KEYS_3D

    keys = list(JSON_KEYS)
    keys += [k for k in JSON_KEYS_3D if k not in keys]
    return keys + ["length_m", "radius_x_m", "radius_y_m", "auto_reason"]


def _summary_names():
    return [f"solved_{k}" if k in OPTIONS else k for k in _summary_keys()]


def table_columns() -> list[str]:
    """The table's columns, in order."""
    return ["key", *OPTIONS, "status", "message", *_summary_names()]


def scene_of(params: dict):
    """The scene (``Scene`` or ``Scene3D``) of a row's parameters (``api.make_scene``)."""
    from .api import make_scene

    return make_scene(**{k: params[k] for k in _SCENE_KEYS if params[k] is not None})


def _solve(params: dict):
    from .api import solve

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
    row = {"key": scene_key(params), **params, "status": status, "message": message}
    for k, name in zip(_summary_keys(), _summary_names()):
        row[name] = summary.get(k)
    return row, prof


def solve_row(params: dict) -> dict:
    """Solve the scene of ``params`` (a dict of ``OPTIONS``, missing ones defaulted) and return
    its table row (see the module docstring); never raises for a failing scene."""
    p = {k: OPTIONS[k][1] for k in OPTIONS}
    unknown = [k for k in params if k not in OPTIONS]
    if unknown:
        raise InputError(f"unknown option {unknown[0]!r} (accepted: {', '.join(OPTIONS)})")
    p.update(params)
    return _task(_fill(p))[0]


# --- store --------------------------------------------------------------------------------------
def _atomic_write(path: Path, write, binary: bool = False) -> None:
    """Write ``path`` whole or not at all: ``write(fh)`` into a temporary beside it, renamed."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=".tmp")
    try:
        with (os.fdopen(fd, "wb") if binary else
              os.fdopen(fd, "w", encoding="utf-8", newline="")) as fh:
            write(fh)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


class _Store:
    """``out/scenes/<key>.json`` per finished scene; ``out/profiles/<key>.csv`` when asked."""

    def __init__(self, out, profiles: bool):
        if out is not None and not str(out).strip():  # issue 24: Path("") is the current folder
            raise InputError("--out: empty folder name")
        self.out = Path(out) if out is not None else None
        self.profiles = profiles
        if self.out is None:
            return
        if self.out.exists() and not self.out.is_dir():
            raise InputError(f"--out {out}: exists and is not a directory")
        if not self.out.parent.is_dir():
            raise InputError(f"--out {out}: directory {self.out.parent} does not exist")
        self.scenes = self.out / "scenes"
        self.prof = self.out / "profiles"

    def prepare(self):
        if self.out is not None:
            self.scenes.mkdir(parents=True, exist_ok=True)
            if self.profiles:
                self.prof.mkdir(exist_ok=True)

    def load(self, key: str, params: dict):
        """The stored row of ``key``, or None (absent, unreadable, other parameters/version)."""
        if self.out is None:
            return None
        try:
            rec = json.loads((self.scenes / f"{key}.json").read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        if (not isinstance(rec, dict) or rec.get("version") != _version()
                or rec.get("params") != params or not isinstance(rec.get("row"), dict)):
            return None
        if self.profiles and rec["row"].get("status") == "ok" and not all(
                _file_digest(self.prof / f"{key}{ext}") == rec.get("files", {}).get(f"{key}{ext}")
                for ext in self._kinds(params)):
            # stored by a run without profiles, or a profile file missing, truncated or changed
            # since (issue 24: every reused file is verified against its recorded sha256)
            return None
        return rec["row"]

    @staticmethod
    def _kinds(params):
        return (".csv",) if params.get("indenter", "line") == "line" else (".csv", ".npz")

    def save(self, row: dict, params: dict, prof) -> None:
        if self.out is None or row["status"] == "crashed":
            return
        key = row["key"]
        files = {}
        if prof is not None:
            maps = None
            if "maps" in prof:
                prof, maps = prof["profiles"], prof["maps"]
            _atomic_write(self.prof / f"{key}.csv", lambda fh: _write_profiles(fh, prof))
            if maps is not None:
                _atomic_npz(self.prof / f"{key}.npz", maps)
            files = {f"{key}{ext}": _file_digest(self.prof / f"{key}{ext}")
                     for ext in self._kinds(params)}
        rec = {"key": key, "version": _version(), "params": params, "row": row, "files": files}
        _atomic_write(self.scenes / f"{key}.json", lambda fh: json.dump(rec, fh, indent=1))


def _file_digest(path: Path):
    """sha256 of a file's bytes (None if it cannot be read): a reused profile must match the
    digest recorded with its scene."""
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return None


def _atomic_npz(path: Path, arrays: dict) -> None:
    _atomic_write(path, lambda fh: np.savez_compressed(fh, **arrays), binary=True)


def _write_profiles(fh, prof: dict) -> None:
    names = list(prof)
    fh.write(",".join(names) + "\n")
    for vals in zip(*(prof[n] for n in names)):
        fh.write(",".join(repr(float(v)) for v in vals) + "\n")


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
def _need_dask():
    try:
        import distributed  # noqa: F401
    except ModuleNotFoundError:
        raise InputError(f"the local and external engines need dask.distributed: {EXTRA} "
                         "(or run with --serial)") from None


WORKER_ENV = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def connect_scheduler(address: str, timeout: float = 10.0):
    """A dask Client on a running scheduler; InputError (naming --scheduler) if unreachable."""
    _need_dask()
    import logging

    from distributed import Client

    if not isinstance(address, str) or "://" not in address and ":" not in address:
        raise InputError(f"--scheduler must be an address such as tcp://HOST:PORT; got {address!r}")
    probe_scheduler(address, timeout)
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
    client = None
    old_hook = sys.unraisablehook  # a half-made Client's __del__ times out noisily: keep quiet
    sys.unraisablehook = lambda unraisable: None
    try:
        client = Client(address, timeout=timeout, set_as_default=False)
        return client
    except Exception as exc:  # noqa: BLE001 -- whatever the peer did: one line
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"--scheduler {address}: unreachable ({msg[:160]})") from None
    finally:
        if client is None:
            import gc

            gc.collect()
        sys.unraisablehook = old_hook


# --- issue 24: the sweep's bounds, checked before any work ----------------------------------------
MAX_SCENES = 100_000
"""Largest Cartesian product of a sweep (the product of the option lists' lengths, checked before
it is enumerated): 10^5 scenes of ~10 ms are ~20 min on 1 core, and their table ~100 MB."""
WORKERS_PER_CORE = 2
"""--workers is bounded by this many per usable core (each worker is one process with one
thread: more only adds start-up time and memory; 1000 never started on 2 cores)."""
_HANDSHAKE_MAX = 1 << 20  # a dask handshake is ~100 bytes; 1 MiB is nothing a scheduler sends


def max_workers() -> int:
    """The bound of --workers: WORKERS_PER_CORE x the usable cores."""
    return WORKERS_PER_CORE * _default_workers()


def check_product(given: dict) -> int:
    """The number of scenes of ``given`` ({option: values}), InputError above MAX_SCENES."""
    n = 1
    for v in given.values():
        n *= len(v)
    if n > MAX_SCENES:
        sizes = " x ".join(f"{len(v)} (--{_flag(k)})" for k, v in given.items() if len(v) > 1)
        raise InputError(f"the sweep has {sizes} = {n:.4g} scenes: at most {MAX_SCENES} (split it "
                         f"into several sweeps sharing --out)")
    return n


def probe_scheduler(address: str, timeout: float) -> None:
    """Check, with a raw socket and a hard ``timeout``, that a tcp:// ``address`` speaks dask's
    protocol before a Client is made: a dask server writes its handshake first (8-byte length,
    then ~100 bytes).  Something else (an HTTP server: silent; random bytes: a "length" of
    exabytes) is an InputError naming --scheduler, within ``timeout``."""
    import socket
    import struct

    scheme, _, rest = address.rpartition("://")
    if scheme not in ("", "tcp"):
        return  # tls://, inproc://, ...: left to dask
    host, _, port = rest.rpartition(":")
    host = host.strip("[]")
    try:
        port_n = int(port)
    except ValueError:
        port_n = -1
    if not host or not 0 < port_n < 65536:
        raise InputError(f"--scheduler must be an address such as tcp://HOST:PORT (PORT in 1 ... "
                         f"65535); got {address!r}")
    deadline = time.monotonic() + timeout

    def recv(sock, n):
        data = b""
        while len(data) < n:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError
            sock.settimeout(left)
            chunk = sock.recv(n - len(data))
            if not chunk:
                raise ConnectionError("closed by the peer")
            data += chunk
        return data

    try:
        with socket.create_connection((host, port_n), timeout=timeout) as sock:
            (n,) = struct.unpack("<Q", recv(sock, 8))
            if not 0 < n <= _HANDSHAKE_MAX:
                raise InputError(f"--scheduler {address}: not a dask scheduler (its first bytes "
                                 f"announce a message of {n:.3g} bytes; dask's handshake is ~100)")
            recv(sock, n)
    except TimeoutError:
        raise InputError(f"--scheduler {address}: no dask handshake within --scheduler-timeout "
                         f"{timeout:g} s (not a dask scheduler, or not answering)") from None
    except OSError as exc:
        raise InputError(f"--scheduler {address}: unreachable ({exc.strerror or exc})") from None
# --- end of issue 24's bounds ---------------------------------------------------------------------


def _worker_version():
    try:
        from spectral_contact._version import __version__
    except Exception as exc:  # noqa: BLE001 -- reported to the client as the reason
        return f"cannot import spectral_contact ({type(exc).__name__}: {exc})"
    return __version__


def check_workers(client, what: str, timeout: float = 10.0) -> int:
    """Wait (up to ``timeout`` s) for at least one worker and check that every worker runs this
    package version (a scene's key holds the version); returns the worker threads.  InputError
    naming ``what`` otherwise."""
    t_end = time.monotonic() + timeout
    while not client.nthreads():
        if time.monotonic() > t_end:
            raise InputError(f"{what}: no workers joined the scheduler in {timeout:g} s")
        time.sleep(0.1)
    versions = client.run(_worker_version)
    mine = _version()
    for addr, v in sorted(versions.items()):
        if v != mine:
            raise InputError(f"{what}: worker {addr} runs spectral_contact {v} (this is {mine}); "
                             "install the same version on every worker")
    return sum(client.nthreads().values())


# dask settings of the sweep's LocalCluster (its scheduler and nannies in this process, and the
# worker processes, which get the nannies' copy): its periodic work costs CPU on the cores that
# solve.  Measured on 2 cores, 400 2D scenes of ~10 ms (studies/benchmark_sweep.py): the workers'
# statistical profiler (it takes the GIL from the solve every 10 ms to walk its stack) and the
# 20 ms event-loop tick, the system and memory monitors cost an idle 2-worker cluster 0.066 core
# s per s (0.015 with these settings); the profiler feeds only the dashboard, which is off.
# glibc: the nannies set MALLOC_TRIM_THRESHOLD_=65536 in the workers, which also freezes glibc's
# mmap threshold at 128 KiB: every array above it is mmap'd and faulted in anew (91000 page
# faults in the workers for those 400 scenes, 14000 without); None leaves glibc's defaults, as in
# the serial engine (unless this process's environment has the variable: a dask Nanny started
# here with dask's default config writes it into os.environ, and the workers inherit it).
# Together, the solving thread's CPU went from 1.01-1.05 to 0.93-0.97 x a plain process's main
# thread's (1 worker, the same scenes in alternation; profiler alone -3 %, glibc alone -3.5 %).
DASK_CONFIG = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "10s",
    "distributed.worker.memory.monitor-interval": "500ms",
    "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
}


def local_client(workers: int | None = None):
    """A dask LocalCluster of ``workers`` processes (default: the cores), one thread each, BLAS
    pinned to one thread, with ``DASK_CONFIG`` (this process's dask config is left as it was);
    returns (client, cluster): close both when done."""
    _need_dask()
    workers = workers or _default_workers()
    import logging

    import dask
    from distributed import Client, LocalCluster  # before dask.config.set: its defaults first

    # on 127.0.0.1 only; no dashboard; the scheduler's health page on a free port (not 8787)
    with dask.config.set(DASK_CONFIG):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address=None,
                               scheduler_kwargs={"dashboard": False, "dashboard_address": "127.0.0.1:0"},
                               silence_logs=logging.CRITICAL, env=dict(WORKER_ENV))
    return Client(cluster, set_as_default=False), cluster


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


def _crashed_row(params, exc) -> dict:
    row = {"key": scene_key(params), **params, "status": "crashed",
           "message": (f"{type(exc).__name__}: {exc}".splitlines() or [""])[0][:300]}
    for name in _summary_names():
        row[name] = None
    return row


# --- the sweep ----------------------------------------------------------------------------------
def _need_pandas():
    try:
        import pandas
    except ModuleNotFoundError:
        raise InputError(f"the sweep returns a pandas table: {EXTRA}") from None
    return pandas


def _default_workers() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def plan(spec=None, **options) -> list[dict]:
    """The scenes of a sweep (spec file or dict, then ``options`` over it), checked."""
    merged = {}
    if spec is not None:
        merged.update(read_spec(spec) if isinstance(spec, (str, os.PathLike)) else dict(spec))
    merged.update({k: v for k, v in options.items() if v is not None})
    return scenes(merged)


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
        radius_y, model, method, tol, grid_points, domain_length: a value, a list, or a string of
        comma lists / start:stop:step ranges (SI).

    Returns
    -------
    pandas.DataFrame
        One row per scene (see the module docstring for the columns).

    Raises
    ------
    InputError
        A bad specification (empty range, step <= 0, unknown option or value, unreachable
        scheduler, missing extra), before any scene is solved.
    """
    pd = _need_pandas()
    todo_all = plan(spec, **options)
    if engine not in ("local", "serial"):
        raise InputError(f"engine must be 'local' or 'serial'; got {engine!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or not 1 <= workers <= max_workers()):
        raise InputError(f"--workers must be an integer in [1, {max_workers()}] ({WORKERS_PER_CORE} "
                         f"per usable core); got {workers!r}")
    store = _Store(out, profiles)
    if profiles and out is None:
        raise InputError("--profiles needs --out DIR")
    keys = [scene_key(p) for p in todo_all]
    rows = {}
    for k, p in zip(keys, todo_all):
        if k not in rows:
            row = store.load(k, p)
            if row is not None:
                rows[k] = row
    reused = len(rows)
    todo, seen = [], set(rows)
    for k, p in zip(keys, todo_all):
        if k not in seen:
            seen.add(k)
            todo.append(p)
    total = len(seen)
    own = cluster = None
    name = "serial"
    t0 = time.perf_counter()
    if todo:  # the engine before anything is written: a missing extra, an unreachable scheduler
        if client is not None:
            name = "client"
            check_workers(client, "client", scheduler_timeout)
        elif scheduler is not None:
            client = own = connect_scheduler(scheduler, scheduler_timeout)
            name = f"scheduler {scheduler}"
            try:
                check_workers(client, f"--scheduler {scheduler}", scheduler_timeout)
            except BaseException:
                client.close()
                raise
        elif engine == "local":
            _need_dask()
            n = workers or _default_workers()
            name = f"LocalCluster({n} workers)"
    bar = _Progress(len(todo), progress)

    def on_result(params, row, prof):
        store.save(row, params, prof)
        rows[row["key"]] = row
        bar.update(row["status"] != "ok")
        if on_row is not None:
            on_row(row)

    tasks = 0
    try:
        if todo and name.startswith("LocalCluster"):
            client, cluster = local_client(workers)
            own = client
        if progress and out is not None:
            print(f"sweep: {total} scenes, {reused} reused from {store.scenes}, {len(todo)} to "
                  f"solve" + (f" ({name})" if todo else ""), file=sys.stderr)
        store.prepare()
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
        _write_tables(df, store.out)
        if profiles:
            _write_profile_index(df, store.prof)
    if info is not None:
        counts = df["status"].value_counts()
        info.update({"scenes": total, "reused": reused, "solved": len(todo), "engine": name,
                     "dask_tasks": tasks,
                     "statuses": {s: int(counts.get(s, 0)) for s in STATUSES},
                     "elapsed_s": time.perf_counter() - t0})
    return df


def _have_dask() -> bool:
    try:
        import distributed  # noqa: F401
    except ModuleNotFoundError:
        return False
    return True


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
        engine = "local" if _have_dask() else "serial"
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


def _plain(v):
    """A cell as plain text for the files: lists (3D [nx, ny], contact_intervals_m) as JSON with
    ';' for ',' ("[256;256]": ``json.loads(cell.replace(";", ","))`` reads it back), commas in
    text as ';' (so that readers without quoting, numpy.genfromtxt, split the columns right)."""
    if isinstance(v, (list, tuple)):
        return json.dumps(v, separators=(";", ":"))
    if isinstance(v, str):
        return v.replace(",", ";")
    return v


def _write_profile_index(df, folder: Path) -> None:
    """``profiles/index.csv`` (issue 24): which file holds which scene -- the file names (a
    hash each) with the options that vary across the sweep and the status, in the table's
    order.  Scenes without profiles (failed) are listed with an empty file name."""
    varying = [k for k in OPTIONS if df[k].astype(str).nunique() > 1] or ["indenter"]
    rows = []
    for _, r in df.iterrows():
        ok = r["status"] == "ok"
        kinds = _Store._kinds({"indenter": r["indenter"]})
        rows.append({"file": f"{r['key']}.csv" if ok else "",
                     "maps_file": f"{r['key']}.npz" if ok and ".npz" in kinds else "",
                     **{k: r[k] for k in varying}, "status": r["status"]})
    import pandas as pd

    index = pd.DataFrame(rows)
    for c in index.columns:
        index[c] = [_plain(v) for v in index[c]]
    _atomic_write(folder / "index.csv", lambda fh: index.to_csv(fh, index=False))


def _write_tables(df, out: Path) -> None:
    from pandas.api.types import is_numeric_dtype

    df = df.copy()
    for c in df.columns:  # text and list columns (object, or pandas' string dtype)
        if not is_numeric_dtype(df[c]):
            df[c] = [_plain(v) for v in df[c]]
    _atomic_write(out / "summary.csv", lambda fh: df.to_csv(fh, index=False))
    try:
        import pyarrow  # noqa: F401
    except ModuleNotFoundError:
        return
    for c in df.columns:  # a column of mixed kinds (2D int and 3D "[nx;ny]") as text for Arrow
        if not is_numeric_dtype(df[c]):
            kinds = {type(v) for v in df[c] if v is not None and v == v}
            if len(kinds) > 1:
                df[c] = [None if v is None else str(v) for v in df[c]]
    path = out / "summary.parquet"
    fd, tmp = tempfile.mkstemp(dir=out, prefix="summary.parquet.", suffix=".tmp")
    os.close(fd)
    try:
        df.to_parquet(tmp, index=False)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


class _CallableModule(type(sys)):
    """``spectral_contact.sweep`` is both this module and the function: once a submodule is
    imported Python binds it as the package's attribute, so the module itself forwards calls."""

    def __call__(self, *args, **kwargs):
        return sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
