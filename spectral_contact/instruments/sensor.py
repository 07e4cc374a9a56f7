"""MEMS sensor view of the base stresses: S = G (*) sigma and U = A S.

Plane strain: the base stresses do not depend on y, so the 2D convolution with an axisymmetric
apparatus function reduces to a 1D convolution with its line form (``apparatus.py``); it is done
through the package's FFT plan cache (``numerics.fft.get_rfft``).

Signs (the paper's): S_zz = -G_zz (*) sigma_zz(x, 0) is positive in compression;
S_xz = +G_xz (*) sigma_xz(x, 0), positive when the film drags the base toward +x (for mu > 0,
sliding toward +x, Int S_xz dx = +mu_d P_L).  U = A S with A in mV/bar (1 bar = 1e5 Pa), so
U_zz_mV = A_zz S_zz_Pa / 1e5.  The line forms have unit integral, so Int S_zz dx = P_L and
Int S_xz dx = mu_d P_L exactly (on the grid).
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..numerics.fft import get_rfft
from ..numerics.grid import Grid
from .apparatus import A_XZ_MV_PER_BAR, A_ZZ_MV_PER_BAR, PA_PER_BAR, ApparatusFunction, check_gain, default_apparatus

__all__ = ["sensor_view", "sensor_profiles", "convolve_line", "sensor_maps", "SENSOR_KEYS",
           "SENSOR_MAP_KEYS"]

SENSOR_KEYS = ("S_zz_Pa", "S_xz_Pa", "U_zz_mV", "U_xz_mV")


def _fast_size(n: int) -> int:
    """Smallest 2^a 3^b 5^c >= n."""
    best = 1 << max(int(n - 1).bit_length(), 0)
    p5 = 1
    while p5 < 2 * n:
        p35 = p5
        while p35 < 2 * n:
            m = p35
            while m < n:
                m *= 2
            best = min(best, m)
            p35 *= 3
        p5 *= 5
    return best


def _resolve(apparatus):
    """(G_zz, G_xz) from None, a pair, or a mapping with keys "zz", "xz" (None: paper's)."""
    dzz, dxz = default_apparatus()
    if apparatus is None:
        return dzz, dxz
    if isinstance(apparatus, dict):
        gzz, gxz = apparatus.get("zz"), apparatus.get("xz")
    else:
        try:
            gzz, gxz = apparatus
        except (TypeError, ValueError):
            raise InputError("apparatus must be None, a pair (G_zz, G_xz) or a dict with keys "
                             "'zz', 'xz'") from None
    gzz, gxz = gzz or dzz, gxz or dxz
    for g in (gzz, gxz):
        if not isinstance(g, ApparatusFunction):
            raise InputError(f"apparatus functions must be ApparatusFunction instances; got {g!r}")
    return gzz, gxz


def _check_grid(x_m) -> tuple[np.ndarray, float]:
    x = np.asarray(x_m, dtype=float)
    if x.ndim != 1 or x.size < 4:
        raise InputError("x_m must be a 1D array of at least 4 points")
    if not np.all(np.isfinite(x)):
        raise InputError("x_m has non-finite values")
    d = np.diff(x)
    dx = (x[-1] - x[0]) / (x.size - 1)
    if not (dx > 0) or np.max(np.abs(d - dx)) > 1e-6 * dx:
        raise InputError("x_m must be uniformly spaced and increasing (FFT convolution)")
    return x, float(dx)


def convolve_line(x_m, field, apparatus: ApparatusFunction, periodic: bool = False) -> np.ndarray:
    """g (*) field on the uniform grid x_m, with g the line form of ``apparatus``.

    periodic=True: the grid is one period (the FFT solver's grid): circular convolution.
    periodic=False: the field is taken as zero outside the grid (zero padding by the apparatus
    support, no wrap-around).
    """
    x, dx = _check_grid(x_m)
    f = np.asarray(field, dtype=float)
    if f.shape != x.shape:
        raise InputError(f"field has shape {f.shape}, x_m has {x.shape}")
    if not np.all(np.isfinite(f)):
        raise InputError("field has non-finite values")
    n = x.size
    if periodic:
        return get_rfft(n).apply(f, apparatus.line_symbol(n, dx))
    pad = int(np.ceil(apparatus.support_radius / dx)) + 1
    m = _fast_size(n + 2 * pad)
    buf = np.zeros(m)
    buf[:n] = f
    return get_rfft(m).apply(buf, apparatus.line_symbol(m, dx))[:n]


def sensor_profiles(x_m, sigma_zz_Pa, sigma_xz_Pa, A_zz_mV_per_bar: float = A_ZZ_MV_PER_BAR,
                    A_xz_mV_per_bar: float = A_XZ_MV_PER_BAR, apparatus=None,
                    periodic: bool = False) -> dict:
    """Sensor view of base-stress profiles given as plain arrays (SI).

    Parameters
    ----------
    x_m : uniform increasing abscissae [m]
    sigma_zz_Pa, sigma_xz_Pa : base stresses sigma_zz(x, 0) (< 0 in compression), sigma_xz(x, 0)
    A_zz_mV_per_bar, A_xz_mV_per_bar : conversion constants (> 0)
    apparatus : None (paper's G_zz, G_xz), a pair (G_zz, G_xz) or {"zz": .., "xz": ..}
    periodic : whether the arrays are one period of a periodic field (else zero outside)

    Returns {"S_zz_Pa", "S_xz_Pa", "U_zz_mV", "U_xz_mV"} on x_m.
    """
    a_zz = check_gain("A_zz", A_zz_mV_per_bar)
    a_xz = check_gain("A_xz", A_xz_mV_per_bar)
    gzz, gxz = _resolve(apparatus)
    s_zz = -convolve_line(x_m, sigma_zz_Pa, gzz, periodic)
    s_xz = convolve_line(x_m, sigma_xz_Pa, gxz, periodic)
    return {"S_zz_Pa": s_zz, "S_xz_Pa": s_xz,
            "U_zz_mV": s_zz * (a_zz / PA_PER_BAR), "U_xz_mV": s_xz * (a_xz / PA_PER_BAR)}


def check_line_result(result) -> None:
    """InputError unless ``result`` is a line result of ``solve`` (a 3D one: ``sensor_maps``)."""
    from ..result import ContactResult

    if isinstance(result, ContactResult):
        return
    if hasattr(result, "maps") and hasattr(result, "scene"):
        raise InputError("the sensor view of a 3D result is sensor_maps(result) "
                         "(spectral_contact.instruments.sensor); sensor() takes a line result")
    raise InputError(f"sensor() takes a result of solve() (a ContactResult); got "
                     f"{type(result).__name__}")


def sensor_view(result, A_zz_mV_per_bar: float = A_ZZ_MV_PER_BAR,
                A_xz_mV_per_bar: float = A_XZ_MV_PER_BAR, apparatus=None) -> dict:
    """Sensor view of a ``ContactResult`` on ``result.x`` (apex frame).

    A periodic solver grid (FFT, closed form: n dx = domain_length) is convolved circularly
    (exact on that grid); other abscissae (Abel nodes) with the fields taken as zero outside.
    Returns {"S_zz_Pa", "S_xz_Pa", "U_zz_mV", "U_xz_mV"}: S in Pa (S_zz > 0 in compression),
    U in mV.
    """
    check_line_result(result)
    x = np.asarray(result.x_m, dtype=float)
    szz, sxz = result.base_sigma_zz_Pa, result.base_sigma_xz_Pa
    d = np.diff(x)
    if x.size >= 4 and np.all(d > 0) and np.ptp(d) <= 1e-6 * d.mean():
        # one period of a periodic grid (FFT and closed-form solvers): n dx equals the period;
        # node sets with both ends (Abel) span (n - 1) dx and are convolved with zero padding
        L = float(getattr(result, "domain_length", 0.0) or 0.0) * result.scene.length_unit
        periodic = L > 0 and abs(x.size * d.mean() - L) <= 1e-9 * L
        return sensor_profiles(x, szz, sxz, A_zz_mV_per_bar, A_xz_mV_per_bar, apparatus,
                               periodic=periodic)
    # non-uniform abscissae (e.g. quadrature nodes): resample, convolve (zero outside), return
    if x.size < 2 or np.any(d <= 0):
        raise InputError("result.x must be increasing to compute the sensor view")
    n = int(min(max(4 * x.size, np.ptp(x) / d.min() + 1), 2**20))
    xu = np.linspace(x[0], x[-1], n)
    view = sensor_profiles(xu, np.interp(xu, x, szz), np.interp(xu, x, sxz), A_zz_mV_per_bar,
                           A_xz_mV_per_bar, apparatus, periodic=False)
    return {k: np.interp(x, xu, v) for k, v in view.items()}


SENSOR_MAP_KEYS = ("S_zz_Pa", "S_xz_Pa", "S_yz_Pa", "U_zz_mV", "U_xz_mV", "U_yz_mV")


def sensor_maps(result, A_zz_mV_per_bar: float = A_ZZ_MV_PER_BAR,
                A_xz_mV_per_bar: float = A_XZ_MV_PER_BAR, apparatus=None) -> dict:
    """MEMS view of a 3D result (``ContactResult3D``): the base tractions convolved with the 2D
    apparatus functions on the solver's periodic grid (exact circular convolution there).

    S_zz = -G_zz (*) sigma_zz(x, y, 0) (> 0 in compression), S_xz = G_xz (*) sigma_xz,
    S_yz = G_yz (*) sigma_yz with G_yz = G_xz and A_yz = A_xz (the paper's section 2).
    Returns (nx, ny) arrays [x, y]: S_* in Pa and U_* = A S in mV.
    """
    gzz, gxz = _resolve(apparatus)
    a_zz = check_gain("A_zz", A_zz_mV_per_bar)
    a_xz = check_gain("A_xz", A_xz_mV_per_bar)
    maps = result.maps()
    x, y = maps["x_m"], maps["y_m"]
    shape = (x.size, y.size)
    lengths = tuple(L * result.scene.length_unit for L in result.domain_length)  # the periods [m]
    grid = Grid(shape, lengths)
    fft = get_rfft(shape)
    if max(gzz.support_radius, gxz.support_radius) > 0.5 * min(lengths):
        raise InputError("the apparatus function is wider than half the solver's period: "
                         "fix a larger domain_length")
    sym_zz = np.asarray(gzz.transform(grid.kmag), dtype=float)
    sym_xz = np.asarray(gxz.transform(grid.kmag), dtype=float)
    S_zz = -fft.apply(maps["base_sigma_zz_Pa"], sym_zz)
    S_xz = fft.apply(maps["base_sigma_xz_Pa"], sym_xz)
    S_yz = fft.apply(maps["base_sigma_yz_Pa"], sym_xz)
    return {"S_zz_Pa": S_zz, "S_xz_Pa": S_xz, "S_yz_Pa": S_yz,
            "U_zz_mV": a_zz * S_zz / PA_PER_BAR, "U_xz_mV": a_xz * S_xz / PA_PER_BAR,
            "U_yz_mV": a_xz * S_yz / PA_PER_BAR}
