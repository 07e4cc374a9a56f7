"""Real FFTs through pyfftw, planned once per size and reused.

``RealFFT(n)`` owns aligned input/output buffers and two FFTW plans (r2c and c2r).  ``get_rfft(n)``
returns a cached instance, so every solve on the same grid shares one pair of plans.  Wisdom is
kept in-process (pyfftw keeps it) and can be exported with ``export_wisdom``.

Convention (numpy's): forward f^_k = sum_j f_j exp(-2 pi i jk/n); backward divides by n.

Planner effort: FFTW_ESTIMATE by default (planning costs milliseconds; a transform pair is
1.2-1.8x slower than with FFTW_MEASURE from N = 2^14 on, up to 2.9x seen at 2^18, and no
slower below, while MEASURE planning costs ~0.4 s at 2^10 and 13-40 s at 2^18-2^20:
studies/large_domain).  Set the environment variable SPECTRAL_CONTACT_FFTW=measure (or call
``set_planner_effort("FFTW_MEASURE")``) for long sweeps; measured plans are then stored as FFTW
wisdom in ``~/.cache/spectral_contact/fftw_wisdom`` and reused by later runs.
"""
from __future__ import annotations

import os
import pickle
import threading
import time
from pathlib import Path

import numpy as np
import pyfftw

__all__ = ["RealFFT", "get_rfft", "plan_cache_info", "clear_plans"]

_EFFORTS = {"estimate": "FFTW_ESTIMATE", "measure": "FFTW_MEASURE", "patient": "FFTW_PATIENT"}
_PLANNER_EFFORT = _EFFORTS.get(os.environ.get("SPECTRAL_CONTACT_FFTW", "estimate").lower(),
                               "FFTW_ESTIMATE")
WISDOM_FILE = Path.home() / ".cache" / "spectral_contact" / "fftw_wisdom"
_lock = threading.Lock()
_cache: dict[tuple[int, ...], RealFFT] = {}


class RealFFT:
    """A planned real-to-complex / complex-to-real transform pair along the last axis.

    Parameters
    ----------
    shape : int or tuple of int
        Real-space shape (the transform runs along the last axis; 2D shapes transform both axes).
    """

    def __init__(self, shape, planner_effort: str | None = None):
        planner_effort = planner_effort or _PLANNER_EFFORT
        shape = (int(shape),) if np.isscalar(shape) else tuple(int(s) for s in shape)
        self.shape = shape
        self.n = shape[-1]
        kshape = shape[:-1] + (shape[-1] // 2 + 1,)
        axes = tuple(range(-len(shape), 0))
        t0 = time.perf_counter()
        self._r = pyfftw.empty_aligned(shape, dtype="float64")
        self._c = pyfftw.empty_aligned(kshape, dtype="complex128")
        self._fwd = pyfftw.FFTW(self._r, self._c, axes=axes, direction="FFTW_FORWARD",
                                flags=(planner_effort,), threads=1)
        self._bwd = pyfftw.FFTW(self._c, self._r, axes=axes, direction="FFTW_BACKWARD",
                                flags=(planner_effort, "FFTW_DESTROY_INPUT"), threads=1)
        self.plan_time_s = time.perf_counter() - t0
        self._scale = 1.0 / float(np.prod(shape))

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


def get_rfft(shape) -> RealFFT:
    """The cached plan pair for this shape (planned on first use)."""
    key = (int(shape),) if np.isscalar(shape) else tuple(int(s) for s in shape)
    with _lock:
        plan = _cache.get(key)
        if plan is None:
            plan = _cache[key] = RealFFT(key)
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


def load_wisdom() -> bool:
    """Import stored FFTW wisdom if there is any; returns whether it did."""
    try:
        pyfftw.import_wisdom(pickle.loads(WISDOM_FILE.read_bytes()))
        return True
    except (OSError, ValueError, pickle.UnpicklingError, EOFError):
        return False


def save_wisdom() -> None:
    try:
        WISDOM_FILE.parent.mkdir(parents=True, exist_ok=True)
        WISDOM_FILE.write_bytes(pickle.dumps(pyfftw.export_wisdom()))
    except OSError:
        pass  # wisdom is an optimisation: a read-only home must not break a solve


def plan_cache_info() -> dict:
    """Shapes currently planned and their planning times [s]."""
    return {k: v.plan_time_s for k, v in _cache.items()}


def clear_plans() -> None:
    with _lock:
        _cache.clear()


if _PLANNER_EFFORT != "FFTW_ESTIMATE":
    load_wisdom()
