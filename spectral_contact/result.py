"""The result object shared by every solver (FFT, Abel, Hertz) and every model (exact, Goodman).

Internally everything is dimensionless (see ``physics.scene``); the ``*_m``, ``*_Pa`` properties
convert to SI.  Positions are measured from the indenter apex, +x the sliding direction
(for mu > 0).  Stress sign convention of the model: sigma_zz < 0 in compression.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .physics.scene import Scene

__all__ = ["ContactResult", "ContactResult3D", "JSON_KEYS", "JSON_KEYS_3D", "MAP_KEYS",
           "PROFILE_COLUMNS", "COUNTER_KEYS"]

COUNTER_KEYS = ("transforms", "iterations", "linear_iterations")
"""Work counters every method fills (``ContactResult.counters``): FFT pairs (forward +
backward; 0 where none are used), outer iterations (active-set, or root finding on the
half-width) and inner ones (GMRES matrix-vector products, or Nystrom solves), summed over every
level of the resolution control."""

JSON_KEYS = (
    "model", "method", "load_N_per_m", "mu", "young_Pa", "radius_m", "thickness_m",
    "half_width_m", "contact_center_m", "x0_m", "indentation_m", "max_pressure_Pa",
    "max_pressure_x_m", "grid_points", "domain_length_m", "iterations", "residual",
    "error_estimate", "wall_time_s", "plan_time_s",
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
    (solve only), plan_time_s (FFT planning), info (free-form dict: method details),
    counters (``COUNTER_KEYS``: transforms, iterations, linear_iterations; the same for every
    method).
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
    counters: dict = field(default_factory=lambda: dict.fromkeys(COUNTER_KEYS, 0))

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


JSON_KEYS_3D = (
    "model", "method", "indenter", "force_N", "mu", "young_Pa", "radius_m", "thickness_m",
    "contact_area_m2", "contact_radius_m", "contact_x_min_m", "contact_x_max_m",
    "contact_y_half_width_m", "pressure_centroid_x_m", "indentation_m", "max_pressure_Pa",
    "max_pressure_x_m", "max_pressure_y_m", "line_load_y0_N_per_m", "grid_points",
    "domain_length_m", "iterations", "residual", "error_estimate", "wall_time_s", "plan_time_s",
)
"""JSON keys of a 3D result (+ length_m for a cylinder, radius_x_m and radius_y_m for a
paraboloid)."""
MAP_KEYS = ("x_m", "y_m", "pressure_Pa", "base_sigma_zz_Pa", "base_sigma_xz_Pa", "base_sigma_yz_Pa",
            "surface_ux_m", "surface_uy_m", "surface_uz_m")


@dataclass
class ContactResult3D:
    """Solution of one 3D scene (``physics.scene.Scene3D``): fields on the surface grid.

    Dimensionless (lengths in h, displacements in h^2/2R, stresses in E h/6R), arrays indexed
    [x, y] on the axes ``x`` (nx) and ``y`` (ny), apex at (0, 0), x the sliding direction:

    pressure                       p >= 0 (= -sigma_zz(x, y, h))
    base_sigma_zz, _xz, _yz        base tractions (sigma_zz < 0 in compression)
    surface_ux, _uy, _uz           surface displacements (u_z > 0 upward: the film sinks, u_z < 0)
    measures : dict                area, x_min, x_max, y_min, y_max, pmax, xmax, ymax, xc,
                                   load, line_load_y0 (``numerics.measure2d``), indentation
    error_estimate                 relative, of the contact radius, extents, centroid (relative
                                   to the radius), indentation and peak pressure
    counters                       transforms, iterations, linear_iterations
    """

    scene: object
    model: str
    method: str
    x: np.ndarray
    y: np.ndarray
    pressure: np.ndarray
    base_sigma_zz: np.ndarray
    base_sigma_xz: np.ndarray
    base_sigma_yz: np.ndarray
    surface_ux: np.ndarray
    surface_uy: np.ndarray
    surface_uz: np.ndarray
    measures: dict
    grid_points: tuple
    domain_length: tuple
    iterations: int
    residual: float
    error_estimate: float
    wall_time_s: float = 0.0
    plan_time_s: float = 0.0
    info: dict = field(default_factory=dict)
    counters: dict = field(default_factory=lambda: dict.fromkeys(COUNTER_KEYS, 0))

    @property
    def indentation(self) -> float:
        return self.measures["indentation"]

    @property
    def contact_radius(self) -> float:
        """sqrt(area / pi), in h."""
        return float(np.sqrt(self.measures["area"] / np.pi))

    def summary(self) -> dict:
        """The JSON record (all SI); see ``JSON_KEYS_3D``."""
        s, L = self.scene, self.scene.length_unit
        m, S = self.measures, self.scene.stress_unit
        out = {
            "model": self.model, "method": self.method, "indenter": s.indenter,
            "force_N": s.force, "mu": s.mu, "young_Pa": s.young, "radius_m": s.radius,
            "thickness_m": s.thickness,
        }
        if s.indenter == "cylinder":
            out["length_m"] = s.length
        if s.indenter == "paraboloid":
            out["radius_x_m"], out["radius_y_m"] = s.radius_x, s.radius_y
        out.update({
            "contact_area_m2": float(m["area"] * L * L),
            "contact_radius_m": float(self.contact_radius * L),
            "contact_x_min_m": float(m["x_min"] * L) + 0.0,
            "contact_x_max_m": float(m["x_max"] * L) + 0.0,
            "contact_y_half_width_m": float(0.5 * (m["y_max"] - m["y_min"]) * L),
            "pressure_centroid_x_m": float(m["xc"] * L) + 0.0,
            "indentation_m": float(m["indentation"] * s.displacement_unit),
            "max_pressure_Pa": float(m["pmax"] * S),
            "max_pressure_x_m": float(m["xmax"] * L) + 0.0,
            "max_pressure_y_m": float(m["ymax"] * L) + 0.0,
            "line_load_y0_N_per_m": float(m["line_load_y0"] * S * L),
            "grid_points": [int(n) for n in self.grid_points],
            "domain_length_m": [float(d * L) for d in self.domain_length],
            "iterations": int(self.iterations),
            "residual": float(self.residual),
            "error_estimate": float(self.error_estimate),
            "wall_time_s": float(self.wall_time_s),
            "plan_time_s": float(self.plan_time_s),
        })
        return out

    def maps(self) -> dict:
        """The surface and base fields in SI, named as ``MAP_KEYS`` ((nx, ny) arrays [x, y])."""
        s = self.scene
        L, S, U = s.length_unit, s.stress_unit, s.displacement_unit
        return {
            "x_m": self.x * L, "y_m": self.y * L,
            "pressure_Pa": self.pressure * S,
            "base_sigma_zz_Pa": self.base_sigma_zz * S,
            "base_sigma_xz_Pa": self.base_sigma_xz * S,
            "base_sigma_yz_Pa": self.base_sigma_yz * S,
            "surface_ux_m": self.surface_ux * U,
            "surface_uy_m": self.surface_uy * U,
            "surface_uz_m": self.surface_uz * U,
        }

    def profiles(self) -> dict:
        """The y = 0 line (the grid line nearest it) in SI, with the 2D profile columns."""
        j = int(np.argmin(np.abs(self.y)))
        s = self.scene
        L, S = s.length_unit, s.stress_unit
        return {
            "x_m": self.x * L,
            "pressure_Pa": self.pressure[:, j] * S,
            "surface_shear_Pa": s.mu * self.pressure[:, j] * S,
            "base_sigma_zz_Pa": self.base_sigma_zz[:, j] * S,
            "base_sigma_xz_Pa": self.base_sigma_xz[:, j] * S,
        }
