"""Every option of a scene and of a solve, declared once: its Python name, command-line flag,
unit, accepted range, default, help and the scenes that take it.

The rest is generated from ``OPTIONS``: the validation of ``Scene`` (lines) and ``Scene3D``
(surfaces), the same bounds for both (``validate``); the command line's scene options
(``cli.main``, ``cli.mems``: ``Option.flag``, ``Option.cli_help``); the sweep's options
(``sweep.OPTIONS``: the rows with ``sweep=True``); the messages, which name the option as the
caller typed it (``errors.named``: ``poisson`` from Python, ``--poisson`` from the command line).

A new option: one row here (and the field of ``Scene`` / ``Scene3D`` whose default is read from
it); ``tests/test_options.py`` checks that the command line, the sweep and the Python API agree.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

from ..errors import InputError, named

__all__ = ["Option", "OPTIONS", "option", "default", "validate", "check_applies", "check_needs",
           "check_prony",
           "INDENTERS_3D", "INDENTERS", "FRICTION_LAWS", "INTERFACE_LAWS", "MODELS", "MU_MAX",
           "TOL_MIN", "scene_options"]

INDENTERS_3D = ("sphere", "cylinder", "paraboloid", "function")
"""The surface (3D) indenters by name ("function": any height function, Python only)."""
INDENTERS = ("line",) + INDENTERS_3D[:-1]
"""The indenters the command line and the sweep name."""
FRICTION_LAWS = ("amontons", "power", "linear")
INTERFACE_LAWS = ("linear", "exponential")
MODELS = ("exact", "goodman", "hertz", "auto")
MU_MAX = 1e3
"""Largest |mu_d| accepted, lines and surfaces: the FFT solver is verified to |mu| = 100 (and
fails to converge, exit 3, from ~1e3 on the paper's scene); beyond 1e3 round-off breaks the
linear algebra."""
TOL_MIN = 1e-14
"""Smallest relative tolerance: differences of a few round-offs (2.2e-16) cannot be resolved."""

_KINDS = ("line", "surface", "both", "solve")


@dataclass(frozen=True)
class Option:
    """One option.

    name : the Python name (``Scene`` field, ``solve`` keyword, sweep option, TOML key).
    what : its symbol and a few words ("P_L, the load per unit length"), said in messages.
    unit : SI unit ("" if none).  kind : float, int or str.
    default : the Python default (None: optional, or chosen per scene: ``default_text`` says).
    lo, hi, lo_open, hi_open : the accepted range (None: unbounded); choices : for str.
    scenes : "line", "surface", "both" (a scene field) or "solve" (an option of the solve).
    indenters : the surface indenters that take it (None: all the scene's).
    sweep : an option of ``sweep`` (its column and store key).
    json : the JSON key of the results (None: none, or said by the result).
    cli : on the command line: True (``solve`` and the subcommands that take a scene), "solve"
        (``solve`` only), False; help : more words for --help.
    needs : an option that must be given with this one on the command line and in a sweep
        (``check_needs``; Python keeps the field's default).
    practice : (lo, hi), the range of soft-contact practice: a value outside is accepted with
        a warning, most often being a units slip (``physics.scene.SOFT_CONTACT_RANGES``).
    """

    name: str
    what: str
    unit: str = ""
    kind: type = float
    default: object = None
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple | None = None
    scenes: str = "both"
    indenters: tuple | None = None
    default_text: str | None = None
    sweep: bool = False
    json: str | None = None
    cli: bool | str = True
    help: str = ""
    practice: tuple | None = None
    needs: str | None = None

    def __post_init__(self):
        assert self.scenes in _KINDS, self.scenes

    @property
    def symbol(self) -> str | None:
        """The symbol that opens ``what`` ("P_L" of "P_L, the load per unit length"), if any:
        the metavar of --help."""
        head, sep, _ = self.what.partition(", ")
        return head if sep and " " not in head else None

    @property
    def flag(self) -> str:
        """The command-line flag: --friction-exponent for friction_exponent."""
        return "--" + self.name.replace("_", "-")

    def accepted(self, unit: bool = True) -> str:
        """The accepted values in words: "> 0 Pa", "in [0, 0.5]", "one of a, b"."""
        if self.choices is not None:
            return "one of " + ", ".join(self.choices)
        u = f" {self.unit}" if self.unit and unit else ""
        lo, hi = self.lo, self.hi
        if self.kind is tuple:
            return "pairs E1,tau1[,E2,tau2,...] (E_i [Pa] > 0, tau_i [s] > 0)"
        if lo is None and hi is None and self.kind is int:
            return "an integer"
        if lo is None and hi is None:
            return f"a finite number{f' [{self.unit}]' if self.unit and unit else ''}"
        if hi is None:
            return f"{'>' if self.lo_open else '>='} {lo:g}{u}"
        if lo is None:
            return f"{'<' if self.hi_open else '<='} {hi:g}{u}"
        return f"in {'(' if self.lo_open else '['}{lo:g}, {hi:g}{')' if self.hi_open else ']'}{u}"

    def default_said(self) -> str:
        if self.default_text is not None:
            return self.default_text
        if self.kind is tuple:
            return "none" if not self.default else str(self.default)
        if isinstance(self.default, str):
            return self.default
        return "none" if self.default is None else f"{self.default:g}"

    def cli_help(self) -> str:
        """--help's text: what, unit, range, default, more."""
        u = f" [{self.unit}]" if self.unit else ""
        rng = "" if self.choices is not None else f", {self.accepted(unit=False)}"
        more = f"; {self.help}" if self.help else ""
        return f"{self.what}{u}{rng} (default {self.default_said()}){more}"

    @property
    def cli_type(self):
        """The argparse type: the text itself for a structured value (``kind`` tuple: parsed
        by ``check``, as from Python)."""
        return str if self.kind is tuple else self.kind

    def check(self, value):
        """``value`` validated (floats: a real number, finite, in range, -0 made 0; str: one of
        the choices; tuple: the Prony terms, ``check_prony``); InputError naming the option
        (``errors.named``) and the accepted values."""
        if self.kind is tuple:
            return check_prony(value, named(self.name))
        if self.kind is str:
            if not isinstance(value, str) or value not in self.choices:
                raise self._refused(f"must be {self.accepted()}; got {_short(value)}")
            return value
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise self._refused(f"must be a number ({self.accepted()}); got {_short(value)}")
        try:
            v = float(value)
        except (TypeError, ValueError, OverflowError):
            raise self._refused(f"must be a finite number ({self.accepted()}); got "
                                f"{_short(value)}") from None
        if not math.isfinite(v):
            raise self._refused(f"must be finite ({self.accepted()}); got {v}")
        lo, hi = self.lo, self.hi
        if ((lo is not None and (v < lo or (self.lo_open and v == lo)))
                or (hi is not None and (v > hi or (self.hi_open and v == hi)))):
            raise self._refused(f"must be {self.accepted()}; got {v:g}")
        return v + 0.0  # no -0

    def _refused(self, what: str) -> InputError:
        """The one-line InputError of ``check``: the option as the user named it (``named``,
        looked up only when refusing: ``check`` runs ~20 times per ``solve()``), what it is,
        ``what`` is wrong."""
        return InputError(f"{named(self.name)} ({self.what}) {what}")


def check_prony(prony, option: str = "--prony") -> tuple:
    """Prony terms as a tuple of (E_i [Pa], tau_i [s]) pairs, each finite and > 0: the one parser
    of the option ``prony`` (a string 'E1,tau1[,E2,tau2,...]' or pairs; () or None: none).
    InputError (one line naming ``option``) otherwise."""
    if prony is None:
        return ()
    if isinstance(prony, str):
        parts = [t.strip() for t in prony.split(",")]
        try:
            values = [float(t) for t in parts]
        except ValueError:
            raise InputError(f"{option} must be numbers E1,tau1[,E2,tau2,...] (E_i [Pa] > 0, "
                             f"tau_i [s] > 0); got {prony!r:.60}") from None
        if len(values) % 2 or not values:
            raise InputError(f"{option} needs pairs E1,tau1[,E2,tau2,...] (an even count of "
                             f"numbers); got {len(values)} in {prony!r:.60}")
        prony = list(zip(values[::2], values[1::2]))
    try:
        terms = tuple((float(e), float(t)) for e, t in prony)
    except (TypeError, ValueError):
        raise InputError(f"{option} must be pairs E1,tau1[,E2,tau2,...] (E_i [Pa] > 0, tau_i "
                         f"[s] > 0); got {prony!r:.60}") from None
    for e, t in terms:
        if not (math.isfinite(e) and e > 0.0 and math.isfinite(t) and t > 0.0):
            raise InputError(f"{option} terms need E_i > 0 Pa and tau_i > 0 s, finite; got "
                             f"E = {e:g}, tau = {t:g}")
    return terms


def _short(value, n: int = 40) -> str:
    r = repr(value)
    return r if len(r) <= n else r[:n] + "..."


_POS = {"lo": 0.0, "lo_open": True}
_NONNEG = {"lo": 0.0}

OPTIONS: tuple[Option, ...] = (
    # --- the indenter and its load (the sweep's column order) ---
    Option("indenter", "the indenter", kind=str, default="line", choices=INDENTERS, sweep=True,
           json="indenter",
           help="line: the plane-strain cylinder of the paper (--load, N/m); sphere, cylinder "
                "(finite length along y, sharp ends), paraboloid (--radius-x, --radius-y): 3D, "
                "pressed with --force [N]"),
    Option("load", "P_L, the load per unit length", "N/m", default=200.0, **_NONNEG,
           scenes="line", sweep=True, json="load_N_per_m", help="line indenter only"),
    Option("force", "F, the normal force", "N", default=1.0, **_NONNEG, scenes="surface",
           sweep=True, json="force_N", help="3D indenters only"),
    Option("mu", "mu_d, the friction coefficient", default=2.0, lo=-MU_MAX, hi=MU_MAX,
           sweep=True, json="mu", help="signed: < 0 slides toward -x"),
    # --- the film ---
    Option("young", "E, the film's Young modulus", "Pa", default=2.2e6, **_POS, sweep=True,
           json="young_Pa", practice=(1e3, 1e9)),
    Option("radius", "R, the indenter's radius", "m", default=0.130, **_POS, sweep=True,
           json="radius_m", practice=(1e-6, 10.0)),
    Option("thickness", "h, the film thickness", "m", default=0.002, **_POS, sweep=True,
           json="thickness_m", practice=(1e-6, 0.1)),
    # --- the surface indenters' shapes ---
    Option("length", "the finite cylinder's length along y", "m", default=0.008, **_POS,
           scenes="surface", indenters=("cylinder",), sweep=True, json="length_m",
           default_text="0.008: the paper's cover slide", practice=(1e-5, 1.0)),
    Option("radius_x", "the paraboloid's radius along x, the sliding direction", "m", **_POS,
           scenes="surface", indenters=("paraboloid",), sweep=True, json="radius_x_m",
           default_text="--radius"),
    Option("radius_y", "the paraboloid's radius along y", "m", **_POS, scenes="surface",
           indenters=("paraboloid",), sweep=True, json="radius_y_m", default_text="--radius"),
    Option("extent", "a bound of a height function's contact half-extent", "m", **_POS,
           cli=False, default_text="2 h"),
    # --- beyond the paper's assumptions (issue 14) ---
    Option("poisson", "nu, the film's Poisson ratio", default=0.5, lo=0.0, hi=0.5,
           json="poisson", help="0.5: incompressible; < 0.5 needs --method fft"),
    Option("friction_law", "the friction law", kind=str, default="amontons",
           choices=FRICTION_LAWS, json="friction_law",
           help="amontons: q = mu p; power: q = mu (p/p_ref)^-n p; linear: q = tau_0 + alpha p "
                "in the contact (--method fft)"),
    Option("friction_exponent", "n, the power law's exponent", lo=0.0, hi=1.0, hi_open=True,
           default_text="0", json="friction_exponent", help="friction law power only"),
    Option("friction_pref", "p_ref, the power law's reference pressure", "Pa", **_POS,
           default_text="none: required by the power law", json="friction_pref_Pa",
           help="friction law power only"),
    Option("shear_strength", "tau_0, the linear law's shear strength", "Pa",
           default_text="0", json="shear_strength_Pa",
           help="friction law linear only; same sign as --shear-slope"),
    Option("shear_slope", "alpha, the linear law's slope", default_text="0",
           json="shear_slope", help="friction law linear only"),
    Option("interface_compliance", "C, the interface compliance", "m/Pa", default=0.0,
           **_NONNEG, json="interface_compliance_m_per_Pa",
           help="the interface closes by C p (0: rigid; --method fft)"),
    Option("interface_law", "the interface law", kind=str, default="linear",
           choices=INTERFACE_LAWS, scenes="line", json="interface_law",
           help="linear: --interface-compliance; exponential: p = p0 exp(-g/lambda) at an "
                "interface gap g (soft edges; --method fft, Amontons friction)"),
    Option("interface_pressure", "p0, the exponential interface law's pressure", "Pa", **_POS,
           scenes="line", default_text="none: required by the exponential law",
           json="interface_pressure_Pa"),
    Option("interface_length", "lambda, the exponential interface law's length", "m", **_POS,
           scenes="line", default_text="none: required by the exponential law",
           json="interface_length_m"),
    # --- a viscoelastic film (issue 23) ---
    Option("speed", "V, the sliding speed of a viscoelastic film", "m/s", default=0.0,
           sweep=True, json="speed_m_per_s", cli="solve",
           help="signed like --mu; != 0 needs --prony (0: the relaxed film, with or without "
                "it)"),
    Option("prony", "the Prony terms of a viscoelastic film", kind=tuple, default=(),
           sweep=True, json="prony_terms", cli="solve", needs="speed",
           help="moduli E_i and relaxation times tau_i; --young is the relaxed modulus E_inf; "
                "needs --speed (Python: speed 0 by default); an incompressible film, Amontons "
                "friction, a rigid interface; a sweep takes several series separated by ';'"),
    # --- the solve ---
    Option("model", "the model", kind=str, default="exact", choices=MODELS, scenes="solve",
           sweep=True, json="model",
           help="exact: the paper's model, friction coupled into the contact; goodman: "
                "frictionless pressure and window, friction loads the base only; hertz: "
                "half-space Hertz pressure put on the film (closed form; 3D: sphere only); auto "
                "(line only): the cheapest of the three whose error bound is below --tol"),
    Option("method", "the method", kind=str, default="fft", choices=("fft", "abel"),
           scenes="solve", sweep=True, json="method",
           help="fft: spectral solver on a periodic grid; abel: the paper's Abel/Fredholm "
                "formulation, an independent check (line indenter only)"),
    Option("tol", "the relative accuracy target", lo=TOL_MIN, hi=0.1, hi_open=True,
           scenes="solve", sweep=True, json=None,
           default_text="1e-4 for a line; 1e-3 in 3D, 1e-2 for the finite cylinder"),
    Option("grid_points", "the number of grid points", kind=int, scenes="solve", sweep=True,
           json="grid_points", default_text="chosen from --tol",
           help="fix N (fft: 64 ... 2^22, even; 3D: per axis, 32 ... 8192; abel: 6 ... 2000 "
                "nodes) instead of choosing it from --tol"),
    Option("domain_length", "the FFT period", "m", **_POS, scenes="solve", sweep=True,
           json="domain_length_m", default_text="chosen from --tol",
           help="fix the FFT period L instead of choosing it from --tol (3D: both axes)"),
)

_BY_NAME = {o.name: o for o in OPTIONS}


def option(name: str) -> Option:
    """The option called ``name``."""
    return _BY_NAME[name]


def default(name: str):
    """The Python default of option ``name`` (the dataclasses' field defaults read it)."""
    return _BY_NAME[name].default


def scene_options(scene: str) -> tuple[Option, ...]:
    """The options a scene takes: ``scene`` "line" or "surface"."""
    return tuple(o for o in OPTIONS if o.scenes in (scene, "both"))


def validate(obj, scene: str) -> dict:
    """The scene fields of ``obj`` (``Scene``: ``scene`` "line"; ``Scene3D``: "surface")
    validated by the table, the same bounds for both; a field left None (optional) stays None.
    The indenter's own choice and the cross-field rules are the scene's."""
    out = {}
    for o in scene_options(scene):
        if o.name == "indenter" or not hasattr(obj, o.name):
            continue
        v = getattr(obj, o.name)
        out[o.name] = None if v is None and o.default is None else o.check(v)
    return out


def check_needs(given) -> None:
    """Refuse an option given without the option it needs (``Option.needs``: --prony without
    --speed), on the command line and in a sweep: ``given`` the names the caller set."""
    for name in given:
        need = _BY_NAME[name].needs if name in _BY_NAME else None
        if need is not None and need not in given:
            o = _BY_NAME[need]
            raise InputError(f"{named(name)} needs {named(need)} ({o.what} [{o.unit}])")


def check_applies(given, indenter: str) -> None:
    """Refuse an option the indenter does not take (one line naming it as typed): ``given``
    the names of the options the caller set (not left to their defaults)."""
    line = indenter == "line"
    ind = named("indenter")
    for name in given:
        o = _BY_NAME.get(name)
        if o is None or o.scenes in ("both", "solve"):
            continue
        n = named(name)
        if name == "load" and not line:
            raise InputError(f"{n} [N/m] is for the line indenter; {ind} {indenter} takes "
                             f"{named('force')} [N]")
        if name == "force" and line:
            raise InputError(f"{n} [N] is for 3D indenters (sphere, cylinder, paraboloid); a line "
                             f"indenter takes {named('load')} [N/m]")
        if o.scenes == "line" and not line:
            raise InputError(f"{n} applies to the line indenter only (3D indenters: the linear "
                             f"{named('interface_compliance')})" if name.startswith("interface")
                             else f"{n} applies to the line indenter only")
        if o.scenes == "surface" and line:
            raise InputError(f"{n} is for 3D indenters ({ind} sphere, cylinder, paraboloid); "
                             f"the line indenter takes {named('load')} [N/m]")
        if o.indenters and not line and indenter not in o.indenters:
            raise InputError(f"{n} applies to {ind} {' or '.join(o.indenters)} only")
