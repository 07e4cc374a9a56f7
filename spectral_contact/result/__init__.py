"""The result of a solve, one type that knows its dimension: ``Result`` carries what lines and
surfaces share; ``ContactResult`` (a line, ``dimension`` "line") and ``ContactResult3D`` (a
surface, "surface") add their fields.  Every solver (FFT, Abel, Hertz) and every model returns
one of them.

Internally everything is dimensionless (see ``physics.scene``); the SI views (``*_m``, ``*_Pa``,
``*_N``, and the scene's fields under their JSON keys) are generated from one table,
``SI_VIEWS``: the same attribute names where they apply (``max_pressure_Pa``, ``indentation_m``,
``pressure_Pa``, ``base_sigma_zz_Pa``, ``x_m``, ``mu``, ``young_Pa`` ... on both), the line's
``half_width_m`` and the surface's ``contact_radius_m`` where they do not.  ``summary()`` is the
JSON record (a dict) for both (``to_dict()``, the same); the command line prints its text.
Positions are measured from the indenter apex, +x the sliding direction (for mu > 0).  Stress
sign convention of the model: sigma_zz < 0 in compression.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..physics.options import option
from ..physics.scene import Scene
from .plots import MAP_CLIP_PERCENTILE, TAIL_FRACTION  # noqa: F401 (the figures' constants)

__all__ = ["Result", "ContactResult", "ContactResult3D", "JSON_KEYS", "JSON_KEYS_3D", "MAP_KEYS",
           "PROFILE_COLUMNS", "COUNTER_KEYS", "SI_VIEWS"]

COUNTER_KEYS = ("transforms", "iterations", "linear_iterations")
"""Work counters every method fills (``ContactResult.counters``): FFT pairs (forward +
backward; 0 where none are used), outer iterations (active-set, or root finding on the
half-width) and inner ones (GMRES matrix-vector products, or Nystrom solves), summed over every
level of the resolution control."""

JSON_KEYS = (
    "model", "method", "load_N_per_m", "mu", "young_Pa", "poisson", "radius_m", "thickness_m",
    "half_width_m", "contact_center_m", "x0_m", "indentation_m", "max_pressure_Pa",
    "max_pressure_x_m", "contact_intervals_m", "friction_law", "Q_over_P", "deformation_friction",
    "interface_compliance_m_per_Pa", "interface_law", "grid_points", "domain_length_m",
    "iterations", "residual", "error_estimate", "tolerance_met", "wall_time_s", "plan_time_s",
)
PROFILE_COLUMNS = ("x_m", "pressure_Pa", "surface_shear_Pa", "base_sigma_zz_Pa", "base_sigma_xz_Pa")
_SCALARS_LINE = ("half_width", "center", "indentation", "max_pressure", "max_pressure_x", "grid_points",
            "domain_length", "iterations", "residual", "error_estimate")
_ARRAYS_LINE = ("x", "pressure", "base_sigma_zz", "base_sigma_xz")


class _SI:
    """An SI view of a dimensionless attribute ``name``: its value times the scene's ``units``
    (``length_unit``, ``stress_unit``, ``displacement_unit``; several multiply in turn); a
    scalar as a float (+ 0.0 with ``form`` "nozero": no "-0.0" in the JSON record), "array" as
    it is, "pair" a list of floats (a surface's two periods)."""

    def __init__(self, name: str, units: tuple, doc: str, form: str = ""):
        self.name, self.units, self.form = name, units, form
        self.__doc__ = doc

    def __get__(self, obj, owner=None):
        if obj is None:
            return self
        v = getattr(obj, self.name)
        if self.form == "pair":
            return [float(self._si(obj, d)) for d in v]
        v = self._si(obj, v)
        if self.form == "array":
            return v
        return float(v) + 0.0 if self.form == "nozero" else float(v)

    def _si(self, obj, v):
        for u in self.units:
            v = v * getattr(obj.scene, u)
        return v


class _Scene:
    """A field of the result's scene, read through (SI already)."""

    def __init__(self, name: str, doc: str):
        self.name = name
        self.__doc__ = doc

    def __get__(self, obj, owner=None):
        return self if obj is None else getattr(obj.scene, self.name)


_L, _S, _D = ("length_unit",), ("stress_unit",), ("displacement_unit",)
_BOTH, _LINE, _SURF = ("line", "surface"), ("line",), ("surface",)
SI_VIEWS = (
    # (attribute, dimensionless source or scene field, units (None: a scene field, SI already),
    #  doc, dimensions, form)
    ("mu", "mu", None, "mu_d, the signed friction coefficient (> 0: sliding toward +x)", _BOTH, ""),
    ("poisson", "poisson", None, "nu, the film's Poisson ratio", _BOTH, ""),
    ("friction_law", "friction_law", None, "the friction law", _BOTH, ""),
    ("interface_compliance_m_per_Pa", "interface_compliance", None, "C [m/Pa]", _BOTH, ""),
    ("young_Pa", "young", None, "E, the film's Young modulus [Pa]", _BOTH, ""),
    ("radius_m", "radius", None, "R, the indenter's radius [m]", _BOTH, ""),
    ("thickness_m", "thickness", None, "h, the film's thickness [m]", _BOTH, ""),
    ("load_N_per_m", "load", None, "P_L, the lineic load [N/m]", _LINE, ""),
    ("interface_law", "interface_law", None, "the interface law", _LINE, ""),
    ("force_N", "force", None, "F, the normal force [N]", _SURF, ""),
    ("indenter", "indenter", None, "the indenter's name", _SURF, ""),
    ("length_m", "length", None, "the finite cylinder's length [m] (None otherwise)", _SURF, ""),
    ("radius_x_m", "radius_x", None, "the paraboloid's radius along x [m]", _SURF, ""),
    ("radius_y_m", "radius_y", None, "the paraboloid's radius along y [m]", _SURF, ""),
    # fields (arrays: a line's profiles; a surface's maps, indexed [x, y])
    ("x_m", "x", _L, "node positions along x [m] from the apex", _BOTH, "array"),
    ("y_m", "y", _L, "node positions along y [m] from the apex", _SURF, "array"),
    ("pressure_Pa", "pressure", _S, "p >= 0 [Pa]", _BOTH, "array"),
    ("surface_shear_Pa", "surface_shear", _S, "sigma_xz(h) [Pa]", _BOTH, "array"),
    ("base_sigma_zz_Pa", "base_sigma_zz", _S, "sigma_zz(0) [Pa], < 0 in compression", _BOTH,
     "array"),
    ("base_sigma_xz_Pa", "base_sigma_xz", _S, "sigma_xz(0) [Pa]", _BOTH, "array"),
    ("base_sigma_yz_Pa", "base_sigma_yz", _S, "sigma_yz(0) [Pa]", _SURF, "array"),
    ("surface_ux_m", "surface_ux", _D, "surface displacement u_x [m]", _SURF, "array"),
    ("surface_uy_m", "surface_uy", _D, "surface displacement u_y [m]", _SURF, "array"),
    ("surface_uz_m", "surface_uz", _D, "surface displacement u_z [m] (> 0 upward)", _SURF,
     "array"),
    # measures
    ("half_width_m", "half_width", _L,
     "a, contact half-width [m] (of the envelope when the contact splits)", _LINE, ""),
    ("contact_center_m", "center", _L, "x_c, contact centre relative to the apex [m] (> 0: "
     "toward the sliding direction)", _LINE, "nozero"),
    ("x0_m", "x0", _L, "the paper's x0 [m]: apex relative to the contact centre "
     "(= -contact_center_m)", _LINE, "nozero"),
    ("indentation_m", "indentation", _D, "d, indentation depth [m] (the paper's 1/alpha)",
     _BOTH, ""),
    ("max_pressure_Pa", "max_pressure", _S, "peak pressure [Pa]", _BOTH, ""),
    ("max_pressure_x_m", "max_pressure_x", _L, "where the pressure peaks along x [m], apex "
     "frame", _LINE, ""),
    ("max_pressure_x_m", "max_pressure_x", _L, "where the pressure peaks along x [m], apex "
     "frame", _SURF, "nozero"),
    ("max_pressure_y_m", "max_pressure_y", _L, "where the pressure peaks along y [m]", _SURF,
     "nozero"),
    ("domain_length_m", "domain_length", _L, "length covered by the profiles [m]: the FFT "
     "period, or the Abel sampling window", _LINE, ""),
    ("domain_length_m", "domain_length", _L, "the FFT periods [x, y] [m]", _SURF, "pair"),
    ("contact_area_m2", "contact_area", _L + _L, "contact area [m^2]", _SURF, ""),
    ("contact_radius_m", "contact_radius", _L, "sqrt(area / pi) [m]", _SURF, ""),
    ("contact_x_min_m", "contact_x_min", _L, "the contact's rear end along x [m]", _SURF,
     "nozero"),
    ("contact_x_max_m", "contact_x_max", _L, "the contact's front end along x [m]", _SURF,
     "nozero"),
    ("contact_y_half_width_m", "contact_y_half_width", _L, "the contact's half-width along y "
     "[m]", _SURF, ""),
    ("pressure_centroid_x_m", "pressure_centroid_x", _L, "the pressure's centroid along x [m]",
     _SURF, "nozero"),
    ("line_load_y0_N_per_m", "line_load_y0", _S + _L, "the line load on y = 0 [N/m]", _SURF, ""),
)
"""Every SI view of the results, one row each: the attribute (a JSON key), its dimensionless
source and the scene's units it is multiplied by (None: the scene's own field, SI already),
its doc, the dimensions that have it and its form ("nozero": +0.0, "array", "pair")."""


def _with_views(dimension: str):
    """Class decorator: the SI views of ``SI_VIEWS`` for ``dimension`` as attributes."""
    def install(cls):
        cls.dimension = dimension
        for name, source, units, doc, dims, form in SI_VIEWS:
            if dimension in dims:
                setattr(cls, name, _Scene(source, doc) if units is None else
                        _SI(source, units, doc, form))
        return cls
    return install


def _diagnostics(cls):
    """Append the fields every result ends with, after its dimension's own (their order is the
    constructor's): iterations, residual (relative), error_estimate (relative), wall_time_s
    (solve only), plan_time_s (FFT planning), info (free-form: method details), counters
    (``COUNTER_KEYS``), shear (the surface shear along x when it is not mu_d p: friction laws,
    issue 14; None otherwise).  Applied before ``dataclass``."""
    fields = (("iterations", "int", None), ("residual", "float", None),
              ("error_estimate", "float", None), ("wall_time_s", "float", 0.0),
              ("plan_time_s", "float", 0.0), ("info", "dict", field(default_factory=dict)),
              ("counters", "dict", field(default_factory=lambda: dict.fromkeys(COUNTER_KEYS, 0))),
              ("shear", "np.ndarray | None", None))
    annotations = cls.__dict__.get("__annotations__", {})
    for name, kind, default in fields:
        annotations[name] = kind
        if default is not None or name == "shear":
            setattr(cls, name, default)
    cls.__annotations__ = annotations
    return cls


class Result:
    """What a line's and a surface's results share (``ContactResult``, ``ContactResult3D``):
    ``dimension`` ("line" or "surface"), the SI views of ``SI_VIEWS``, the friction ratios, the
    viscoelastic film's fields, the tolerance flag, ``summary()`` = ``to_dict()`` (the JSON
    record, a dict, for both)."""

    dimension = ""

    @property
    def ndim(self) -> int:
        """1 for a line (profiles along x), 2 for a surface (maps over x, y)."""
        return 1 if self.dimension == "line" else 2

    @property
    def tolerance_met(self) -> bool:
        """Whether error_estimate is within the tolerance asked for (False only when the
        resolution was fixed by the user, ``grid_points``, and is too coarse for ``tol``)."""
        return bool(self.info.get("tolerance_met", True))

    @property
    def surface_shear(self) -> np.ndarray:
        """sigma_xz(h): mu_d p (Amontons) or the friction law's q, dimensionless."""
        if self.shear is not None:
            return self.shear
        return self.scene.mu * self.pressure

    @property
    def Q_over_P(self) -> float:  # noqa: N802 (the JSON key)
        """The macroscopic Q/P, the horizontal force on the indenter over the load, for every
        film (elastic or viscoelastic; issue 23): Q = Int q + Int p df/dx, i.e.
        ``friction_ratio`` (the interface's Int q / Int p: mu for Amontons) +
        ``deformation_friction`` (the pressure on the inclined indenter: (h/R) x_p; on an
        elastic film it is nonzero with friction only, 0.0118 at the paper's scene, mu 2)."""
        return self.friction_ratio + self.deformation_friction

    @property
    def speed_m_per_s(self) -> float:
        """V [m/s], the sliding speed of a viscoelastic film (0: elastic or relaxed)."""
        return float(getattr(self.scene, "speed", 0.0))

    @property
    def prony_terms(self) -> list:
        """[[E_i [Pa], tau_i [s]], ...] of a viscoelastic film ([] for an elastic one)."""
        return [list(t) for t in getattr(self.scene, "prony", ())]

    @property
    def auto_reason(self) -> str | None:
        """With model "auto": which model was chosen and why (else None)."""
        return self.info.get("auto_reason")

    @property
    def friction_ratio(self) -> float:
        """The macroscopic Q/P of the interface, Int q / Int p (mu_d for Amontons; 0 without
        contact)."""
        if self.shear is None:
            return float(self.scene.mu)
        P = float(np.sum(self.pressure))
        return float(np.sum(self.shear)) / P if P > 0 else 0.0

    _SCALARS: tuple = ()  # compared by ``==`` (after scene, model and method), then _ARRAYS
    _ARRAYS: tuple = ()

    def __eq__(self, other) -> bool:
        """Equal when scene, model, method, every scalar and every field are equal (timings,
        ``info`` ignored).  Never raises (arrays are compared whole)."""
        if not isinstance(other, type(self)):
            return NotImplemented
        if (self.model, self.method) != (other.model, other.method) or self.scene != other.scene:
            return False
        if any(getattr(self, n) != getattr(other, n) for n in self._SCALARS):
            return False
        return all(np.array_equal(getattr(self, n), getattr(other, n)) for n in self._ARRAYS)

    def _viscoelastic_record(self) -> dict:
        """The viscoelastic film's keys of the JSON record (issue 23; none for an elastic one)."""
        if getattr(self.scene, "viscoelastic", False):
            return {"speed_m_per_s": self.speed_m_per_s, "prony_terms": self.prony_terms}
        return {}

    def summary(self) -> dict:
        """The JSON record (same as ``to_dict()``), for lines and surfaces alike."""
        return self.to_dict()

    __hash__ = None  # mutable: not hashable


@dataclass(repr=False, eq=False)
@_with_views("line")
@_diagnostics
class ContactResult(Result):
    """Solution of one scene.

    Dimensionless fields (lengths in h, displacements in h^2/2R, stresses in G h/2R = E h/6R
    at nu = 1/2; ``physics.scene``):

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

    SI views: every key of the JSON record (``JSON_KEYS``) is an attribute of the same name
    (``r.half_width_m``, ``r.x0_m``, ``r.max_pressure_Pa``, ``r.contact_intervals_m``, ...);
    ``r.to_dict()`` is the record, ``r.profiles()`` the SI profiles named like the CSV columns
    (``pandas.DataFrame(r.profiles())``), ``r.plot()`` a matplotlib Figure.  ``repr(r)`` is a
    one-line SI summary; ``r == r2`` compares numbers and profiles (timings ignored).
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
    # then the diagnostics (``_diagnostics``): iterations, residual, error_estimate,
    # wall_time_s, plan_time_s, info, counters, shear (q(x) when it is not mu_d p)

    _SCALARS, _ARRAYS = _SCALARS_LINE, _ARRAYS_LINE

    # --- SI views -----------------------------------------------------------------------------
    @property
    def x0(self) -> float:
        """The paper's x0: apex position relative to the contact centre (= -center), in h."""
        return -self.center + 0.0

    @property
    def deformation_friction(self) -> float:
        """mu_def = Int p df/dx dx / P: the horizontal force of the pressure on the indenter's
        inclined surface over the load, f = (x - x_apex)^2 h^2/(2R) the cylinder's height, so
        mu_def = (h/R) x_p with x_p the pressure's centroid relative to the apex (in h).  Signed
        like mu: > 0 when it opposes a motion toward +x (the pressure then pushes the indenter
        toward -x); Q/P = mu + mu_def.  The solver's averaged centroid when it has one (its
        error, over the contact half-width, is in ``error_estimate``), else the final grid's."""
        m = self.info.get("pressure_centroid")
        if m is None:
            P = float(np.sum(self.pressure))
            m = float(np.dot(self.pressure, self.x)) / P if P > 0 else 0.0
        return float(m * self.scene.thickness / self.scene.radius) + 0.0

    @property
    def contact_intervals(self) -> list[tuple[float, float]]:
        """The contact as a list of (start, end) intervals in h, apex frame, sorted.

        One interval [x_c - a, x_c + a] for a simply connected contact; several when the contact
        splits (e.g. mu_d beyond ~95 at the paper's load): the outer ends are then x_c -+ a (the
        grid-averaged envelope) and the inner ends the sub-grid edges fitted on the final grid.
        Empty at zero load."""
        if not self.half_width > 0:
            return []
        lo, hi = self.center - self.half_width, self.center + self.half_width
        edges = sorted((float(e[0]), float(e[1])) for e in (self.info.get("edges") or ()))
        if len(edges) <= 1:
            return [(float(lo), float(hi))]
        out = [list(e) for e in edges]
        out[0][0], out[-1][1] = lo, hi
        return [(float(a), float(b)) for a, b in out]

    @property
    def contact_intervals_m(self) -> list[list[float]]:
        """``contact_intervals`` in metres, as [[start, end], ...] (the JSON form)."""
        L = self.scene.length_unit
        return [[a * L + 0.0, b * L + 0.0] for a, b in self.contact_intervals]

    def to_dict(self) -> dict:
        """The JSON record (all SI; ``--json`` prints it): the keys of ``JSON_KEYS``, plus
        ``auto_reason`` with model "auto".  Each key is also an attribute of the same name."""
        rec = {key: getattr(self, key) for key in JSON_KEYS}
        for key, value in rec.items():
            if isinstance(value, np.generic):
                rec[key] = value.item()
        rec |= self.scene.friction.describe()  # the law's parameters (none for Amontons)
        if self.scene.interface_law == "exponential":  # its parameters, by their JSON keys
            rec |= {option(n).json: getattr(self.scene, n)
                    for n in ("interface_pressure", "interface_length")}
        if self.auto_reason is not None:
            rec["auto_reason"] = self.auto_reason
        return rec | self._viscoelastic_record()

    # --- notebook niceties --------------------------------------------------------------------
    def __repr__(self) -> str:
        s = self.scene
        mm, kPa = 1e3, 1e-3
        n = len(self.contact_intervals)
        split = f" in {n} intervals" if n > 1 else ""
        return (f"<ContactResult {self.model}/{self.method}: P_L={s.load:g} N/m, mu_d={s.mu:g}, "
                f"E={s.young / 1e6:g} MPa, R={s.radius * mm:g} mm, h={s.thickness * mm:g} mm | "
                f"a={self.half_width_m * mm:.5g} mm{split}, x0={self.x0_m * mm:.5g} mm, "
                f"d={self.indentation_m * 1e6:.5g} um, p_max={self.max_pressure_Pa * kPa:.5g} kPa | "
                f"N={self.grid_points}, error estimate {self.error_estimate:.1e}>")

    def profiles(self) -> dict:
        """Profile columns in SI (see ``PROFILE_COLUMNS``), apex frame."""
        return {
            "x_m": self.x_m,
            "pressure_Pa": self.pressure_Pa,
            "surface_shear_Pa": self.surface_shear_Pa,
            "base_sigma_zz_Pa": self.base_sigma_zz_Pa,
            "base_sigma_xz_Pa": self.base_sigma_xz_Pa,
        }

    def plot(self, ax=None, sensor=None):
        """Draw the profiles; return the matplotlib ``Figure``.

        Panels (x in mm from the indenter apex, +x the sliding direction; stresses in kPa):
        surface pressure p (left axis) and surface shear mu_d p (right axis, its own scale);
        base stresses sigma_zz(x, 0) (< 0 in compression) and sigma_xz(x, 0); with ``sensor``
        (a ``SensorView`` from ``spectral_contact.sensor``, or a dict with ``S_zz_Pa``,
        ``S_xz_Pa`` on ``x_m``) the MEMS view S_zz (> 0 in compression), S_xz.  The contact
        interval(s) are shaded; the x range is the contact plus 2 h on each side (the surface
        panel zooms on the contact when the contact is small against that range).

        ax : None (a new Figure with every panel), one matplotlib Axes (the surface panel only)
             or a sequence of Axes (one per panel, in the order above).

        matplotlib is imported here only (the rest of the package does not need it).
        """
        from .plots import _plot

        return _plot(self, ax, sensor)


JSON_KEYS_3D = (
    "model", "method", "indenter", "force_N", "mu", "young_Pa", "poisson", "radius_m",
    "thickness_m", "friction_law", "Q_over_P", "deformation_friction",
    "interface_compliance_m_per_Pa", "contact_area_m2",
    "contact_radius_m", "contact_x_min_m", "contact_x_max_m",
    "contact_y_half_width_m", "pressure_centroid_x_m", "indentation_m", "max_pressure_Pa",
    "max_pressure_x_m", "max_pressure_y_m", "line_load_y0_N_per_m", "grid_points",
    "domain_length_m", "iterations", "residual", "error_estimate", "tolerance_met", "wall_time_s",
    "plan_time_s",
)
"""JSON keys of a 3D result (+ length_m for a cylinder, radius_x_m and radius_y_m for a
paraboloid)."""
_ARRAYS_3D = ("x", "y", "pressure", "base_sigma_zz", "base_sigma_xz", "base_sigma_yz",
              "surface_ux", "surface_uy", "surface_uz")
MAP_KEYS = ("x_m", "y_m", "pressure_Pa", "base_sigma_zz_Pa", "base_sigma_xz_Pa", "base_sigma_yz_Pa",
            "surface_ux_m", "surface_uy_m", "surface_uz_m")


@dataclass(repr=False, eq=False)
@_with_views("surface")
@_diagnostics
class ContactResult3D(Result):
    """Solution of one 3D scene (``physics.scene.Scene3D``): fields on the surface grid.

    Dimensionless (lengths in h, displacements in h^2/2R, stresses in E h/6R), arrays indexed
    [x, y] on the axes ``x`` (nx) and ``y`` (ny), apex at (0, 0), x the sliding direction:

    pressure                       p >= 0 (= -sigma_zz(x, y, h))
    base_sigma_zz, _xz, _yz        base tractions (sigma_zz < 0 in compression)
    surface_ux, _uy, _uz           surface displacements (u_z > 0 upward: the film sinks, u_z < 0)
    measures : dict                area, x_min, x_max, y_min, y_max, pmax, xmax, ymax, xc,
                                   load, line_load_y0 (``numerics.measure2d``), indentation
    error_estimate                 relative, of the contact radius, centroid (relative to the
                                   radius), indentation, line load at y = 0 and peak pressure
    counters                       transforms, iterations, linear_iterations

    As in 2D: every JSON key (``JSON_KEYS_3D``) is an attribute of the same name
    (``r.contact_radius_m``, ``r.max_pressure_Pa``, ...), ``r.to_dict()`` is the record,
    ``r.maps()`` / ``r.profiles()`` the SI arrays, ``r.plot(sensor=None)`` a Figure of the maps,
    ``repr(r)`` a one-line SI summary, ``r == r2`` compares numbers and fields.
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
    # then the diagnostics (``_diagnostics``): iterations, residual, error_estimate,
    # wall_time_s, plan_time_s, info, counters, shear (q(x, y) along x when not mu_d p)

    # --- the measures, dimensionless (``numerics.measure2d``; their SI views: ``SI_VIEWS``) ---
    @property
    def indentation(self) -> float:
        """d, in h^2/(2R)."""
        return self.measures["indentation"]

    @property
    def contact_radius(self) -> float:
        """sqrt(area / pi), in h."""
        return float(np.sqrt(self.measures["area"] / np.pi))

    _SCALARS, _ARRAYS = ("measures",), _ARRAYS_3D

    contact_area = property(lambda self: self.measures["area"], doc="contact area, in h^2")
    contact_x_min = property(lambda self: self.measures["x_min"], doc="rear end along x, in h")
    contact_x_max = property(lambda self: self.measures["x_max"], doc="front end along x, in h")
    contact_y_half_width = property(
        lambda self: 0.5 * (self.measures["y_max"] - self.measures["y_min"]),
        doc="half-width along y, in h")
    pressure_centroid_x = property(lambda self: self.measures["xc"],
                                   doc="the pressure's centroid along x, in h")
    max_pressure = property(lambda self: self.measures["pmax"], doc="peak pressure")
    max_pressure_x = property(lambda self: self.measures["xmax"], doc="where it peaks along x")
    max_pressure_y = property(lambda self: self.measures["ymax"], doc="where it peaks along y")
    line_load_y0 = property(lambda self: self.measures["line_load_y0"],
                            doc="the line load on y = 0, in E h^2/6R")

    @property
    def deformation_friction(self) -> float:
        """mu_def = Int p df/dx / P (the solver's; as the line's ``deformation_friction``)."""
        return float(self.info.get("deformation_friction", 0.0)) + 0.0

    def to_dict(self) -> dict:
        """The JSON record (all SI): the keys of ``JSON_KEYS_3D`` (each an attribute of the same
        name), the friction law's parameters at ``friction_law``, the shape's (``length_m``;
        ``radius_x_m``, ``radius_y_m``) after ``interface_compliance_m_per_Pa``."""
        s = self.scene
        shape = {"cylinder": ("length_m",), "paraboloid": ("radius_x_m", "radius_y_m")}
        rec = {}
        for key in JSON_KEYS_3D:
            if key == "friction_law":
                rec |= s.friction.describe()
            elif key == "grid_points":
                rec[key] = [int(n) for n in self.grid_points]
            elif key in ("iterations", "residual", "error_estimate", "wall_time_s", "plan_time_s"):
                rec[key] = (int if key == "iterations" else float)(getattr(self, key))
            else:
                rec[key] = getattr(self, key)
            if key == "interface_compliance_m_per_Pa":
                rec |= {k: getattr(self, k) for k in shape.get(s.indenter, ())}
        return rec | self._viscoelastic_record()

    def __repr__(self) -> str:
        s, r = self.scene, self.summary()
        mm = 1e3
        return (f"<ContactResult3D {self.model}/{self.method} {s.indenter}: F={s.force:g} N, "
                f"mu_d={s.mu:g} | contact radius {r['contact_radius_m'] * mm:.5g} mm, x "
                f"{r['contact_x_min_m'] * mm:.4g}..{r['contact_x_max_m'] * mm:.4g} mm, "
                f"d={r['indentation_m'] * 1e6:.5g} um, p_max={r['max_pressure_Pa'] / 1e3:.5g} kPa | "
                f"grid {self.grid_points[0]}x{self.grid_points[1]}, error estimate "
                f"{self.error_estimate:.1e}>")

    def plot(self, sensor: dict | None = None, window: float = 3.0):
        """Maps of the pressure and the three base tractions (with ``sensor``, from
        ``instruments.sensor.sensor_maps``, the MEMS maps as iso-lines), x the sliding direction
        in mm from the apex, stresses in kPa, the contact outlined; returns the Figure.
        ``window``: film thicknesses shown beyond the contact."""
        from .plots import _plot_maps

        return _plot_maps(self, sensor, window)

    def maps(self) -> dict:
        """The surface and base fields in SI, named as ``MAP_KEYS`` ((nx, ny) arrays [x, y])."""
        return {k: getattr(self, k) for k in MAP_KEYS}

    def profiles(self) -> dict:
        """The y = 0 line (the grid line nearest it) in SI, with the 2D profile columns."""
        j = int(np.argmin(np.abs(self.y)))
        s = self.scene
        L, S = s.length_unit, s.stress_unit
        return {
            "x_m": self.x * L,
            "pressure_Pa": self.pressure[:, j] * S,
            "surface_shear_Pa": (s.mu * self.pressure[:, j] if self.shear is None
                                 else self.shear[:, j]) * S,
            "base_sigma_zz_Pa": self.base_sigma_zz[:, j] * S,
            "base_sigma_xz_Pa": self.base_sigma_xz[:, j] * S,
        }
