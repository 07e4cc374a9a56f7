"""The result object shared by every solver (FFT, Abel, Hertz) and every model (exact, Goodman).

Internally everything is dimensionless (see ``physics.scene``); the ``*_m``, ``*_Pa`` properties
convert to SI.  Positions are measured from the indenter apex, +x the sliding direction
(for mu > 0).  Stress sign convention of the model: sigma_zz < 0 in compression.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .physics.scene import Scene

__all__ = ["ContactResult", "JSON_KEYS", "PROFILE_COLUMNS"]

JSON_KEYS = (
    "model", "method", "load_N_per_m", "mu", "young_Pa", "radius_m", "thickness_m",
    "half_width_m", "contact_center_m", "x0_m", "indentation_m", "max_pressure_Pa",
    "max_pressure_x_m", "grid_points", "domain_length_m", "iterations", "residual",
    "error_estimate", "tolerance_met", "wall_time_s", "plan_time_s",
)
PROFILE_COLUMNS = ("x_m", "pressure_Pa", "surface_shear_Pa", "base_sigma_zz_Pa", "base_sigma_xz_Pa")


@dataclass
class ContactResult:
    """Solution of one scene.

    Dimensionless fields (lengths in h, displacements in h^2/2R, stresses in E h/6R):

    x : ndarray            profile abscissae, apex frame
    pressure : ndarray     p(x) >= 0, the contact pressure (= -sigma_zz(x, h))
    base_sigma_zz : ndarray   sigma_zz(x, 0) at the rigid base (< 0 in compression)
    base_sigma_xz : ndarray   sigma_xz(x, 0) at the rigid base
    half_width : float     a, contact half-width
    center : float         x_c, contact centre relative to the apex (paper's x0 = -x_c)
    indentation : float    d, indentation depth (paper's 1/alpha), in h^2/(2R)
    max_pressure, max_pressure_x : float   peak of p and where it sits

    Diagnostics: grid_points, domain_length (in h), iterations, residual (dimensionless,
    relative), error_estimate (relative, of a, x_c, d and the peak pressure), wall_time_s
    (solve only), plan_time_s (FFT planning), info (free-form dict: method details).
    """

    scene: Scene
    model: str
    method: str
    x: np.ndarray
    pressure: np.ndarray
    base_sigma_zz: np.ndarray
    base_sigma_xz: np.ndarray
    half_width: float
    center: float
    indentation: float
    max_pressure: float
    max_pressure_x: float
    grid_points: int
    domain_length: float
    iterations: int
    residual: float
    error_estimate: float
    wall_time_s: float = 0.0
    plan_time_s: float = 0.0
    info: dict = field(default_factory=dict)

    @property
    def tolerance_met(self) -> bool:
        """Whether error_estimate is within the tolerance asked for (False only when the
        resolution was fixed by the user, ``grid_points``, and is too coarse for ``tol``)."""
        return bool(self.info.get("tolerance_met", True))

    # --- SI views -----------------------------------------------------------------------------
    @property
    def surface_shear(self) -> np.ndarray:
        """sigma_xz(x, h) = mu_d p(x) (Amontons), dimensionless."""
        return self.scene.mu * self.pressure

    @property
    def x0(self) -> float:
        """The paper's x0: apex position relative to the contact centre (= -center), in h."""
        return -self.center + 0.0

    @property
    def x_m(self):
        return self.x * self.scene.length_unit

    @property
    def pressure_Pa(self):
        return self.pressure * self.scene.stress_unit

    @property
    def surface_shear_Pa(self):
        return self.surface_shear * self.scene.stress_unit

    @property
    def base_sigma_zz_Pa(self):
        return self.base_sigma_zz * self.scene.stress_unit

    @property
    def base_sigma_xz_Pa(self):
        return self.base_sigma_xz * self.scene.stress_unit

    @property
    def half_width_m(self) -> float:
        return self.half_width * self.scene.length_unit

    @property
    def contact_center_m(self) -> float:
        return self.center * self.scene.length_unit

    @property
    def indentation_m(self) -> float:
        return self.indentation * self.scene.displacement_unit

    def summary(self) -> dict:
        """The JSON record (all SI); see ``JSON_KEYS``."""
        s, L = self.scene, self.scene.length_unit
        return {
            "model": self.model,
            "method": self.method,
            "load_N_per_m": s.load,
            "mu": s.mu,
            "young_Pa": s.young,
            "radius_m": s.radius,
            "thickness_m": s.thickness,
            "half_width_m": float(self.half_width * L),
            "contact_center_m": float(self.center * L) + 0.0,
            "x0_m": float(-self.center * L) + 0.0,  # + 0.0: no "-0.0" for a centred contact
            "indentation_m": float(self.indentation * s.displacement_unit),
            "max_pressure_Pa": float(self.max_pressure * s.stress_unit),
            "max_pressure_x_m": float(self.max_pressure_x * L),
            "grid_points": int(self.grid_points),
            "domain_length_m": float(self.domain_length * L),
            "iterations": int(self.iterations),
            "residual": float(self.residual),
            "error_estimate": float(self.error_estimate),
            "tolerance_met": self.tolerance_met,
            "wall_time_s": float(self.wall_time_s),
            "plan_time_s": float(self.plan_time_s),
        } | ({"auto_reason": self.info["auto_reason"]} if "auto_reason" in self.info else {})

    def profiles(self) -> dict:
        """Profile columns in SI (see ``PROFILE_COLUMNS``), apex frame."""
        return {
            "x_m": self.x_m,
            "pressure_Pa": self.pressure_Pa,
            "surface_shear_Pa": self.surface_shear_Pa,
            "base_sigma_zz_Pa": self.base_sigma_zz_Pa,
            "base_sigma_xz_Pa": self.base_sigma_xz_Pa,
        }
