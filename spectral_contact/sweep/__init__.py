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
slowest), one name per quantity, with its unit, the names of ``solve --json``:

- ``key``;
- the options, each under its column (``column(name)``): ``indenter``, ``load_N_per_m``
  (``load``), ``force_N`` (``force``), ``mu``, ``young_Pa``, ``radius_m``, ``thickness_m``,
  ``length_m``, ``radius_x_m``, ``radius_y_m``, ``speed_m_per_s`` (``speed``), ``prony_terms``
  (``prony``: [[E_i, tau_i], ...]), ``model``, ``method``, ``tol``, ``grid_points``,
  ``domain_length_m``: the value of the scene (a line's ``force_N`` and a 3D indenter's
  ``load_N_per_m`` are empty; an option left empty whose value the solve reports -- a
  paraboloid's ``radius_x_m`` -- holds that value);
- ``status`` ("ok", "input_error", "not_converged", "crashed"), ``message`` (the error's first
  line, "" when ok);
- every other JSON key of ``solve``'s summaries (``result.JSON_KEYS``, then the 3D ones of
  ``result.JSON_KEYS_3D``, ``auto_reason``).  What the solver chooses when the request leaves
  it empty is ``solved_model`` (``model="auto"``: the model chosen), ``solved_method``,
  ``solved_grid_points`` and ``solved_domain_length_m``, for lines and surfaces alike: the
  points and period along x; a surface's along y are ``solved_grid_points_y`` and
  ``solved_domain_length_y_m`` (empty for a line).  ``grid_points`` / ``domain_length_m`` are
  the request (empty: chosen from ``tol``; a surface's ``grid_points`` is per axis).

Every column holds one number or one word, but ``contact_intervals_m`` (a JSON list).  A failed
scene has empty summary columns, a line's row empty 3D columns and the reverse.  Defaults per
indenter: a line's load 200 N/m and tol 1e-4; a 3D indenter's force 1 N, tol left to ``solve``
(empty column).  The inputs -- keywords, flags, spec keys, ``--plot-x`` -- keep the options'
names (``load``); ``--plot-x`` and ``--plot-group`` take a column name too.  (Earlier tables
had the options' names as columns -- ``load``, ``young`` -- beside the summary's
``load_N_per_m``, ``young_Pa``, and [nx;ny] text for a surface's grid: a store written so is
solved again, not reused.)

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

Layout: ``table`` (options, values, scenes, columns), ``engine`` (one scene's row, the serial and
dask runners, ``map_tasks``, progress), ``cluster`` (dask clusters and their checks), ``store``
(the scene store and the files), ``run`` (``sweep``).
"""
from __future__ import annotations

import sys

from .cluster import (  # noqa: F401
    DASK_CONFIG,
    WORKER_ENV,
    WORKERS_PER_CORE,
    check_workers,
    connect_scheduler,
    local_client,
    max_workers,
    probe_scheduler,
)
from .engine import (  # noqa: F401
    MAX_BATCH,
    MIN_TASK_SECONDS,
    NO_WORKER_SECONDS,
    TASK_SECONDS,
    NoWorkersError,
    _batch_size,
    map_tasks,
    scene_of,
    solve_row,
)
from .run import sweep
from .store import plain as _plain  # noqa: F401
from .table import (  # noqa: F401
    EXTRA,
    MAX_SCENES,
    OPTIONS,
    STATUSES,
    TIMING_COLUMNS,
    check_product,
    column,
    option_of,
    parse_values,
    plan,
    read_spec,
    scene_key,
    scenes,
    table_columns,
)

__all__ = ["sweep", "OPTIONS", "TIMING_COLUMNS", "STATUSES", "parse_values", "read_spec",
           "scenes", "scene_key", "scene_of", "solve_row", "table_columns", "column",
           "connect_scheduler", "local_client", "DASK_CONFIG", "check_workers", "map_tasks",
           "MAX_SCENES", "max_workers", "plan"]


class _CallableModule(type(sys)):
    """``spectral_contact.sweep`` is both this package and the function: once a submodule is
    imported Python binds it as the package's attribute, so the package itself forwards calls."""

    def __call__(self, *args, **kwargs):
        return sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
