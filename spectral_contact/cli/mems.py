"""MEMS subcommands of the command line: ``compare`` and ``calibrate``.

``register(subparsers)`` adds them to the main parser (``cli.main``).  Each handler
returns an exit status; input problems raise ``InputError`` (the main CLI prints one line and
exits with status 2).  Every input is read and checked before any file is written.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..physics.options import option
from ..units import A_XZ_MV_PER_BAR, A_ZZ_MV_PER_BAR
from .files import csv_file, plan_outputs, staged, to_json, write_outputs

__all__ = ["register", "COMPARE_JSON_KEYS", "CALIBRATE_JSON_KEYS"]

COMPARE_JSON_KEYS = ("load_N_per_m", "mu", "offset_m", "chi_zz_exact", "chi_xz_exact",
                     "chi_zz_goodman", "chi_xz_goodman", "fit_load_N_per_m", "fit_mu", "fits",
                     "best_model")
_EXTRA_KEYS = ("poisson", "poisson_sigma", "interface_compliance_m_per_Pa",
               "interface_compliance_sigma")
CALIBRATE_JSON_KEYS = ("component", "method", "A_mV_per_bar", "A_lo_mV_per_bar",
                       "A_hi_mV_per_bar", "noise_sd_mV", "points", "out")


def _positive(name):
    def conv(text):
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be a number > 0; got {text!r}") from None
        if not (math.isfinite(v) and v > 0):
            raise argparse.ArgumentTypeError(f"must be a finite number > 0; got {text!r}")
        return v
    conv.__name__ = name
    return conv


class _Progress:
    """``what done/total`` on stderr, rewritten in place, only on a terminal and only once the
    work has taken more than ``after_s``; erased when done (stderr keeps its one-line promise)."""

    def __init__(self, what: str, after_s: float = 2.0, stream=None):
        import sys
        import time

        self.what, self.after_s, self.clock = what, after_s, time.monotonic
        self.t0 = self.clock()
        self.stream = sys.stderr if stream is None else stream

    def __call__(self, done: int, total: int) -> None:
        if not (getattr(self.stream, "isatty", lambda: False)()
                and self.clock() - self.t0 > self.after_s):
            return
        text = f"{self.what} {done}/{total}" if done < total else ""
        self.stream.write(f"\r\033[K{text}")
        self.stream.flush()


def _nonnegative(text):
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number >= 0; got {text!r}") from None
    if not (math.isfinite(v) and v >= 0):
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0; got {text!r}")
    return v


def _int_in(lo, hi, why=""):
    def conv(text):
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be an integer in [{lo}, {hi}]; got "
                                             f"{text!r}") from None
        if not lo <= v <= hi:
            raise argparse.ArgumentTypeError(f"must be in [{lo}, {hi}]{why}; got {v}")
        return v
    return conv


N_BOOT_MAX = 10_000
"""Largest --n-boot: each replicate costs one deconvolution; 10^4 replicates pin the 2.5 / 97.5 %
quantiles of the band to ~0.3 % of its width (binomial sd of a quantile, 1/sqrt(n))."""
SEED_MAX = 2**63 - 1
_VALUE_MAX = 1e100  # measured/computed profile values (mV, Pa): squares and sums stay finite
_PLANE_MAX = 4096  # side of the punch's plane grid: ~117 bytes per point (tracemalloc), ~2 GB
_PLANE_BYTES = 117


def _scene_options(p, names, more=None) -> None:
    """Scene options from the one declaration (``physics.options``): flag, default, help; the
    values are checked once, by the scene (or ``options.option(name).check``)."""
    for name in names:
        o = option(name)
        text = o.cli_help() + (f"; {more[name]}" if more and name in more else "")
        p.add_argument(o.flag, dest=o.name, type=o.kind, default=o.default, help=text)


def register(subparsers) -> None:
    """Add ``compare`` and ``calibrate`` to an argparse subparsers object."""
    p = subparsers.add_parser(
        "compare", help="compare measured MEMS profiles with the exact and Goodman models",
        description="Extract P_L = Int S_zz dx and mu_d = Int S_xz / Int S_zz from a measured "
                    "profile, solve both models, view them through the sensor, fit the "
                    "sensor-apex offset, report chi per component and model; also fit P_L, "
                    "mu_d and the offset directly for each model, with 1-sigma uncertainties, "
                    "chi per component and AIC (JSON 'fits', keyed by model; 'best_model').")
    p.add_argument("measured", metavar="MEASURED.csv",
                   help="columns x_m,S_zz_Pa,S_xz_Pa or x_m,U_zz_mV,U_xz_mV (uniform x)")
    _scene_options(p, ("young", "radius", "thickness", "poisson"),
                   {"poisson": "--fit-poisson starts there"})
    p.add_argument("--a-zz", type=_positive("--a-zz"), default=A_ZZ_MV_PER_BAR,
                   help=f"A_zz [mV/bar] for U files ({A_ZZ_MV_PER_BAR:.2f})")
    p.add_argument("--a-xz", type=_positive("--a-xz"), default=A_XZ_MV_PER_BAR,
                   help=f"A_xz [mV/bar] for U files ({A_XZ_MV_PER_BAR:.2f})")
    p.add_argument("--apparatus-zz", metavar="G.csv", default=None,
                   help="radial G_zz (columns r_m, G or G_per_m2) instead of the paper's")
    p.add_argument("--apparatus-xz", metavar="G.csv", default=None,
                   help="radial G_xz instead of the paper's")
    p.add_argument("--tol", type=float, default=1e-4,
                   help=f"{option('tol').what}, {option('tol').accepted()} (default 1e-4)")
    p.add_argument("--no-fit", action="store_true", help="skip the direct fits of P_L, mu_d")
    p.add_argument("--fit-poisson", action="store_true",
                   help="also fit the exact model with the film's Poisson ratio free (in [0, 0.5]):"
                        " fits['exact+poisson'] with poisson, poisson_sigma")
    p.add_argument("--fit-interface", action="store_true",
                   help="also fit the exact model with a linear interface compliance C >= 0 free:"
                        " fits['exact+interface'] with interface_compliance_m_per_Pa and its sigma")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="FILE.png", help="measured points and both models")
    p.set_defaults(func=_cmd_compare)

    p = subparsers.add_parser(
        "calibrate", help="deconvolve the MEMS apparatus function from a rod-scan profile",
        description="Radial profiles (r from 0, uniform): the measured output U and the "
                    "computed base stress under the rod; returns G(r), A and a bootstrap band.")
    p.add_argument("--measured", required=True, metavar="U.csv",
                   help="columns r_m and U_zz_mV (or U_xz_mV)")
    p.add_argument("--computed", metavar="SIGMA.csv", default=None,
                   help="columns r_m and S_zz_Pa (compression > 0) or sigma_zz_Pa (model sign)"
                        " (or the xz ones); default: the flat punch of --punch-load")
    p.add_argument("--punch-load", type=_positive("--punch-load"), default=None,
                   help="rod load P [N] of the scan, to compute sigma (no --computed)")
    p.add_argument("--punch-radius", type=_positive("--punch-radius"), default=250e-6,
                   help="rod radius [m] (250e-6)")
    _scene_options(p, ("thickness",))
    p.add_argument("--component", choices=("zz", "xz"), default="zz",
                   help="zz: normal channel (U_zz, S_zz); xz: shear channel (U_xz, S_xz) "
                        "(default zz)")
    p.add_argument("--method", choices=("ratio", "wiener"), default="wiener",
                   help="ratio: the paper's Fourier ratio with noise floors; wiener: Tikhonov "
                        "with robust GCV (default)")
    p.add_argument("--noise-sd", type=_nonnegative, default=None,
                   help="noise sd of U [mV], >= 0 (default: estimated)")
    p.add_argument("--n-boot", type=_int_in(0, N_BOOT_MAX, " (each replicate costs one "
                                                         "deconvolution)"), default=40,
                   help=f"bootstrap realisations, 0 ... {N_BOOT_MAX} (40)")
    p.add_argument("--seed", type=_int_in(0, SEED_MAX), default=0,
                   help="seed of the bootstrap's random numbers, >= 0 (0)")
    p.add_argument("--out", metavar="FILE.csv", help="write the radial apparatus function")
    p.add_argument("--plot", metavar="FILE.png", help="A G(r) with its band, and the U fit")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_cmd_calibrate)


# --- compare --------------------------------------------------------------------------------

def _apparatus(args):
    from ..instruments.apparatus import load_apparatus_csv

    gzz = load_apparatus_csv(args.apparatus_zz) if args.apparatus_zz else None
    gxz = load_apparatus_csv(args.apparatus_xz) if args.apparatus_xz else None
    return None if gzz is None and gxz is None else (gzz, gxz)


def _cmd_compare(args) -> int:
    from ..api import check_tol
    from ..instruments.compare import FIT_KEYS, compare_models, fit_model, integral_estimates
    from ..instruments.measured_io import read_measured_profile
    from ..physics.scene import Scene

    tol = check_tol(args.tol)
    Scene(young=args.young, radius=args.radius, thickness=args.thickness,
          poisson=args.poisson)  # names the option as typed
    outputs = plan_outputs(inputs={"MEASURED.csv": args.measured,
                                   "--apparatus-zz": args.apparatus_zz,
                                   "--apparatus-xz": args.apparatus_xz},
                           plots=("--plot",), **{"--plot": args.plot})
    prof = read_measured_profile(args.measured)
    apparatus = _apparatus(args)
    Szz, Sxz = prof.stresses(args.a_zz, args.a_xz)
    _warn_x_units(prof.x_m, args.thickness, args.measured)
    P, mu = integral_estimates(prof.x_m, Szz, Sxz)
    try:
        scene = Scene(load=P, mu=mu, young=args.young, radius=args.radius,
                      thickness=args.thickness, poisson=args.poisson)
    except InputError as exc:
        # the estimates' names, not options of compare (the table's words follow them)
        why = exc.as_typed(lambda name: {"load": "the estimate", "mu": "the estimate"}.get(name, name))
        raise InputError(f"{args.measured}: the integral estimates P_L = {P:.4g} N/m, mu_d = "
                         f"{mu:.4g} are out of range ({why})") from None
    try:
        models = compare_models(prof.x_m, Szz, Sxz, scene, tol=tol, apparatus=apparatus)
    except InputError as exc:
        raise InputError(f"{args.measured}: with the integral estimates P_L = {P:.4g} N/m, "
                         f"mu_d = {mu:.4g}: {exc}") from None
    ex, go = models["exact"], models["goodman"]
    fit, fit_note = None, "skipped (--no-fit)" if args.no_fit else "ok"
    fits, failed = {}, {}
    if not args.no_fit:
        from ..errors import ConvergenceError

        # each model fitted directly (P_L, mu_d, offset), with 1-sigma uncertainties and AIC
        for name, m in models.items():
            try:
                fits[name] = fit_model(prof.x_m, Szz, Sxz, scene, m["offset_m"], model=name,
                                       tol=tol, apparatus=apparatus)
            except (ConvergenceError, InputError) as exc:  # the comparison itself stands
                failed[name] = str(exc).splitlines()[0]
        for name, flag, kw in (("exact+poisson", args.fit_poisson, {"fit_poisson": True}),
                               ("exact+interface", args.fit_interface, {"fit_interface": True})):
            if not flag:
                continue
            try:
                fits[name] = fit_model(prof.x_m, Szz, Sxz, scene, ex["offset_m"], model="exact",
                                       tol=tol, apparatus=apparatus, **kw)
            except (ConvergenceError, InputError) as exc:
                failed[name] = str(exc).splitlines()[0]
        for name in list(fits):  # a fit that explains nothing has failed too (issue 24)
            why = _failed_fit(fits[name])
            if why:
                failed[name] = why
                del fits[name]
        if failed:
            fit_note = "; ".join(f"{name} fit failed: {why}" for name, why in failed.items())
        if failed and not fits:
            import warnings

            warnings.warn(f"every direct fit failed ({fit_note}): no best model (JSON "
                          f"\"fits_failed\"); the comparison at the integral estimates stands",
                          UserWarning, stacklevel=2)
        fit = fits.get("exact")
    nan = float("nan")
    rec = {"load_N_per_m": P, "mu": mu, "offset_m": ex["offset_m"],
           "chi_zz_exact": ex["chi_zz"], "chi_xz_exact": ex["chi_xz"],
           "chi_zz_goodman": go["chi_zz"], "chi_xz_goodman": go["chi_xz"],
           "fit_load_N_per_m": fit["load_N_per_m"] if fit else nan,
           "fit_mu": fit["mu"] if fit else nan,
           "offset_goodman_m": go["offset_m"],
           "fit_offset_m": fit["offset_m"] if fit else nan,
           "fit_chi_zz": fit["chi_zz"] if fit else nan,
           "fit_chi_xz": fit["chi_xz"] if fit else nan,
           "fit_note": fit_note, "points": int(prof.x_m.size), "input": prof.kind,
           "young_Pa": args.young, "radius_m": args.radius, "thickness_m": args.thickness,
           "poisson": scene.poisson,
           "fits": {name: {k: f[k] for k in FIT_KEYS + _EXTRA_KEYS if k in f}
                    for name, f in fits.items()},
           "best_model": min(fits, key=lambda k: fits[k]["aic"]) if fits else None,
           "fits_failed": failed}
    write_outputs(outputs, {"--plot": staged(lambda path: _plot_compare(
        path, prof, Szz, Sxz, models, fits, rec, (args.a_zz, args.a_xz)))},
        lambda: _compare_text(args, prof, P, mu, ex, go, fits, fit_note, rec))
    return 0


def _compare_text(args, prof, P, mu, ex, go, fits, fit_note, rec) -> str:
    """compare's summary: the JSON record, or the text."""
    if args.json:
        return to_json(rec)  # null, not NaN
    else:
        mm = 1e3
        lines = [
            f"{prof.path}: {prof.x_m.size} points, x from {prof.x_m[0] * mm:g} to "
            f"{prof.x_m[-1] * mm:g} mm ({'stresses' if prof.kind == 'S' else 'outputs'})",
            f"  integral estimates   P_L = {P:.4g} N/m, mu_d = {mu:.4g}",
            f"  exact model          offset {ex['offset_m'] * mm:8.4f} mm   "
            f"chi_zz {ex['chi_zz']:.4f}   chi_xz {ex['chi_xz']:.4f}",
            f"  Goodman model        offset {go['offset_m'] * mm:8.4f} mm   "
            f"chi_zz {go['chi_zz']:.4f}   chi_xz {go['chi_xz']:.4f}",
        ]
        if not fits or fit_note != "ok":
            lines.append(f"  direct fit           {fit_note}")
        for name, f in fits.items():
            lines.append(
                f"  fit {name:<8s}         P_L = {f['load_N_per_m']:.4g} +- {f['load_sigma']:.2g} N/m, "
                f"mu_d = {f['mu']:.4g} +- {f['mu_sigma']:.2g}, offset {f['offset_m'] * mm:.4f} "
                f"+- {f['offset_sigma'] * mm:.2g} mm, chi_zz {f['chi_zz']:.4f}, "
                f"chi_xz {f['chi_xz']:.4f}, AIC {f['aic']:.1f}"
                + (f", nu = {f['poisson']:.4f} +- {f['poisson_sigma']:.2g}" if "poisson" in f else "")
                + (f", C = {f['interface_compliance_m_per_Pa']:.3g} +- "
                   f"{f['interface_compliance_sigma']:.2g} m/Pa"
                   if "interface_compliance_m_per_Pa" in f else ""))
        if fits:
            lines.append(f"  best model (AIC)     {rec['best_model']}")
        return "\n".join(lines)


FIT_CHI_FAILED = 0.99
"""A direct fit whose chi is at least this in both components leaves the data unexplained (the
model curve misses the window: chi = |S - model| / |S| = 1 when the model is ~0 there)."""
X_SPAN_H = (0.5, 100.0)
"""Plausible span of a measured profile, in film thicknesses (a contact of a few h plus the
base stresses' tails of ~10 h); outside: a units warning (x_m in millimetres, say)."""


def _failed_fit(f) -> str:
    """Why the direct fit ``f`` (a ``fit_model`` record) failed, or "" if it did not."""
    chi = max(f.get("chi_zz", math.nan), f.get("chi_xz", math.nan))
    if not chi < FIT_CHI_FAILED:
        return f"the fitted model explains nothing (chi_zz {f.get('chi_zz', math.nan):.3g}, " \
               f"chi_xz {f.get('chi_xz', math.nan):.3g})"
    sig = [f.get(k) for k in ("load_sigma", "mu_sigma", "offset_sigma")]
    if any(v is None or not math.isfinite(v) for v in sig):
        return "its uncertainties are undetermined (singular Jacobian)"
    return ""


def _warn_x_units(x_m, thickness, path) -> None:
    """A units warning when the measured x span is implausible for the film (``X_SPAN_H``)."""
    span = float(x_m[-1] - x_m[0]) / thickness
    if not X_SPAN_H[0] <= span <= X_SPAN_H[1]:
        import warnings

        warnings.warn(f"{path}: x spans {x_m[-1] - x_m[0]:.4g} m = {span:.3g} film thicknesses "
                      f"(--thickness {thickness:g} m), outside the plausible {X_SPAN_H[0]:g} ... "
                      f"{X_SPAN_H[1]:g}: is x_m in metres?", UserWarning, stacklevel=2)


def _plot_compare(path, prof, Szz, Sxz, models, fits, rec, gains=(19.00, 7.95)):
    """Measured points with each model's direct fit (or, with --no-fit, each model at the
    integral estimates), in the file's units (S in kPa, or U in mV), each component with its
    residual panel (measured - model)."""
    from matplotlib.figure import Figure

    from ..instruments.compare import _shifted

    mm = 1e3
    x = prof.x_m
    step = max(1, x.size // 300)
    if prof.kind == "U":  # plot what the file holds: outputs in mV (U = A S, A in mV/bar)
        scale = {"zz": gains[0] / 1e5, "xz": gains[1] / 1e5}
        unit, what = "mV", "U"
    else:
        scale = {"zz": 1e-3, "xz": 1e-3}
        unit, what = "kPa", "S"
    fig = Figure(figsize=(7.5, 8.5), layout="constrained")
    axes = fig.subplots(4, 1, sharex=True, gridspec_kw={"height_ratios": [3, 1.3, 3, 1.3]})
    styles = {"exact": ("-", "C0"), "goodman": ("--", "C3"), "exact+poisson": ("-.", "C2"),
              "exact+interface": (":", "C4")}
    if fits:
        curves = [(name, m, *styles.get(name, ("-", None)),
                   f"{name} fit: P_L {m['load_N_per_m']:.4g} N/m, mu_d {m['mu']:.3g}")
                  for name, m in fits.items()]
    else:
        curves = [(name, m, *styles.get(name, ("-", None)), f"{name} model at the integral estimates")
                  for name, m in models.items()]
    for (ax, res), E, c in (((axes[0], axes[1]), Szz, "zz"), ((axes[2], axes[3]), Sxz, "xz")):
        key, k = f"S_{c}_Pa", scale[c]
        ax.plot(x[::step] * mm, E[::step] * k, "o", ms=3, mfc="none", color="k", label="measured")
        for _name, m, ls, col, label in curves:
            sel = (m["x_m"] + m["offset_m"] >= x[0]) & (m["x_m"] + m["offset_m"] <= x[-1])
            chi = m.get(f"chi_{c}")
            ax.plot((m["x_m"][sel] + m["offset_m"]) * mm, m[key][sel] * k, ls, color=col,
                    label=f"{label} (chi {chi:.3f})" if chi is not None else label)
            r = (E - _shifted(m["x_m"], m[key], x, m["offset_m"])) * k
            res.plot(x * mm, r, ls, color=col, lw=1)
        ax.axhline(0.0, color="0.6", lw=0.5)
        res.axhline(0.0, color="0.6", lw=0.5)
        ax.set_ylabel(f"{what}_{c} [{unit}]" + (" (> 0 compression)" if c == "zz" else ""))
        res.set_ylabel(f"measured - model\n[{unit}]", fontsize=8)
        ax.legend(fontsize=7)
    name = Path(prof.path).name
    if fits:
        title = (f"{name}: direct fits, best by AIC {rec['best_model']} (integral estimates "
                 f"{rec['load_N_per_m']:.4g} N/m, {rec['mu']:.4g})")
    else:
        title = (f"{name}: P_L = {rec['load_N_per_m']:.4g} N/m, mu_d = {rec['mu']:.4g} (integral "
                 f"estimates, biased low when the window cuts the tails; no fit)")
    fig.suptitle(title, fontsize=9)
    axes[-1].set_xlabel("x [mm] (file frame)")
    fig.savefig(path, dpi=120)


# --- calibrate ------------------------------------------------------------------------------

def _same_grid(r_meas, r_comp, values, name):
    if r_comp.size == r_meas.size and np.allclose(r_comp, r_meas, rtol=0, atol=1e-9 * r_meas[-1]):
        return values
    if r_comp[0] > r_meas[0] + 1e-12 or r_comp[-1] < r_meas[-1] * (1 - 1e-9):
        raise InputError(f"{name}: radii {r_comp[0]:g}..{r_comp[-1]:g} m do not cover the "
                         f"measured profile's {r_meas[0]:g}..{r_meas[-1]:g} m")
    from scipy.interpolate import CubicSpline

    return CubicSpline(r_comp, values)(r_meas)


def _cmd_calibrate(args) -> int:
    from ..instruments.calibration import calibrate
    from ..instruments.measured_io import read_radial_profile

    outputs = plan_outputs(inputs={"--measured": args.measured, "--computed": args.computed},
                           csvs=("--out",), plots=("--plot",),
                           **{"--out": args.out, "--plot": args.plot})
    out = outputs.get("--out")
    comp = args.component
    r, U, _ = read_radial_profile(args.measured, (f"U_{comp}_mV",))
    if args.computed:
        rc, vals, col = read_radial_profile(args.computed, (f"S_{comp}_Pa", f"sigma_{comp}_Pa"))
        S = vals if (comp == "xz" or col.startswith("S_")) else -vals  # compression > 0
        S = _same_grid(r, rc, S, args.computed)
        source = args.computed
    elif args.punch_load:
        from ..instruments.axisym import film_of_thickness, flat_punch_base_stresses

        film = film_of_thickness(args.thickness)  # the thickness checked once, here
        dr, r_max, h = float(r[1] - r[0]), float(r[-1]), film.thickness
        if args.punch_radius >= r_max:
            raise InputError(f"calibrate: --punch-radius {args.punch_radius:g} m must be below the "
                             f"scan's reach r_max = {r_max:g} m ({args.measured}): the scan must "
                             f"cross the punch's edge")
        # the plane grid the film's base stresses are computed on (instruments/axisym.py:
        # period 2 (r_max + 16 h), step dr), before allocating it
        n = 2.0 * (r_max + 16.0 * h) / dr
        if not n <= _PLANE_MAX:
            gb = n * n * _PLANE_BYTES / 1e9 if math.isfinite(n) else math.inf
            h_max = (_PLANE_MAX * dr / 2 - r_max) / 16
            if h_max > 0:  # a thinner film would do
                blame = (f"--thickness {h:g} m" if 16.0 * h > r_max else
                         f"{args.measured} (step dr = {dr:g} m over r_max = {r_max:g} m)")
                hint = f"the film thickness must be <= {h_max:.3g} m for this step"
            else:  # the scan alone is too fine for the grid, whatever the film
                blame = f"{args.measured} (step dr = {dr:g} m over r_max = {r_max:g} m)"
                hint = (f"the scan's step must be >= {2 * (r_max + 16 * h) / _PLANE_MAX:.3g} m "
                        f"(resample it)")
            raise InputError(f"calibrate: {blame} needs a plane grid of {n:.3g}^2 points "
                             f"(~{gb:.3g} GB): at most {_PLANE_MAX}^2; {hint}")
        b = flat_punch_base_stresses(args.punch_load, args.punch_radius, film,
                                     dx_m=float(r[1] - r[0]), r_max_m=float(r[-1]))
        S = -b["sigma_zz_Pa"] if comp == "zz" else b["sigma_xz_Pa"]
        S = S[:r.size]
        source = (f"flat punch P = {args.punch_load:g} N, a = {args.punch_radius:g} m, "
                  f"h = {args.thickness:g} m")
    else:
        raise InputError("calibrate: give --computed SIGMA.csv or --punch-load P")
    for values, where in ((U, args.measured), (S, args.computed or source)):
        big = float(np.max(np.abs(values))) if np.all(np.isfinite(values)) else math.inf
        if not 1.0 / _VALUE_MAX <= big <= _VALUE_MAX:
            raise InputError(f"calibrate: {where}: values up to {big:.3g} are beyond the range "
                             f"the deconvolution can square (largest |value| in "
                             f"[{1 / _VALUE_MAX:g}, {_VALUE_MAX:g}])")
    cal = calibrate(r, U, S, comp, args.method, noise_sd_mV=args.noise_sd, n_boot=args.n_boot,
                    seed=args.seed, progress=_Progress("bootstrap"))
    has_band = int(cal.info["n_boot"]) > 0
    write_outputs(outputs, {
        "--out": csv_file(cal.columns, {
            "written_by": "spectral-contact calibrate",
            "columns": {"r_m": "radius [m] from the sensor centre",
                        "G_per_m2": f"G_{comp}, unit integral over the plane [1/m^2]",
                        "G_lo_per_m2": f"lower edge of the {cal.info['level']:.0%} bootstrap band "
                                       f"(noise only; bias not included) [1/m^2]",
                        "G_hi_per_m2": "upper edge of that band [1/m^2]",
                        "AG_mV_per_bar_per_m2": f"A_{comp} G_{comp} [mV/bar/m^2]"},
            "component": comp, "method": args.method, "A_mV_per_bar": cal.A_mV_per_bar,
            "A_lo_mV_per_bar": cal.A_lo if has_band else None,
            "A_hi_mV_per_bar": cal.A_hi if has_band else None,
            "band_level": cal.info["level"], "n_boot": cal.info["n_boot"],
            "noise_sd_mV": cal.info["noise_sd_mV"], "measured": str(args.measured),
            "computed": source}),
        "--plot": staged(lambda path: _plot_calibration(path, cal, r, U)),
    }, lambda: _calibration_text(args, cal, comp, r, out, has_band))
    return 0


def _calibration_text(args, cal, comp, r, out, has_band) -> str:
    """calibrate's summary: the JSON record, or the text."""
    rec = {"component": comp, "method": args.method, "A_mV_per_bar": cal.A_mV_per_bar,
           "A_lo_mV_per_bar": cal.A_lo if has_band else None,  # no band without the bootstrap
           "A_hi_mV_per_bar": cal.A_hi if has_band else None,
           "noise_sd_mV": cal.info["noise_sd_mV"], "points": int(r.size),
           "out": str(out) if out else None}
    if args.json:
        return to_json(rec)
    band = (f"{cal.info['level']:.0%} noise band {cal.A_lo:.5g} .. {cal.A_hi:.5g}, bias not "
            f"included" if has_band else "no band: --n-boot 0")
    return (f"G_{comp} by {args.method}: A_{comp} = {cal.A_mV_per_bar:.5g} mV/bar "
            f"({band}); G(0) = {cal.G[0]:.4g} 1/m^2; "
            f"noise sd {cal.info['noise_sd_mV']:.3g} mV" + (f"; wrote {out}" if out else ""))


def _plot_calibration(path, cal, r, U):
    from matplotlib.figure import Figure

    mm = 1e3
    fig = Figure(figsize=(7, 6), layout="constrained")
    axes = fig.subplots(2, 1, sharex=True)
    A = cal.A_mV_per_bar
    ax = axes[0]
    n_boot = int(cal.info.get("n_boot", 0))
    if n_boot > 0:
        ax.fill_between(cal.r_m * mm, A * cal.G_lo / 1e6, A * cal.G_hi / 1e6, color="C0", alpha=0.3,
                        label=f"{cal.info['level']:.0%} band, {n_boot} bootstrap realisations "
                              f"(noise only; bias not included)")
        band = f" (noise band {cal.A_lo:.4g} .. {cal.A_hi:.4g})"
    else:
        band = " (no bootstrap: --n-boot 0)"
    ax.plot(cal.r_m * mm, A * cal.G / 1e6, "C0-", label=f"A G_{cal.component} ({cal.method})")
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.set_ylabel("A G [mV/bar/mm^2]")
    ax.set_xlabel("r [mm] from the sensor centre")
    ax.xaxis.set_tick_params(labelbottom=True)
    ax.set_title(f"A_{cal.component} = {A:.4g} mV/bar{band}", fontsize=9)
    ax.legend(fontsize=8)
    ax = axes[1]
    ax.plot(r * mm, U, "ko", ms=3, mfc="none", label="measured U")
    ax.plot(cal.r_m * mm, cal.U_fit_mV, "C1-", label="fit: A G (*) sigma")
    ax.set_xlabel("r [mm] from the rod axis")
    ax.set_ylabel(f"U_{cal.component} [mV]")
    ax.legend(fontsize=8)
    fig.savefig(path, dpi=120)
