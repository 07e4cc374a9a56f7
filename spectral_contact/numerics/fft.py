"""Real FFTs through pyfftw, planned once per (shape, threads, planner effort) and reused.

``RealFFT(shape)`` owns aligned input/output buffers and two FFTW plans (r2c and c2r) over all
axes.  ``get_rfft(shape)`` returns a cached instance.  The cache is per thread: a plan's buffers
are its state, so two threads sharing one plan would overwrite each other's data mid-transform;
each thread therefore plans (cheaply, from FFTW's in-process wisdom) and keeps its own.

Convention (numpy's): forward f^_k = sum_j f_j exp(-2 pi i j.k/n); backward divides by the
number of points.

Planner effort: FFTW_ESTIMATE by default (planning costs milliseconds; a transform pair is
1.2-1.8x slower than with FFTW_MEASURE from N = 2^14 on, while MEASURE planning costs ~0.4 s at
2^10 and 13-40 s at 2^18-2^20: studies/large_domain).  Set the environment variable
SPECTRAL_CONTACT_FFTW=measure (or call ``set_planner_effort("FFTW_MEASURE")``) for long sweeps;
measured plans are then stored as FFTW wisdom in ``WISDOM_FILE`` and reused by later runs.

The wisdom file holds FFTW's own exported text (``fftw_export_wisdom``), never a pickle: it is
checked to look like FFTW wisdom and handed to FFTW's parser, which only reads plans; anything
unreadable is ignored with one warning.  It is written to a temporary file and renamed.
"""
from __future__ import annotations

import os
import tempfile
import threading
import time
import warnings
from pathlib import Path

import numpy as np


def _import_pyfftw():
    """``import pyfftw`` without the numpy/scipy/dask drop-in interfaces its package imports
    (issue 24): pyfftw/__init__ imports ``pyfftw.interfaces``, which imports scipy.fftpack and
    dask.array (for pyfftw.interfaces.scipy_fft/dask_fft) when they are installed -- 85 % of the
    import (measured under load 12: 6.0-7.0 s against 1.0-1.1 s without them; at rest
    0.35-0.45 s of a 0.5-0.65 s start-up).  This package uses only pyfftw.FFTW, empty_aligned
    and the wisdom functions.  The two modules are marked absent (``sys.modules[name] = None``,
    the import system's documented way) during this one import, which pyfftw tolerates (it
    tries them in try/except ImportError), and unmarked right after: a later ``import
    dask.array`` or ``pyfftw.interfaces.scipy_fft`` works as usual.  Modules already imported
    are left alone (then pyfftw uses them, at no cost)."""
    import sys

    blocked = [m for m in ("dask.array.fft", "scipy.fftpack") if m not in sys.modules]
    for m in blocked:
        sys.modules[m] = None
    try:
        import pyfftw
    finally:
        for m in blocked:
            if m in sys.modules and sys.modules[m] is None:
                del sys.modules[m]
    return pyfftw


pyfftw = _import_pyfftw()

__all__ = ["RealFFT", "get_rfft", "plan_cache_info", "clear_plans", "set_planner_effort",
           "load_wisdom", "save_wisdom", "WISDOM_FILE", "planning_time"]

_EFFORTS = {"estimate": "FFTW_ESTIMATE", "measure": "FFTW_MEASURE", "patient": "FFTW_PATIENT"}
_PLANNER_EFFORT = _EFFORTS.get(os.environ.get("SPECTRAL_CONTACT_FFTW", "estimate").lower(),
                               "FFTW_ESTIMATE")
WISDOM_FILE = Path.home() / ".cache" / "spectral_contact" / "fftw_wisdom.txt"
_WISDOM_MAX_BYTES = 16 * 2**20
_plan_lock = threading.Lock()   # FFTW's planner is not thread-safe
_local = threading.local()      # per-thread plan caches


def _shape(shape) -> tuple[int, ...]:
    return (int(shape),) if np.isscalar(shape) else tuple(int(s) for s in shape)


class RealFFT:
    """A planned real-to-complex / complex-to-real transform pair over all axes.

    Parameters
    ----------
    shape : int or tuple of int
        Real-space shape; the half spectrum has shape ``shape[:-1] + (shape[-1] // 2 + 1,)``.
    planner_effort : str, optional
        "FFTW_ESTIMATE" (default), "FFTW_MEASURE" or "FFTW_PATIENT".
    threads : int
        FFTW threads per transform (1: the solver's transforms are small; parallelism is across
        scenes).

    An instance is not safe to share between threads (its buffers are its state): use
    ``get_rfft``, which keeps one per thread.
    """

    def __init__(self, shape, planner_effort: str | None = None, threads: int = 1):
        planner_effort = planner_effort or _PLANNER_EFFORT
        shape = _shape(shape)
        self.shape = shape
        self.n = shape[-1]
        self.threads = int(threads)
        kshape = shape[:-1] + (shape[-1] // 2 + 1,)
        axes = tuple(range(-len(shape), 0))
        t0 = time.perf_counter()
        self._r = pyfftw.empty_aligned(shape, dtype="float64")
        self._c = pyfftw.empty_aligned(kshape, dtype="complex128")
        with _plan_lock:
            self._fwd = pyfftw.FFTW(self._r, self._c, axes=axes, direction="FFTW_FORWARD",
                                    flags=(planner_effort,), threads=self.threads)
            self._bwd = pyfftw.FFTW(self._c, self._r, axes=axes, direction="FFTW_BACKWARD",
                                    flags=(planner_effort, "FFTW_DESTROY_INPUT"),
                                    threads=self.threads)
        self.plan_time_s = time.perf_counter() - t0
        self._scale = 1.0 / float(np.prod(shape))
        self._flat = self._r.reshape(-1)  # a view (the aligned buffer is contiguous)

    def forward(self, a: np.ndarray) -> np.ndarray:
        """rfft of a real array; returns a new complex array."""
        self._r[...] = a
        self._fwd.execute()
        return self._c.copy()

    def backward(self, c: np.ndarray) -> np.ndarray:
        """irfft (normalised by the number of points) of a half spectrum; returns a new real array."""
        self._c[...] = c
        self._bwd.execute()
        return self._r * self._scale

    def apply(self, a: np.ndarray, symbol: np.ndarray) -> np.ndarray:
        """Periodic convolution: irfft(symbol * rfft(a)), with one copy in and one out."""
        self._r[...] = a
        self._fwd.execute()
        self._c *= symbol
        self._bwd.execute()
        return self._r * self._scale


    def apply_sparse(self, values: np.ndarray, sel, symbol: np.ndarray,
                     out: np.ndarray | None = None) -> np.ndarray:
        """``apply`` to the field that holds ``values`` at the flat positions ``sel`` (an index
        array or a slice) and 0 elsewhere, without building that field: the same operations on
        the same data, bit for bit.  Returns the result gathered at ``sel`` into ``out`` or,
        without ``out``, the whole result (flat, a new array)."""
        r = self._flat
        r.fill(0.0)
        r[sel] = values
        self._fwd.execute()
        self._c *= symbol
        self._bwd.execute()
        if out is None:
            return r * self._scale
        return np.multiply(r[sel], self._scale, out=out)


    def sparse_applier(self, sel):
        """``apply_sparse`` at fixed positions ``sel``, as a function (values, symbol, out) ->
        out with its buffers and plans bound (the same operations: for loops of small
        transforms, where Python's attribute look-ups cost as much as the transform)."""
        r, c, scale = self._flat, self._c, self._scale
        fwd, bwd = self._fwd.execute, self._bwd.execute
        fill, multiply = r.fill, np.multiply

        def apply(values, symbol, out):
            fill(0.0)
            r[sel] = values
            fwd()
            multiply(c, symbol, out=c)
            bwd()
            return multiply(r[sel], scale, out=out)

        return apply


def _cache() -> dict:
    c = getattr(_local, "plans", None)
    if c is None:
        c = _local.plans = {}
    return c


def get_rfft(shape, threads: int = 1) -> RealFFT:
    """This thread's plan pair for ``shape`` (planned on first use)."""
    cache = _cache()
    try:  # fast path (once per matrix-vector product): shape already a tuple of ints
        plan = cache.get((shape, threads, _PLANNER_EFFORT))
    except TypeError:  # unhashable shape (a list)
        plan = None
    if plan is not None:
        return plan
    key = (_shape(shape), int(threads), _PLANNER_EFFORT)
    plan = cache.get(key)
    if plan is None:
        plan = cache[key] = RealFFT(key[0], key[2], key[1])
        if _PLANNER_EFFORT != "FFTW_ESTIMATE":
            save_wisdom()
    return plan


def set_planner_effort(effort: str) -> None:
    """"FFTW_ESTIMATE" (default), "FFTW_MEASURE" or "FFTW_PATIENT" for plans made from now on;
    measured plans load and store wisdom in WISDOM_FILE."""
    global _PLANNER_EFFORT
    if effort not in _EFFORTS.values():
        raise ValueError(f"effort must be one of {sorted(_EFFORTS.values())}; got {effort!r}")
    _PLANNER_EFFORT = effort
    if effort != "FFTW_ESTIMATE":
        load_wisdom()


def load_wisdom(path: Path | None = None) -> bool:
    """Import stored FFTW wisdom (double precision) if there is a valid file; returns whether
    it did.  A file that is not FFTW wisdom is ignored with one warning."""
    path = Path(path or WISDOM_FILE)
    try:
        if not path.is_file():
            return False
        data = path.read_bytes()[: _WISDOM_MAX_BYTES + 1]
    except OSError:
        return False
    ok = (len(data) <= _WISDOM_MAX_BYTES and data.startswith(b"(fftw-")
          and pyfftw.import_wisdom((data, b"", b""))[0])
    if not ok:
        warnings.warn(f"ignoring {path}: not FFTW wisdom (delete it to silence this warning)",
                      RuntimeWarning, stacklevel=2)
    return bool(ok)


def save_wisdom(path: Path | None = None) -> None:
    """Store FFTW's exported double-precision wisdom (text), atomically."""
    path = Path(path or WISDOM_FILE)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as fh:
                fh.write(pyfftw.export_wisdom()[0])
            os.replace(tmp, path)
        except BaseException:
            os.unlink(tmp)
            raise
    except OSError:
        pass  # wisdom is an optimisation: a read-only home must not break a solve


def plan_cache_info() -> dict:
    """This thread's planned (shape, threads, effort) keys and their planning times [s]."""
    return {k: v.plan_time_s for k, v in _cache().items()}


def planning_time() -> float:
    """Total planning time [s] of this thread's cached plans (a solver's plan_time_s is the
    difference across its solve)."""
    return sum(plan_cache_info().values())


def clear_plans() -> None:
    """Forget this thread's plans."""
    _cache().clear()


if _PLANNER_EFFORT != "FFTW_ESTIMATE":
    load_wisdom()
