"""Command line: ``spectral-contact solve|study|...``.

Errors in the input print one line on stderr and exit with status 2; a solver that does not
converge prints one line and exits with status 3.
"""
from __future__ import annotations

import argparse
import importlib
import os
import sys

from ..errors import ConvergenceError, InputError, SpectralContactError
from ..physics.scene import PAPER_SCENE
from ..units import A_XZ_MV_PER_BAR, A_ZZ_MV_PER_BAR

__all__ = ["main", "build_parser"]

# modules that add subcommands: each exposes register(subparsers)
_PLUGINS = ("spectral_contact.cli.mems",)


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit status 2
        raise InputError(f"{self.prog}: {message}")


def _add_scene_options(p):
    d = PAPER_SCENE
    p.add_argument("--load", type=float, default=d.load, help=f"P_L, lineic load [N/m] (default {d.load:g})")
    p.add_argument("--mu", type=float, default=d.mu,
                   help=f"mu_d, friction coefficient, signed: < 0 slides toward -x (default {d.mu:g})")
    p.add_argument("--young", type=float, default=d.young, help=f"E [Pa] (default {d.young:g})")
    p.add_argument("--radius", type=float, default=d.radius, help=f"R [m] (default {d.radius:g})")
    p.add_argument("--thickness", type=float, default=d.thickness, help=f"h [m] (default {d.thickness:g})")
    p.add_argument("--poisson", type=float, default=d.poisson,
                   help=f"nu, the film's Poisson ratio in [0, 0.5] (default {d.poisson:g}: "
                        "incompressible; < 0.5 needs --method fft)")
    p.add_argument("--friction-law", choices=("amontons", "power", "linear"), default="amontons",
                   help="amontons: q = mu p (default); power: q = mu (p/p_ref)^-n p; "
                        "linear: q = tau_0 + alpha p in the contact (--method fft)")
    p.add_argument("--friction-exponent", type=float, default=None,
                   help="n of the power law, in [0, 1) (default 0)")
    p.add_argument("--friction-pref", type=float, default=None, help="p_ref of the power law [Pa], > 0")
    p.add_argument("--shear-strength", type=float, default=None,
                   help="tau_0 of the linear law [Pa] (same sign as --shear-slope)")
    p.add_argument("--shear-slope", type=float, default=None, help="alpha of the linear law")
    p.add_argument("--interface-compliance", type=float, default=0.0,
                   help="C [m/Pa] >= 0: the interface closes by C p (default 0: rigid; --method fft)")
    p.add_argument("--interface-law", choices=("linear", "exponential"), default="linear",
                   help="linear: --interface-compliance (default); exponential: p = p0 exp(-g/lambda) "
                        "at an interface gap g (soft edges; --method fft, Amontons friction)")
    p.add_argument("--interface-pressure", type=float, default=None,
                   help="p0 of the exponential interface law [Pa], > 0")
    p.add_argument("--interface-length", type=float, default=None,
                   help="lambda of the exponential interface law [m], > 0")


def _summary_text(r) -> str:
    s = r.summary()
    for key in ("contact_center_m", "x0_m"):  # a centred contact prints 0, not -0.00000
        if abs(s[key]) < 5e-9:
            s[key] = 0.0
    mm, kPa = 1e3, 1e-3
    lines = [
        f"{s['model']} model, {s['method']} method: P_L = {s['load_N_per_m']:g} N/m, mu_d = {s['mu']:g}, "
        f"E = {s['young_Pa'] / 1e6:g} MPa, R = {s['radius_m'] * mm:g} mm, h = {s['thickness_m'] * mm:g} mm"
        + (f", nu = {s['poisson']:g}" if s["poisson"] != 0.5 else ""),
        f"  contact half-width a     {s['half_width_m'] * mm:10.5f} mm",
        f"  contact centre (apex=0)  {s['contact_center_m'] * mm:10.5f} mm   (paper's x0 = {s['x0_m'] * mm:.5f} mm)",
        f"  indentation              {s['indentation_m'] * 1e6:10.5f} um",
        f"  peak pressure            {s['max_pressure_Pa'] * kPa:10.4f} kPa at x = {s['max_pressure_x_m'] * mm:.4f} mm",
    ]
    if r.base_sigma_zz.size:
        import numpy as np

        i = int(np.argmin(r.base_sigma_zz_Pa))
        j = int(np.argmax(np.abs(r.base_sigma_xz_Pa)))
        for name, field, m in (("zz", r.base_sigma_zz_Pa, i), ("xz", r.base_sigma_xz_Pa, j)):
            lines.append(f"  peak base sigma_{name}       {field[m] * kPa:10.4f} kPa at x = {r.x_m[m] * mm:.4f} mm")
    if s["friction_law"] != "amontons":
        lines.append(f"  friction law {s['friction_law']}: Q/P = {s['Q_over_P']:.5f}")
    if s["interface_compliance_m_per_Pa"]:
        lines.append(f"  interface compliance     {s['interface_compliance_m_per_Pa']:g} m/Pa")
    if s["interface_law"] == "exponential":
        lines.append(f"  exponential interface    p0 = {s['interface_pressure_Pa']:g} Pa, lambda = "
                     f"{s['interface_length_m']:g} m; {r.info.get('width_definition', '')}")
    if "auto_reason" in r.info:
        lines.append(f"  auto: {r.info['auto_reason']}")
    grid = (f"{s['grid_points']} Nystrom nodes, profiles over {s['domain_length_m'] * mm:.2f} mm"
            if s["method"] == "abel" else
            f"grid {s['grid_points']} points over {s['domain_length_m'] * mm:.2f} mm")
    lines.append(
        f"  {grid}, {s['iterations']} iterations, "
        f"residual {s['residual']:.1e}, error estimate {s['error_estimate']:.1e}, "
        f"solve {s['wall_time_s'] * 1e3:.1f} ms (+ planning {s['plan_time_s'] * 1e3:.1f} ms)")
    return "\n".join(lines)


def _cmd_solve(args) -> int:
    from ..api import solve
    from ..physics.scene import Scene
    from .files import check_plot_path, to_json, write_csv

    scene = Scene(load=args.load, mu=args.mu, young=args.young, radius=args.radius,
                  thickness=args.thickness, poisson=args.poisson, friction_law=args.friction_law,
                  friction_exponent=args.friction_exponent, friction_pref=args.friction_pref,
                  shear_strength=args.shear_strength, shear_slope=args.shear_slope,
                  interface_compliance=args.interface_compliance, interface_law=args.interface_law,
                  interface_pressure=args.interface_pressure, interface_length=args.interface_length)
    if args.plot:
        check_plot_path(args.plot)
    r = solve(scene, model=args.model, method=args.method, tol=args.tol,
              grid_points=args.grid_points, domain_length=args.domain_length)
    sensor = None
    if args.sensor:
        from ..instruments.sensor import sensor_view

        sensor = sensor_view(r, A_zz_mV_per_bar=args.a_zz, A_xz_mV_per_bar=args.a_xz)
    if args.profiles:
        cols = r.profiles()
        if sensor:
            cols.update({k: sensor[k] for k in ("S_zz_Pa", "S_xz_Pa", "U_zz_mV", "U_xz_mV")})
        write_csv(args.profiles, cols,
                  "spectral_contact profiles, apex frame, +x = sliding direction; "
                  "sigma_zz < 0 in compression (S_zz > 0 in compression)")
    if args.plot:
        from .plots import plot_result

        plot_result(r, args.plot, sensor=sensor)
    if args.json:
        print(to_json(r.summary()))
    else:
        print(_summary_text(r))
    return 0


def _cmd_study(args) -> int:
    try:
        mod = importlib.import_module(f"studies.{args.name}")
    except ModuleNotFoundError:
        raise InputError(f"study: unknown study {args.name!r} (see studies/README.md)") from None
    argv = (["--quick"] if args.quick else []) + (["--out", args.out] if args.out else [])
    return int(mod.main(argv) or 0)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="spectral-contact",
                     description="Sliding cylinder on a bonded incompressible film: pressure, "
                                 "base stresses, MEMS view.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    p = sub.add_parser("solve", help="solve one scene (default: the paper's)")
    _add_scene_options(p)
    p.add_argument("--model", choices=("exact", "goodman", "hertz", "auto"), default="exact")
    p.add_argument("--method", choices=("fft", "abel"), default="fft")
    p.add_argument("--tol", type=float, default=1e-4, help="relative accuracy target, in (0, 0.1) (default 1e-4)")
    p.add_argument("--grid-points", type=int, default=None, help="fix N instead of choosing it from --tol")
    p.add_argument("--domain-length", type=float, default=None, help="fix the FFT period L [m]")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    p.add_argument("--profiles", metavar="FILE.csv", help="write the profiles (SI) as CSV")
    p.add_argument("--plot", metavar="FILE.png", help="plot pressure and base stresses")
    p.add_argument("--sensor", action="store_true", help="add the MEMS sensor view (S, U) to profiles and plot")
    p.add_argument("--a-zz", type=float, default=A_ZZ_MV_PER_BAR,
                   help=f"A_zz [mV/bar] (default {A_ZZ_MV_PER_BAR:.2f})")
    p.add_argument("--a-xz", type=float, default=A_XZ_MV_PER_BAR,
                   help=f"A_xz [mV/bar] (default {A_XZ_MV_PER_BAR:.2f})")
    p.set_defaults(func=_cmd_solve)
    p = sub.add_parser("study", help="run a study from studies/ (python -m studies.NAME)")
    p.add_argument("name")
    p.add_argument("--quick", action="store_true")
    p.add_argument("--out", default=None)
    p.set_defaults(func=_cmd_study)
    for name in _PLUGINS:
        try:
            mod = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name != name:
                raise
            continue
        mod.register(sub)
    return parser


def main(argv=None) -> int:
    try:
        args = build_parser().parse_args(argv)
        return args.func(args)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except ConvergenceError as exc:
        print(f"not converged: {exc}", file=sys.stderr)
        return 3
    except (OSError, SpectralContactError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except MemoryError:
        print("error: out of memory: raise --tol or fix a smaller --grid-points", file=sys.stderr)
        return 2
    except Exception as exc:  # a bug: still one line (set SPECTRAL_CONTACT_DEBUG=1 for the traceback)
        if os.environ.get("SPECTRAL_CONTACT_DEBUG"):
            raise
        print(f"internal error ({type(exc).__name__}): {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
