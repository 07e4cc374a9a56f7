"""The MEMS sensor's view of a result, as an object: ``sensor(result) -> SensorView``.

    >>> from spectral_contact import solve, sensor
    >>> v = sensor(solve())                       # the paper's apparatus functions and gains
    >>> v.S_zz_peak_Pa, v.S_zz_peak_x_m, v.U_xz_peak_mV
    >>> v.profiles()                              # x_m, S_zz_Pa, S_xz_Pa, U_zz_mV, U_xz_mV

Signs (the paper's): S_zz = -G_zz (*) sigma_zz(x, 0) > 0 in compression; S_xz = G_xz (*)
sigma_xz(x, 0), positive when the film drags the base toward +x.  U = A S with A in mV/bar
(1 bar = 1e5 Pa).  Positions in the apex frame of the result, +x the sliding direction.
The profiles are those of ``instruments.sensor.sensor_view`` (same numbers).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..numerics.edges import peak
from .apparatus import A_XZ_MV_PER_BAR, A_ZZ_MV_PER_BAR, PA_PER_BAR, default_apparatus
from .sensor import sensor_view

__all__ = ["SensorView", "sensor", "SENSOR_JSON_KEYS", "SENSOR_COLUMNS"]

SENSOR_JSON_KEYS = ("S_zz_peak_Pa", "S_zz_peak_x_m", "S_xz_peak_Pa", "S_xz_peak_x_m",
                    "U_zz_peak_mV", "U_xz_peak_mV", "A_zz_mV_per_bar", "A_xz_mV_per_bar",
                    "apparatus_zz", "apparatus_xz")
SENSOR_COLUMNS = ("S_zz_Pa", "S_xz_Pa", "U_zz_mV", "U_xz_mV")


def _signed_peak(x, f):
    """(value, position) of the largest |f|, refined by a parabola; (0, nan) if f is all 0."""
    f = np.asarray(f, dtype=float)
    if f.size == 0 or not np.any(f):
        return 0.0, float("nan")
    sign = 1.0 if f.max() >= -f.min() else -1.0
    d = np.diff(x)
    if x.size >= 3 and np.ptp(d) <= 1e-6 * d.mean():  # uniform: parabolic refinement
        v, xm = peak(x, sign * f)
        return sign * v, xm
    j = int(np.argmax(sign * f))
    return float(f[j]), float(x[j])


@dataclass(repr=False, eq=False)
class SensorView:
    """What the MEMS sensor sees of one ``ContactResult`` (all SI, apex frame).

    Arrays: x_m [m], S_zz_Pa, S_xz_Pa [Pa] (S_zz > 0 in compression), U_zz_mV, U_xz_mV [mV].
    Peaks (largest |value|, sub-grid by a parabola on uniform grids): S_zz_peak_Pa at
    S_zz_peak_x_m, S_xz_peak_Pa (signed) at S_xz_peak_x_m; U_*_peak_mV = A S_*_peak / 1e5 (same
    positions).  A_zz_mV_per_bar, A_xz_mV_per_bar: the gains; apparatus_zz, apparatus_xz: what G
    was used (text).  ``to_dict()`` gives the JSON keys (``SENSOR_JSON_KEYS``), each also an
    attribute; ``profiles()`` the arrays named like the CSV columns.
    """

    x_m: np.ndarray
    S_zz_Pa: np.ndarray
    S_xz_Pa: np.ndarray
    U_zz_mV: np.ndarray
    U_xz_mV: np.ndarray
    A_zz_mV_per_bar: float
    A_xz_mV_per_bar: float
    apparatus_zz: str
    apparatus_xz: str

    def __post_init__(self):
        self.S_zz_peak_Pa, self.S_zz_peak_x_m = _signed_peak(self.x_m, self.S_zz_Pa)
        self.S_xz_peak_Pa, self.S_xz_peak_x_m = _signed_peak(self.x_m, self.S_xz_Pa)
        self.U_zz_peak_mV = self.S_zz_peak_Pa * self.A_zz_mV_per_bar / PA_PER_BAR
        self.U_xz_peak_mV = self.S_xz_peak_Pa * self.A_xz_mV_per_bar / PA_PER_BAR

    def to_dict(self) -> dict:
        """The sensor's JSON keys (``solve --sensor --json`` adds them to the result's)."""
        return {k: getattr(self, k) for k in SENSOR_JSON_KEYS}

    def profiles(self) -> dict:
        """x_m and the S, U profiles (SI; the names of the CSV columns)."""
        return {"x_m": self.x_m, **{k: getattr(self, k) for k in SENSOR_COLUMNS}}

    def __getitem__(self, key):  # dict-style access, as sensor_view's dict
        return self.profiles()[key]

    def __repr__(self) -> str:
        mm, kPa = 1e3, 1e-3
        return (f"<SensorView: S_zz peak {self.S_zz_peak_Pa * kPa:.5g} kPa at x = "
                f"{self.S_zz_peak_x_m * mm:.4g} mm, S_xz peak {self.S_xz_peak_Pa * kPa:.5g} kPa at "
                f"x = {self.S_xz_peak_x_m * mm:.4g} mm (U_zz {self.U_zz_peak_mV:.4g} mV, U_xz "
                f"{self.U_xz_peak_mV:.4g} mV); A_zz = {self.A_zz_mV_per_bar:g}, A_xz = "
                f"{self.A_xz_mV_per_bar:g} mV/bar>")


def sensor(result, A_zz_mV_per_bar: float = A_ZZ_MV_PER_BAR, A_xz_mV_per_bar: float = A_XZ_MV_PER_BAR,
           apparatus=None) -> SensorView:
    """The MEMS view of ``result`` (a ``ContactResult``).

    A_zz_mV_per_bar, A_xz_mV_per_bar : gains [mV/bar] (paper: 19.00, 7.95).
    apparatus : None (the paper's G_zz, G_xz), a pair (G_zz, G_xz) of ``ApparatusFunction``
        (either may be None: the paper's), or {"zz": .., "xz": ..}; e.g. a calibrated G from
        ``instruments.apparatus.load_apparatus_csv("G.csv")`` (what ``calibrate --out`` writes).
    """
    view = sensor_view(result, A_zz_mV_per_bar=A_zz_mV_per_bar, A_xz_mV_per_bar=A_xz_mV_per_bar,
                       apparatus=apparatus)
    dzz, dxz = default_apparatus()
    if apparatus is None:
        gzz = gxz = None
    elif isinstance(apparatus, dict):
        gzz, gxz = apparatus.get("zz"), apparatus.get("xz")
    else:
        gzz, gxz = apparatus
    return SensorView(np.asarray(result.x_m, dtype=float), view["S_zz_Pa"], view["S_xz_Pa"],
                      view["U_zz_mV"], view["U_xz_mV"], float(A_zz_mV_per_bar), float(A_xz_mV_per_bar),
                      repr(gzz or dzz), repr(gxz or dxz))
