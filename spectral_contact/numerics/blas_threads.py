"""One BLAS thread for small dense algebra (issue 21's speed).

The inverses (``instruments.inverse*``) spend their time in hundreds of products and
factorisations of matrices of order 60-300.  OpenBLAS splits such a product over every core it
sees; at that size the threads' start-up and spin-waiting cost more than the product, and
``time.process_time`` counts every thread (measured on the shared 2-core machine, one
contact-prior evidence evaluation with its gradient, 61 nodes: 0.71 ms of CPU with one thread,
16 ms with two while one other process ran, 1.4 ms with two at a load of 0.4 in an earlier
session; a 160^2 surface map's inversion 4.2 s against 18 s CPU at a load of 1.5-2; studies/
README, inverse and inverse_maps, Speed).  ``single_blas_thread()`` holds the BLAS
libraries loaded in this process at one thread for the duration of a ``with`` block (or of a
function decorated with it) and restores their count afterwards, as ``OPENBLAS_NUM_THREADS=1``
would for the whole process; the results are bit for bit those of that setting (the thread
count changes only the rounding of a product, but the evidence's optimisers follow it).

Which libraries: the OpenBLAS builds loaded in the process (numpy's and scipy's wheels each
carry one), found in ``/proc/self/maps`` and driven through their
``[scipy_]openblas_{get,set}_num_threads[64_]`` entry points.  Elsewhere (no /proc, another
BLAS: Accelerate, MKL) it does nothing.  Nested and concurrent blocks share one count: the
first to enter sets one thread, the last to leave restores the number found on entry.
"""
from __future__ import annotations

import ctypes
import functools
import sys
import threading

__all__ = ["single_blas_thread", "blas_thread_counts"]

_PREFIXES = ("scipy_openblas", "openblas")
_SUFFIXES = ("64_", "", "_64_", "_")
_lock = threading.Lock()
_state = {"depth": 0, "saved": [], "held": [], "libs": None, "light": None}


def _openblas_libraries():
    """[(get, set)] ctypes functions of the OpenBLAS libraries loaded in this process."""
    paths = []
    try:
        with open("/proc/self/maps") as fh:
            for line in fh:
                parts = line.split()
                p = parts[-1] if len(parts) >= 6 else ""
                if "openblas" in p.lower() and ".so" in p and p not in paths:
                    paths.append(p)
    except OSError:
        return []
    out = []
    for p in paths:
        try:
            lib = ctypes.CDLL(p)
        except OSError:
            continue
        for pre in _PREFIXES:
            fns = None
            for suf in _SUFFIXES:
                try:
                    g = getattr(lib, f"{pre}_get_num_threads{suf}")
                    s = getattr(lib, f"{pre}_set_num_threads{suf}")
                except AttributeError:
                    continue
                g.restype, g.argtypes = ctypes.c_int, []
                s.restype, s.argtypes = None, [ctypes.c_int]
                fns = (g, s)
                break
            if fns is not None:
                out.append(fns)
                break
    return out


def _libraries(load_scipy: bool = True):
    """The OpenBLAS builds' (get, set) functions: numpy's and scipy's (scipy.linalg imported
    first, so that its build is loaded).  ``load_scipy`` False (the line solver, which uses
    no scipy BLAS): without importing scipy.linalg (~60 ms, once per process) when it is not
    imported yet, the builds loaded now (numpy's)."""
    if not load_scipy and _state["libs"] is None and "scipy.linalg" not in sys.modules:
        if _state["light"] is None:
            import numpy  # noqa: F401

            _state["light"] = _openblas_libraries()
        return _state["light"]
    if _state["libs"] is None:
        import numpy  # noqa: F401  (load numpy's and scipy's BLAS before looking)
        import scipy.linalg  # noqa: F401

        _state["libs"] = _openblas_libraries()
    return _state["libs"]


def blas_thread_counts() -> list[int]:
    """The thread count of each OpenBLAS library loaded in this process (empty if none found)."""
    return [int(g()) for g, _ in _libraries()]


class _SingleBlasThread:
    def __init__(self, load_scipy: bool = True):
        self.load_scipy = load_scipy

    def __enter__(self):
        with _lock:
            if _state["depth"] == 0:
                libs = _state["held"] = _libraries(self.load_scipy)
                _state["saved"] = [int(g()) for g, _ in libs]
                for (_, s), n in zip(libs, _state["saved"]):
                    if n != 1:
                        s(1)
            _state["depth"] += 1
        return self

    def __exit__(self, *exc):
        with _lock:
            _state["depth"] -= 1
            if _state["depth"] == 0:  # (the builds held on entry: the list may have grown)
                for (_, s), n in zip(_state["held"], _state["saved"]):
                    if n != 1:
                        s(n)
        return False

    def __call__(self, fn):
        @functools.wraps(fn)
        def wrapped(*args, **kwargs):
            with self:
                return fn(*args, **kwargs)

        return wrapped


def single_blas_thread(load_scipy: bool = True) -> _SingleBlasThread:
    """A context manager (and decorator) holding the process's OpenBLAS at one thread (module
    docstring); ``load_scipy`` False: the builds already loaded, without importing
    scipy.linalg for its own (``_libraries``)."""
    return _SingleBlasThread(load_scipy)
