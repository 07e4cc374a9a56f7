"""Command line: ``spectral-contact solve|study|...``.

Exit status: 0 success; 2 bad input (one line on stderr naming the option and its accepted
range, nothing written); 3 no convergence (one line); 130 / 143 interrupted by SIGINT / SIGTERM
(one line, temporaries removed, nothing written); 1 only for a bug (one line; set
SPECTRAL_CONTACT_DEBUG=1 for the traceback).  Warnings are printed as one line each.
"""
from __future__ import annotations

import argparse
import importlib
import os
import sys
import threading

from ..errors import ConvergenceError, InputError, SpectralContactError
from ..physics.scene import PAPER_SCENE
from . import files as _files

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


def _summary_text(r) -> str:
    s = r.summary()
    for key in ("contact_center_m", "x0_m"):  # a centred contact prints 0, not -0.00000
        if abs(s[key]) < 5e-9:
            s[key] = 0.0
    mm, kPa = 1e3, 1e-3
    lines = [
        f"{s['model']} model, {s['method']} method: P_L = {s['load_N_per_m']:g} N/m, mu_d = {s['mu']:g}, "
        f"E = {s['young_Pa'] / 1e6:g} MPa, R = {s['radius_m'] * mm:g} mm, h = {s['thickness_m'] * mm:g} mm",
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
    from .files import Outputs, check_outputs, check_plot_path, to_json, write_csv

    scene = Scene(load=args.load, mu=args.mu, young=args.young, radius=args.radius,
                  thickness=args.thickness)
    outputs = check_outputs(**{"--profiles": args.profiles, "--plot": args.plot})
    if args.plot is not None:
        check_plot_path(args.plot)
    r = solve(scene, model=args.model, method=args.method, tol=args.tol,
              grid_points=args.grid_points, domain_length=args.domain_length)
    if not r.tolerance_met:
        print(f"warning: error estimate {r.error_estimate:.1e} > --tol {args.tol:g} at the fixed "
              f"--grid-points {args.grid_points} (JSON: \"tolerance_met\": false); raise "
              f"--grid-points or leave it automatic", file=sys.stderr)
    sensor = None
    if args.sensor:
        from ..instruments.sensor import sensor_view

        sensor = sensor_view(r, A_zz_mV_per_bar=args.a_zz, A_xz_mV_per_bar=args.a_xz)
    with Outputs() as outs:
        if "--profiles" in outputs:
            cols = r.profiles()
            if sensor:
                cols.update({k: sensor[k] for k in ("S_zz_Pa", "S_xz_Pa", "U_zz_mV", "U_xz_mV")})
            write_csv(outs.path(outputs["--profiles"]), cols,
                      "spectral_contact profiles, apex frame, +x = sliding direction; "
                      "sigma_zz < 0 in compression (S_zz > 0 in compression)")
        if "--plot" in outputs:
            from .plots import plot_result

            plot_result(r, outs.path(outputs["--plot"]), sensor=sensor)
    if args.json:
        print(to_json(r.summary()))
    else:
        print(_summary_text(r))
    return 0


def study_names() -> list[str]:
    """The studies the command line runs: the public modules of ``studies`` with a main()."""
    import pkgutil

    try:
        import studies
    except ModuleNotFoundError:
        return []
    return sorted(m.name for m in pkgutil.iter_modules(studies.__path__)
                  if not m.name.startswith("_"))


def _cmd_study(args) -> int:
    names = study_names()
    if args.name not in names:
        listed = ", ".join(names) or "(none found: run from the project folder)"
        raise InputError(f"study: unknown study {args.name!r}; one of {listed}")
    mod = importlib.import_module(f"studies.{args.name}")
    if not callable(getattr(mod, "main", None)):
        raise InputError(f"study: {args.name!r} is not a runnable study (no main)")
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
    p.add_argument("--tol", type=float, default=1e-4, help="relative accuracy target, in [1e-14, 0.1) (default 1e-4)")
    p.add_argument("--grid-points", type=int, default=None, help="fix N instead of choosing it from --tol")
    p.add_argument("--domain-length", type=float, default=None, help="fix the FFT period L [m]")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    p.add_argument("--profiles", metavar="FILE.csv", help="write the profiles (SI) as CSV")
    p.add_argument("--plot", metavar="FILE.png", help="plot pressure and base stresses")
    p.add_argument("--sensor", action="store_true", help="add the MEMS sensor view (S, U) to profiles and plot")
    p.add_argument("--a-zz", type=float, default=19.00, help="A_zz [mV/bar] (default 19.00)")
    p.add_argument("--a-xz", type=float, default=7.95, help="A_xz [mV/bar] (default 7.95)")
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


# the API's parameter names as the options the user typed (messages of InputError)
_OPTION_NAMES = [
    (r"load \(P_L\)", "--load (P_L)"), (r"mu \(mu_d\)", "--mu (mu_d)"),
    (r"young \(E\)", "--young (E)"), (r"radius \(R\)", "--radius (R)"),
    (r"thickness \(h\)", "--thickness (h)"), (r"domain_length", "--domain-length"),
    (r"grid_points", "--grid-points"), (r"tol(?= must| \d|,|$)", "--tol"), (r"raise tol", "raise --tol"),
    (r"method (abel|fft)", r"--method \1"), (r"model (hertz|exact|goodman)", r"--model \1"),
]


def as_options(message: str, options=None) -> str:
    """Rewrite the API's parameter names in ``message`` as command-line options (only those in
    ``options``, the command's option strings, when given)."""
    import re

    for pat, rep in _OPTION_NAMES:
        if options is not None and re.search(r"--[\w-]+", rep).group() not in options:
            continue
        message = re.sub(r"(?<![-\w])" + pat, rep, message)
    return message


def _options_of(parser, argv) -> set | None:
    """The option strings of the subcommand in ``argv`` (None if it cannot be told)."""
    try:
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        cmd = next((x for x in (sys.argv[1:] if argv is None else argv) if x in sub.choices), None)
        return set(sub.choices[cmd]._option_string_actions) if cmd else None
    except (StopIteration, AttributeError):
        return None


class _Terminated(BaseException):
    """SIGTERM, raised in the main thread so that outputs are cleaned up like on Ctrl-C."""


def _on_sigterm(signum, frame):
    raise _Terminated()


_WARNINGS: list[str] = []
_MEMORY_HINTS = {
    "solve": "raise --tol, or lower --grid-points",
    "compare": "raise --tol, or give a shorter measured profile",
    "calibrate": "give a shorter or coarser radial profile",
}


def _one_line_warnings(message, category, filename, lineno, file=None, line=None):
    """Warnings are kept, one line each, and printed only if the command succeeds (a failing
    command prints its one error line and nothing else)."""
    text = "warning: " + " ".join(str(message).split())
    if text not in _WARNINGS:
        _WARNINGS.append(text)


def main(argv=None) -> int:
    import signal
    import warnings

    threading_main = threading.current_thread() is threading.main_thread()
    if threading_main:
        old_term = signal.signal(signal.SIGTERM, _on_sigterm)
    old_show = warnings.showwarning
    warnings.showwarning = _one_line_warnings
    _WARNINGS.clear()
    _files.COMMITTED.clear()
    options = command = None
    try:
        parser = build_parser()
        options = _options_of(parser, argv)
        args = parser.parse_args(argv)
        command = args.command
        status = args.func(args)
        for text in _WARNINGS:
            print(text, file=sys.stderr)
        return status
    except InputError as exc:
        print(f"error: {as_options(_first_line(exc), options)}", file=sys.stderr)
        return 2
    except ConvergenceError as exc:
        print(f"not converged: {as_options(_first_line(exc), options)}", file=sys.stderr)
        return 3
    except KeyboardInterrupt:
        print(f"interrupted (SIGINT): {_written()}", file=sys.stderr)
        return 130
    except _Terminated:
        print(f"terminated (SIGTERM): {_written()}", file=sys.stderr)
        return 143
    except OSError as exc:
        where = f"{exc.filename}: " if exc.filename else ""
        print(f"error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 2
    except SpectralContactError as exc:
        print(f"error: {_first_line(exc)}", file=sys.stderr)
        return 2
    except MemoryError:
        hint = _MEMORY_HINTS.get(command, "the problem is too large for this machine")
        print(f"error: out of memory: {hint}", file=sys.stderr)
        return 2
    except Exception as exc:  # a bug: still one line (set SPECTRAL_CONTACT_DEBUG=1 for the traceback)
        if os.environ.get("SPECTRAL_CONTACT_DEBUG"):
            raise
        if type(exc).__name__ == "LinAlgError":  # round-off defeated the linear algebra
            print(f"not converged: linear algebra failed ({_first_line(exc)})", file=sys.stderr)
            return 3
        print(f"internal error ({type(exc).__name__}): {_first_line(exc)}", file=sys.stderr)
        return 1
    finally:
        warnings.showwarning = old_show
        if threading_main:
            signal.signal(signal.SIGTERM, old_term)


def _written() -> str:
    """What an interrupted command leaves: nothing, or outputs completed before the signal."""
    done = _files.COMMITTED
    if not done:
        return "no output written"
    return "outputs were complete before the signal and kept: " + ", ".join(map(str, done))


def _first_line(exc) -> str:
    return " ".join(str(exc).split())


if __name__ == "__main__":
    sys.exit(main())
