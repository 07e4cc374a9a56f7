"""The result object shared by every solver (FFT, Abel, Hertz) and every model (exact, Goodman).

Internally everything is dimensionless (see ``physics.scene``); the ``*_m``, ``*_Pa`` properties
convert to SI.  Positions are measured from the indenter apex, +x the sliding direction
(for mu > 0).  Stress sign convention of the model: sigma_zz < 0 in compression.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .physics.options import option
from .physics.scene import Scene

__all__ = ["ContactResult", "ContactResult3D", "JSON_KEYS", "JSON_KEYS_3D", "MAP_KEYS",
           "PROFILE_COLUMNS", "COUNTER_KEYS"]

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
_SCALARS = ("half_width", "center", "indentation", "max_pressure", "max_pressure_x", "grid_points",
            "domain_length", "iterations", "residual", "error_estimate")
_ARRAYS = ("x", "pressure", "base_sigma_zz", "base_sigma_xz")


class _SI:
    """An SI view of a dimensionless attribute ``name``: its value times the scene's ``unit``
    (``length_unit``, ``stress_unit``, ``displacement_unit``); a scalar as a float (+ 0.0 where
    ``nozero``: no "-0.0" in the JSON record)."""

    def __init__(self, name: str, unit: str, doc: str, array: bool = False, nozero: bool = False):
        self.name, self.unit, self.array, self.nozero = name, unit, array, nozero
        self.__doc__ = doc

    def __get__(self, obj, owner=None):
        if obj is None:
            return self
        v = getattr(obj, self.name) * getattr(obj.scene, self.unit)
        if self.array:
            return v
        return float(v) + 0.0 if self.nozero else float(v)


class _Scene:
    """A field of the result's scene, read through (SI already)."""

    def __init__(self, name: str, doc: str):
        self.name = name
        self.__doc__ = doc

    def __get__(self, obj, owner=None):
        return self if obj is None else getattr(obj.scene, self.name)


@dataclass(repr=False, eq=False)
class ContactResult:
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
    iterations: int
    residual: float
    error_estimate: float
    wall_time_s: float = 0.0
    plan_time_s: float = 0.0
    info: dict = field(default_factory=dict)
    counters: dict = field(default_factory=lambda: dict.fromkeys(COUNTER_KEYS, 0))
    shear: np.ndarray | None = None  # the surface shear q(x) when it is not mu_d p (friction laws)

    @property
    def tolerance_met(self) -> bool:
        """Whether error_estimate is within the tolerance asked for (False only when the
        resolution was fixed by the user, ``grid_points``, and is too coarse for ``tol``)."""
        return bool(self.info.get("tolerance_met", True))

    # --- SI views -----------------------------------------------------------------------------
    @property
    def surface_shear(self) -> np.ndarray:
        """sigma_xz(x, h): mu_d p(x) (Amontons) or the friction law's q(x), dimensionless."""
        if self.shear is not None:
            return self.shear
        return self.scene.mu * self.pressure

    @property
    def friction_ratio(self) -> float:
        """The macroscopic Q/P = Int q dx / Int p dx (mu_d for Amontons; 0 without contact)."""
        if self.shear is None:
            return float(self.scene.mu)
        P = float(np.sum(self.pressure))
        return float(np.sum(self.shear)) / P if P > 0 else 0.0

    @property
    def x0(self) -> float:
        """The paper's x0: apex position relative to the contact centre (= -center), in h."""
        return -self.center + 0.0

    # SI views, one line each: (dimensionless attribute, the scene's unit) or a scene field
    x_m = _SI("x", "length_unit", "node positions [m] from the apex", array=True)
    pressure_Pa = _SI("pressure", "stress_unit", "p(x) >= 0 [Pa]", array=True)
    surface_shear_Pa = _SI("surface_shear", "stress_unit", "sigma_xz(x, h) [Pa]", array=True)
    base_sigma_zz_Pa = _SI("base_sigma_zz", "stress_unit", "sigma_zz(x, 0) [Pa]", array=True)
    base_sigma_xz_Pa = _SI("base_sigma_xz", "stress_unit", "sigma_xz(x, 0) [Pa]", array=True)
    half_width_m = _SI("half_width", "length_unit",
                       "a, contact half-width [m] (of the envelope when the contact splits)")
    contact_center_m = _SI("center", "length_unit", "x_c, contact centre relative to the apex "
                           "[m] (> 0: toward the sliding direction)", nozero=True)
    indentation_m = _SI("indentation", "displacement_unit",
                        "d, indentation depth [m] (the paper's 1/alpha)")
    x0_m = _SI("x0", "length_unit", "the paper's x0 [m]: apex relative to the contact centre "
               "(= -contact_center_m)", nozero=True)
    max_pressure_Pa = _SI("max_pressure", "stress_unit", "peak pressure [Pa]")
    max_pressure_x_m = _SI("max_pressure_x", "length_unit", "where the pressure peaks [m], apex "
                           "frame")
    domain_length_m = _SI("domain_length", "length_unit", "length covered by the profiles [m]: "
                          "the FFT period, or the Abel sampling window")
    load_N_per_m = _Scene("load", "P_L, the lineic load [N/m]")
    mu = _Scene("mu", "mu_d, the signed friction coefficient (> 0: sliding toward +x)")
    poisson = _Scene("poisson", "nu, the film's Poisson ratio")
    friction_law = _Scene("friction_law", "the friction law")
    interface_compliance_m_per_Pa = _Scene("interface_compliance", "C [m/Pa]")
    interface_law = _Scene("interface_law", "the interface law")
    young_Pa = _Scene("young", "E, the film's Young modulus [Pa]")
    radius_m = _Scene("radius", "R, the cylinder's radius [m]")
    thickness_m = _Scene("thickness", "h, the film's thickness [m]")

    @property
    def Q_over_P(self) -> float:  # noqa: N802 (the JSON key)
        """The macroscopic Q/P, the horizontal force on the indenter over the load, for every
        film (elastic or viscoelastic; issue 23): Q = Int q dx + Int p df/dx dx, i.e.
        ``friction_ratio`` (the interface's Int q / Int p: mu for Amontons) +
        ``deformation_friction`` (the pressure on the inclined indenter: (h/R) x_p; on an
        elastic film it is nonzero with friction only, 0.0118 at the paper's scene, mu 2)."""
        return self.friction_ratio + self.deformation_friction

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
    def speed_m_per_s(self) -> float:
        return float(getattr(self.scene, "speed", 0.0))

    @property
    def prony_terms(self) -> list:
        """[[E_i [Pa], tau_i [s]], ...] of a viscoelastic film ([] for an elastic one)."""
        return [list(t) for t in getattr(self.scene, "prony", ())]

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

    @property
    def auto_reason(self) -> str | None:
        """With model "auto": which model was chosen and why (else None)."""
        return self.info.get("auto_reason")

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
        if getattr(self.scene, "viscoelastic", False):  # issue 23
            rec |= {"speed_m_per_s": self.speed_m_per_s, "prony_terms": self.prony_terms}
        return rec

    def summary(self) -> dict:
        """The JSON record (same as ``to_dict()``)."""
        return self.to_dict()

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

    def __eq__(self, other) -> bool:
        """Equal when scene, model, method, every scalar and every profile are equal (timings,
        ``info`` ignored).  Never raises (arrays are compared whole)."""
        if not isinstance(other, ContactResult):
            return NotImplemented
        if (self.scene, self.model, self.method) != (other.scene, other.model, other.method):
            return False
        for name in _SCALARS:
            if getattr(self, name) != getattr(other, name):
                return False
        return all(np.array_equal(getattr(self, n), getattr(other, n)) for n in _ARRAYS)

    __hash__ = None  # mutable: not hashable

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
        return _plot(self, ax, sensor)


TAIL_FRACTION = 0.01
"""The plots' x range holds the base stresses down to this fraction of their peak (issue 24:
contact +- 2 h cut S_xz at 14 kPa, a quarter of its peak)."""


def _xrange_mm(result, margin_h: float = 2.0):
    """Plot range [mm]: the contact plus ``margin_h`` film thicknesses on each side, widened
    to where both base stresses have fallen below TAIL_FRACTION of their peak."""
    L, mm = result.scene.length_unit, 1e3
    x = result.x_m * mm
    iv = result.contact_intervals
    lo, hi = (iv[0][0], iv[-1][1]) if iv else (0.0, 0.0)
    lo, hi = (lo - margin_h) * L * mm, (hi + margin_h) * L * mm
    base = np.maximum(np.abs(np.asarray(result.base_sigma_zz_Pa)),
                      np.abs(np.asarray(result.base_sigma_xz_Pa)))
    if base.size == x.size and base.size and np.max(base) > 0:
        big = x[base >= TAIL_FRACTION * np.max(base)]
        lo, hi = min(lo, float(big.min())), max(hi, float(big.max()))
    return max(lo, x.min()), min(hi, x.max())


def _plot(result, ax=None, sensor=None):
    from matplotlib.figure import Figure

    s = result.scene
    mm, kPa = 1e3, 1e-3
    if sensor is not None and not isinstance(sensor, dict):
        sensor = sensor.profiles()
    nrow = 3 if sensor is not None else 2
    if ax is None:
        fig = Figure(figsize=(7.0, 2.5 * nrow + 0.5), layout="constrained")
        axes = list(fig.subplots(nrow, 1))
    elif hasattr(ax, "plot"):
        axes, fig = [ax], ax.figure
    else:
        axes = list(ax)
        fig = axes[0].figure
    x = result.x_m * mm
    xs = None
    if sensor is not None:
        xs = np.asarray(sensor.get("x_m", result.x_m), dtype=float) * mm
    lo, hi = _xrange_mm(result)
    sel = (x >= lo) & (x <= hi)
    intervals = [(a * s.length_unit * mm, b * s.length_unit * mm) for a, b in result.contact_intervals]

    def mark_contact(a, label=False):
        for i, (u, v) in enumerate(intervals):
            a.axvspan(u, v, color="0.9", zorder=0,
                      label="contact" if (label and i == 0) else None)
        a.axhline(0.0, color="0.6", lw=0.5, zorder=1)

    a0 = axes[0]
    mark_contact(a0, label=True)
    a0.plot(x[sel], result.pressure_Pa[sel] * kPa, color="C0", label="pressure p = -sigma_zz(x, h)")
    a0.set_ylabel("pressure p [kPa]", color="C0")
    if np.any(result.surface_shear_Pa[sel] != 0.0):
        # one axis, both in kPa (issue 24: a right axis scaled by mu_d drew the Amontons shear
        # on top of the pressure, adding nothing)
        a0.plot(x[sel], result.surface_shear_Pa[sel] * kPa, "--", color="C3",
                label=("surface shear sigma_xz(x, h)" if result.shear is not None
                       else f"surface shear sigma_xz(x, h) = {s.mu:g} p"))
        a0.set_ylabel("surface stress [kPa]", color="black")
    handles, labels = a0.get_legend_handles_labels()
    leg_ax = a0
    leg_ax.legend(handles, labels, fontsize=7, loc="lower left", bbox_to_anchor=(0.0, 1.0),
                  ncols=2, frameon=False, borderaxespad=0.2)
    split = f"; contact in {len(intervals)} intervals" if len(intervals) > 1 else ""
    if ax is None:  # a figure of our own: the scene as its title
        fig.suptitle(f"{result.model} model ({result.method}): P_L = {s.load:g} N/m, mu_d = {s.mu:g}, "
                     f"E = {s.young / 1e6:g} MPa, R = {s.radius * mm:g} mm, h = {s.thickness * mm:g} mm"
                     f"{split}" + ("" if s.friction_law == "amontons" else
                                   f"; {s.friction_law} friction law"), fontsize=10)
    if len(axes) > 1:
        a1 = axes[1]
        mark_contact(a1)
        a1.plot(x[sel], result.base_sigma_zz_Pa[sel] * kPa, color="C0", label="sigma_zz(x, 0)")
        a1.plot(x[sel], result.base_sigma_xz_Pa[sel] * kPa, color="C3", label="sigma_xz(x, 0)")
        a1.set_ylabel("base stress [kPa]")
        a1.legend(fontsize=7, loc="best", title="sigma_zz < 0 in compression", title_fontsize=7)
    if sensor is not None and len(axes) > 2:
        a2 = axes[2]
        mark_contact(a2)
        ss = (xs >= lo) & (xs <= hi)
        a2.plot(xs[ss], np.asarray(sensor["S_zz_Pa"])[ss] * kPa, color="C0", label="S_zz (> 0 compression)")
        a2.plot(xs[ss], np.asarray(sensor["S_xz_Pa"])[ss] * kPa, color="C3", label="S_xz")
        a2.set_ylabel("MEMS view S [kPa]")
        a2.legend(fontsize=7, loc="best")
    xlabel = "x [mm] from the indenter apex (sliding toward +x)"
    for a in axes:
        a.set_xlim(lo, hi)
    if intervals and len(axes) > 1:
        u, v = intervals[0][0], intervals[-1][1]
        if v - u < 0.25 * (hi - lo):  # a small contact: its own zoom on the surface panel
            pad = 0.25 * (v - u)
            a0.set_xlim(u - pad, v + pad)
            a0.set_xlabel(xlabel + ", zoomed on the contact", fontsize=8)
    for a in axes[1:-1]:  # the base and sensor panels share the range: one label at the bottom
        a.sharex(axes[-1])
        a.tick_params(labelbottom=False)
    axes[-1].set_xlabel(xlabel)
    return fig

JSON_KEYS_3D = (
    "model", "method", "indenter", "force_N", "mu", "young_Pa", "poisson", "radius_m",
    "thickness_m", "friction_law", "Q_over_P", "deformation_friction",
    "interface_compliance_m_per_Pa", "contact_area_m2",
    "contact_radius_m", "contact_x_min_m", "contact_x_max_m",
    "contact_y_half_width_m", "pressure_centroid_x_m", "indentation_m", "max_pressure_Pa",
    "max_pressure_x_m", "max_pressure_y_m", "line_load_y0_N_per_m", "grid_points",
    "domain_length_m", "iterations", "residual", "error_estimate", "wall_time_s", "plan_time_s",
)
"""JSON keys of a 3D result (+ length_m for a cylinder, radius_x_m and radius_y_m for a
paraboloid)."""
_ARRAYS_3D = ("x", "y", "pressure", "base_sigma_zz", "base_sigma_xz", "base_sigma_yz",
              "surface_ux", "surface_uy", "surface_uz")
MAP_KEYS = ("x_m", "y_m", "pressure_Pa", "base_sigma_zz_Pa", "base_sigma_xz_Pa", "base_sigma_yz_Pa",
            "surface_ux_m", "surface_uy_m", "surface_uz_m")


@dataclass(repr=False, eq=False)
class ContactResult3D:
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
    iterations: int
    residual: float
    error_estimate: float
    wall_time_s: float = 0.0
    plan_time_s: float = 0.0
    info: dict = field(default_factory=dict)
    counters: dict = field(default_factory=lambda: dict.fromkeys(COUNTER_KEYS, 0))
    shear: np.ndarray | None = None  # surface shear q(x, y) along x when not mu_d p (issue 14)

    @property
    def indentation(self) -> float:
        return self.measures["indentation"]

    @property
    def contact_radius(self) -> float:
        """sqrt(area / pi), in h."""
        return float(np.sqrt(self.measures["area"] / np.pi))

    def __getattr__(self, name):
        # the JSON record's keys as attributes (only names not found otherwise come here)
        if name.endswith(("_m", "_m2", "_Pa", "_N", "_N_per_m")) or name in ("indenter",):
            rec = self.summary()
            if name in rec:
                return rec[name]
        raise AttributeError(f"{type(self).__name__!r} has no attribute {name!r}")

    def to_dict(self) -> dict:
        """The JSON record (same as ``summary()``)."""
        return self.summary()

    def __repr__(self) -> str:
        s, r = self.scene, self.summary()
        mm = 1e3
        return (f"<ContactResult3D {self.model}/{self.method} {s.indenter}: F={s.force:g} N, "
                f"mu_d={s.mu:g} | contact radius {r['contact_radius_m'] * mm:.5g} mm, x "
                f"{r['contact_x_min_m'] * mm:.4g}..{r['contact_x_max_m'] * mm:.4g} mm, "
                f"d={r['indentation_m'] * 1e6:.5g} um, p_max={r['max_pressure_Pa'] / 1e3:.5g} kPa | "
                f"grid {self.grid_points[0]}x{self.grid_points[1]}, error estimate "
                f"{self.error_estimate:.1e}>")

    def __eq__(self, other) -> bool:
        """Equal when scene, model, method, measures and every field are equal (timings and
        ``info`` ignored)."""
        if not isinstance(other, ContactResult3D):
            return NotImplemented
        if (self.model, self.method, self.measures) != (other.model, other.method, other.measures):
            return False
        if self.scene != other.scene:
            return False
        return all(np.array_equal(getattr(self, n), getattr(other, n)) for n in _ARRAYS_3D)

    __hash__ = None

    def plot(self, sensor: dict | None = None, window: float = 3.0):
        """Maps of the pressure and the three base tractions (with ``sensor``, from
        ``instruments.sensor.sensor_maps``, the MEMS maps as iso-lines), x the sliding direction
        in mm from the apex, stresses in kPa, the contact outlined; returns the Figure.
        ``window``: film thicknesses shown beyond the contact."""
        return _plot_maps(self, sensor, window)

    def summary(self) -> dict:
        """The JSON record (all SI); see ``JSON_KEYS_3D``."""
        s, L = self.scene, self.scene.length_unit
        m, S = self.measures, self.scene.stress_unit
        out = {
            "model": self.model, "method": self.method, "indenter": s.indenter,
            "force_N": s.force, "mu": s.mu, "young_Pa": s.young, "poisson": s.poisson,
            "radius_m": s.radius, "thickness_m": s.thickness,
        } | s.friction.describe() | {
            # Q/P = Int q / P + mu_def, mu_def = Int p df/dx / P (as the line's record)
            "Q_over_P": (float(s.mu) if self.shear is None else
                         float(np.sum(self.shear)) / max(float(np.sum(self.pressure)), 1e-300))
            + float(self.info.get("deformation_friction", 0.0)),
            "deformation_friction": float(self.info.get("deformation_friction", 0.0)) + 0.0,
            "interface_compliance_m_per_Pa": s.interface_compliance,
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
        if getattr(s, "viscoelastic", False):  # issue 23: as the line's record
            out |= {"speed_m_per_s": float(s.speed), "prony_terms": [list(t) for t in s.prony]}
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
            "surface_shear_Pa": (s.mu * self.pressure[:, j] if self.shear is None
                                 else self.shear[:, j]) * S,
            "base_sigma_zz_Pa": self.base_sigma_zz[:, j] * S,
            "base_sigma_xz_Pa": self.base_sigma_xz[:, j] * S,
        }


def _plot_maps(result, sensor, window):
    """3D result: maps of the pressure and of the three base tractions (and the MEMS maps
    S_zz, S_xz, S_yz with ``sensor``, drawn like the paper's measured field: iso-lines), x the
    sliding direction, in mm from the apex, stresses in kPa, the contact outline in black.
    ``window``: film thicknesses shown beyond the contact."""
    import numpy as np
    from matplotlib.figure import Figure

    s = result.scene
    maps = result.maps()
    mm = 1e3
    x, y = maps["x_m"] * mm, maps["y_m"] * mm
    q, L = result.measures, s.length_unit * mm
    sx = (x >= (q["x_min"] - window) * L) & (x <= (q["x_max"] + window) * L)
    sy = (y >= (q["y_min"] - window) * L) & (y <= (q["y_max"] + window) * L)
    panels = [("pressure_Pa", "pressure p = -sigma_zz(h)"),
              ("base_sigma_zz_Pa", "base sigma_zz(x, y, 0)"),
              ("base_sigma_xz_Pa", "base sigma_xz(x, y, 0)"),
              ("base_sigma_yz_Pa", "base sigma_yz(x, y, 0)")]
    fields = {k: maps[k] for k, _ in panels}
    if sensor:
        panels += [("S_zz_Pa", "MEMS S_zz [kPa] (+ compression)"), ("S_xz_Pa", "MEMS S_xz [kPa]"),
                   ("S_yz_Pa", "MEMS S_yz [kPa]")]
        fields.update({k: sensor[k] for k in ("S_zz_Pa", "S_xz_Pa", "S_yz_Pa")})
    ncol = 3 if not sensor else 4
    nrow = int(np.ceil((len(panels) + 1) / ncol))  # + the y = 0 line
    fig = Figure(figsize=(3.8 * ncol, 3.5 * nrow))
    axes = fig.subplots(nrow, ncol, squeeze=False)
    X, Y = np.meshgrid(x[sx], y[sy], indexing="ij")
    contact = result.pressure[np.ix_(sx, sy)] > 0
    clipped = []
    for ax, (key, title) in zip(axes.ravel(), panels):
        f = fields[key][np.ix_(sx, sy)] / 1e3
        top = max(np.max(np.abs(f)), 1e-30)
        # the colour scale stops at a percentile of |value| (issue 24: the finite cylinder's
        # singular ends took the whole scale); the clipped maximum is said in the title
        lim = max(float(np.percentile(np.abs(f), MAP_CLIP_PERCENTILE)), 1e-30)
        lim = top if top <= 1.05 * lim else lim
        if lim < top:
            clipped.append(f"{title.split(' [')[0]} max {top:.3g} kPa")
        signed = key != "pressure_Pa"
        cmap = "RdBu_r" if signed else "viridis"
        if key.startswith("S_"):  # the paper's measured field: iso-lines, with a colour bar
            cs = ax.contour(X, Y, np.clip(f, -lim, lim), levels=8, cmap=cmap,
                            vmin=-lim if signed else None, vmax=lim if signed else None)
            ax.clabel(cs, fontsize=8, fmt="%.2g")
            fig.colorbar(cs, ax=ax, label="kPa", shrink=0.85)
        else:
            im = ax.pcolormesh(X, Y, f, shading="auto", cmap=cmap,
                               vmin=-lim if signed else 0.0, vmax=lim)
            fig.colorbar(im, ax=ax, label="kPa", shrink=0.85,
                         extend=("both" if signed else "max") if lim < top else "neither")
        ax.contour(X, Y, contact.astype(float), levels=[0.5], colors="k", linewidths=0.8)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("x [mm] (sliding toward +x)")
        ax.set_ylabel("y [mm]")
        ax.set_aspect("equal")
    # the line the sensor measures: y = 0 (issue 24)
    ax = axes.ravel()[len(panels)]
    j = int(np.argmin(np.abs(y)))
    for key, label, style in (("pressure_Pa", "pressure p", "k-"),
                              ("base_sigma_zz_Pa", "base sigma_zz", "C0-"),
                              ("base_sigma_xz_Pa", "base sigma_xz", "C3-"),
                              ("S_zz_Pa", "MEMS S_zz", "C0--"), ("S_xz_Pa", "MEMS S_xz", "C3--")):
        if key in fields:
            ax.plot(x[sx], fields[key][sx, j] / 1e3, style, lw=1.2, label=label)
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.set_title(f"the line y = {y[j]:.3g} mm", fontsize=10)
    ax.set_xlabel("x [mm] (sliding toward +x)")
    ax.set_ylabel("stress [kPa]")
    ax.legend(fontsize=7)
    for ax in axes.ravel()[len(panels) + 1:]:
        ax.set_visible(False)
    note = (f"; colour scales clipped at the {MAP_CLIP_PERCENTILE:g}th percentile of |value| "
            f"({', '.join(clipped)})" if clipped else "")
    fig.suptitle(f"{result.model} model, {s.indenter}: F = {s.force:g} N, mu_d = {s.mu:g}, "
                 f"E = {s.young / 1e6:g} MPa, R = {s.radius * 1e3:g} mm, "
                 f"h = {s.thickness * 1e3:g} mm (black: contact outline){note}", fontsize=10,
                 wrap=True)
    fig.tight_layout()
    return fig


MAP_CLIP_PERCENTILE = 99.5
"""The maps' colour scales end at this percentile of |value| in the window when the maximum is
more than 5 % above it (singular edges: the finite cylinder's ends); the title says so."""
