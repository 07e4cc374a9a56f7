"""Reading and checking the maps of the surface inverse (issue 21): ``read_maps`` (NPZ) and the
checks of axes and arrays (one line naming the file and the key, InputError)."""
from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["read_maps", "check_maps", "VIEWS", "MIN_POINTS"]

MIN_POINTS = 8
VIEWS = {"base": ("base_sigma_zz_Pa", "base_sigma_xz_Pa", "base_sigma_yz_Pa"),
         "sensor": ("S_zz_Pa", "S_xz_Pa", "S_yz_Pa")}
_VIEWS = VIEWS


def _check_axis(a, name, src):
    a = np.asarray(a, dtype=float)
    if a.ndim != 1:
        raise InputError(f"{src}{name} must be a 1D array; got shape {a.shape}")
    if a.size < MIN_POINTS:
        raise InputError(f"{src}{name} has {a.size} points; the inversion needs at least "
                         f"{MIN_POINTS} along each axis")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{src}{name} has non-finite values")
    d = np.diff(a)
    step = (a[-1] - a[0]) / (a.size - 1)
    if np.any(d <= 0) or np.max(np.abs(d - step)) > 1e-3 * step:
        raise InputError(f"{src}{name} must be strictly increasing and uniformly spaced "
                         f"(within 0.1 %)")
    return a


def _check_maps(x_m, y_m, fields, names, src=""):
    x = _check_axis(x_m, "x_m", src)
    y = _check_axis(y_m, "y_m", src)
    out = []
    for f, nm in zip(fields, names):
        f = np.asarray(f, dtype=float)
        if f.shape != (x.size, y.size):
            raise InputError(f"{src}{nm} has shape {f.shape}; x_m and y_m need "
                             f"({x.size}, {y.size}) (arrays indexed [x, y])")
        if not np.all(np.isfinite(f)):
            raise InputError(f"{src}{nm} has non-finite values")
        out.append(f)
    if not any(np.any(f) for f in out):
        raise InputError(f"{src}the maps are zero everywhere: nothing to invert")
    from .inverse import VALUE_RANGE_PA  # the line inverse's range (the evidence squares them)

    big = max(float(np.max(np.abs(f))) for f in out)
    if not VALUE_RANGE_PA[0] <= big <= VALUE_RANGE_PA[1]:
        raise InputError(f"{src}the maps' largest |stress| is {big:.3g} Pa: the inversion takes "
                         f"{VALUE_RANGE_PA[0]:g} ... {VALUE_RANGE_PA[1]:g} Pa")
    return x, y, out


def read_maps(path):
    """Base-stress maps from an NPZ: ``x_m, y_m`` and either ``base_sigma_zz_Pa,
    base_sigma_xz_Pa, base_sigma_yz_Pa`` (the package's ``--maps`` keys and signs: sigma_zz < 0
    in compression) or ``S_zz_Pa, S_xz_Pa, S_yz_Pa`` (the MEMS view, S_zz > 0 in compression),
    arrays [x, y]; one view per file (a ``solve --maps --sensor`` file holds both: refused,
    keep one).  Returns (x_m, y_m, (d_zz, d_xz,
    d_yz), view) with d_zz > 0 in compression.  Raises InputError (one line naming the file)."""
    import zipfile

    name = str(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            keys = set(z.files)
            arrays = {k: z[k] for k in keys if k in {"x_m", "y_m", *_VIEWS["base"],
                                                     *_VIEWS["sensor"]}}
    except FileNotFoundError:
        raise InputError(f"{name}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{name}: is a directory, not an NPZ file") from None
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as e:
        raise InputError(f"{name}: not a readable NPZ file ({type(e).__name__})") from None
    want = " or ".join("x_m, y_m, " + ", ".join(v) for v in _VIEWS.values())
    for k in ("x_m", "y_m"):
        if k not in keys:
            raise InputError(f"{name}: missing {k}; need {want}")
    present = [v for v, ks in _VIEWS.items() if any(k in keys for k in ks)]
    if not present:
        raise InputError(f"{name}: no stress maps; need {want}")
    if len(present) > 1:
        raise InputError(f"{name}: mixes views (base_sigma_* and S_*, as solve --maps --sensor "
                         f"writes); keep one in the file: {want}")
    view = present[0]
    miss = [k for k in _VIEWS[view] if k not in keys]
    if miss:
        raise InputError(f"{name}: missing {', '.join(miss)}; need {want}")
    x, y, (zz, xz, yz) = _check_maps(arrays["x_m"], arrays["y_m"],
                                     [arrays[k] for k in _VIEWS[view]], _VIEWS[view],
                                     src=f"{name}: ")
    return x, y, ((-zz if view == "base" else zz), xz, yz), view


check_maps = _check_maps
