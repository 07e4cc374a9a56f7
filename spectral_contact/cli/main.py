"""Command line: ``spectral-contact solve|study|...``.

Exit status: 0 success; 2 bad input (one line on stderr naming the option and its accepted
range, nothing written); 3 no convergence (one line); 130 / 143 interrupted by SIGINT / SIGTERM
(one line, temporaries removed, nothing written); 1 only for a bug (one line; set
SPECTRAL_CONTACT_DEBUG=1 for the traceback).  Warnings are printed as one line each.
"""
from __future__ import annotations

import argparse
import importlib
import math
import os
import re
import sys
import threading

from ..errors import ConvergenceError, InputError, SpectralContactError
from ..units import A_XZ_MV_PER_BAR, A_ZZ_MV_PER_BAR
from . import files as _files
from .scene_options import add_scene_options, add_solve_options, scene_from_args

__all__ = ["main", "build_parser"]



def _plugins():
    """The subcommands' modules beside ``solve`` and ``study``: each exposes register(subparsers)
    (a new subcommand: its module in cli/ and one line here)."""
    from . import invert, mems, onset, sweep

    return (mems.register, sweep.register, onset.register, invert.register)


class _Parser(argparse.ArgumentParser):
    # a negative number in any notation is a value, not an option: `--mu -1e-3`, `--mu -inf`
    # (Python < 3.13's argparse took "-1e-3" for an option: "expected one argument")
    # (as 3.13 does; a sweep's list or range `-1e-1,2`, `-1:1:0.5` too)
    _NEGATIVE = re.compile(r"^-\.?\d|^-(inf|infinity|nan)\b", re.IGNORECASE)

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = self._NEGATIVE

    def error(self, message):  # one line, exit status 2
        raise InputError(f"{self.prog}: {message}")


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def _law_text(s: dict) -> str:
    """The friction law with its parameters, for a summary's header (the linear law does not
    use mu_d: it is not shown then)."""
    law = s.get("friction_law", "amontons")
    if law == "linear":
        return (f"q = tau_0 + alpha p with tau_0 = {s['shear_strength_Pa']:g} Pa, alpha = "
                f"{s['shear_slope']:g}")
    if law == "power":
        return (f"mu_d = {s['mu']:g} (p/p_ref)^-n with n = {s['friction_exponent']:g}, p_ref = "
                f"{s['friction_pref_Pa']:g} Pa")
    return f"mu_d = {s['mu']:g}"


def _summary_text(r, view=None) -> str:
    """The text summary of a result (and of its sensor view, if given)."""
    s = r.to_dict()
    for key in ("contact_center_m", "x0_m"):  # a centred contact prints 0, not -0.00000
        if abs(s[key]) < 5e-9:
            s[key] = 0.0
    mm, kPa = 1e3, 1e-3
    loaded = s["max_pressure_Pa"] > 0
    at = f" at x = {s['max_pressure_x_m'] * mm:.4f} mm" if loaded else ""
    lines = [
        f"{s['model']} model, {s['method']} method: P_L = {s['load_N_per_m']:g} N/m, {_law_text(s)}, "
        f"E = {s['young_Pa'] / 1e6:g} MPa, R = {s['radius_m'] * mm:g} mm, h = {s['thickness_m'] * mm:g} mm"
        + (f", nu = {s['poisson']:g}" if s["poisson"] != 0.5 else ""),
        f"  contact half-width a     {s['half_width_m'] * mm:10.5f} mm",
        f"  contact centre (apex=0)  {s['contact_center_m'] * mm:10.5f} mm   (paper's x0 = {s['x0_m'] * mm:.5f} mm)",
        f"  indentation              {s['indentation_m'] * 1e6:10.5f} um",
        f"  peak pressure            {s['max_pressure_Pa'] * kPa:10.4f} kPa{at}",
    ]
    iv = s["contact_intervals_m"]
    if len(iv) > 1:
        spans = ", ".join(f"[{u * mm:.4f}, {v * mm:.4f}]" for u, v in iv)
        lines.append(f"  contact in {len(iv)} intervals {spans} mm (a and centre: of their envelope)")
    if r.base_sigma_zz.size and loaded:
        import numpy as np

        i = int(np.argmin(r.base_sigma_zz_Pa))
        j = int(np.argmax(np.abs(r.base_sigma_xz_Pa)))
        for name, field, m in (("zz", r.base_sigma_zz_Pa, i), ("xz", r.base_sigma_xz_Pa, j)):
            lines.append(f"  peak base sigma_{name}       {field[m] * kPa:10.4f} kPa at x = {r.x_m[m] * mm:.4f} mm")
    if view is not None and loaded:
        for c in ("zz", "xz"):
            S, x, U = (getattr(view, f"S_{c}_peak_Pa"), getattr(view, f"S_{c}_peak_x_m"),
                       getattr(view, f"U_{c}_peak_mV"))
            lines.append(f"  sensor peak S_{c}         {S * kPa:10.4f} kPa at x = {x * mm:.4f} mm   "
                         f"(U_{c} = {U:.4f} mV)")
    if s["friction_law"] != "amontons":
        lines.append(f"  friction law {s['friction_law']}: Q/P = {s['Q_over_P']:.5f}")
    if s["interface_compliance_m_per_Pa"]:
        lines.append(f"  interface compliance     {s['interface_compliance_m_per_Pa']:g} m/Pa")
    if s["interface_law"] == "exponential":
        lines.append(f"  exponential interface    p0 = {s['interface_pressure_Pa']:g} Pa, lambda = "
                     f"{s['interface_length_m']:g} m; {r.info.get('width_definition', '')}")
    lines += _visco_text(s)
    if "auto_reason" in r.info:
        lines.append(f"  auto: {r.info['auto_reason']}")
    grid = (f"{s['grid_points']} Nystrom nodes, profiles over {s['domain_length_m'] * mm:.2f} mm"
            if s["method"] == "abel" else
            f"grid {s['grid_points']} points over {s['domain_length_m'] * mm:.2f} mm")
    lines.append(
        f"  {grid}, {_plural(s['iterations'], 'iteration')}, "
        f"residual {s['residual']:.1e}, error estimate {s['error_estimate']:.1e}, "
        f"solve {s['wall_time_s'] * 1e3:.1f} ms (+ planning {s['plan_time_s'] * 1e3:.1f} ms)")
    return "\n".join(lines)


_PROFILE_NOTES = {
    "x_m": "position [m] from the indenter apex, +x the sliding direction (mu_d > 0)",
    "pressure_Pa": "contact pressure p = -sigma_zz(x, h) >= 0 [Pa]",
    "surface_shear_Pa": "surface shear sigma_xz(x, h) = mu_d p [Pa]",
    "base_sigma_zz_Pa": "normal stress at the rigid base sigma_zz(x, 0) [Pa], < 0 in compression",
    "base_sigma_xz_Pa": "shear stress at the rigid base sigma_xz(x, 0) [Pa]",
    "S_zz_Pa": "MEMS view S_zz = -G_zz (*) sigma_zz(x, 0) [Pa], > 0 in compression",
    "S_xz_Pa": "MEMS view S_xz = G_xz (*) sigma_xz(x, 0) [Pa]",
    "U_zz_mV": "sensor output U_zz = A_zz S_zz [mV]",
    "U_xz_mV": "sensor output U_xz = A_xz S_xz [mV]",
}


def _apparatus_option(path):
    if not path:
        return None
    from ..instruments.apparatus import load_apparatus_csv

    return load_apparatus_csv(path)


def _cmd_solve(args) -> int:
    from ..api import solve
    from ..physics.scene import Scene
    from .files import csv_file, json_ready, plan_outputs, staged, to_json, write_outputs

    scene = scene_from_args(args)
    if not isinstance(scene, Scene):
        return _cmd_solve3d(args, scene)
    if args.maps is not None:
        raise InputError("--maps is for 3D indenters (--indenter sphere, cylinder, paraboloid); "
                         "the line indenter takes --profiles")
    outputs = plan_outputs(inputs=_inputs(args), csvs=("--profiles",), plots=("--plot",),
                           **{"--profiles": args.profiles, "--plot": args.plot})
    apparatus = None
    if args.apparatus_zz or args.apparatus_xz:
        if not args.sensor:
            raise InputError("--apparatus-zz/--apparatus-xz need --sensor")
        apparatus = (_apparatus_option(args.apparatus_zz), _apparatus_option(args.apparatus_xz))
    r = solve(scene, model=args.model, method=args.method, tol=args.tol,
              grid_points=args.grid_points, domain_length=args.domain_length)
    if not r.tolerance_met:
        print(f"warning: error estimate {r.error_estimate:.1e} > --tol {args.tol or 1e-4:g} at the "
              f"fixed --grid-points {args.grid_points} (JSON: \"tolerance_met\": false); raise "
              f"--grid-points or leave it automatic", file=sys.stderr)
    view = None
    if args.sensor:
        from ..instruments.mems_view import sensor

        view = sensor(r, A_zz_mV_per_bar=args.a_zz, A_xz_mV_per_bar=args.a_xz, apparatus=apparatus)
    record = r.to_dict() | (view.to_dict() if view is not None else {})

    def columns():
        cols = r.profiles()
        if view is not None:
            cols.update({k: v for k, v in view.profiles().items() if k != "x_m"})
        return cols

    def plot(path):
        from .plots import plot_result

        plot_result(r, path, sensor=view)

    # stdout is one of the outputs: written, then the files renamed, or nothing at all
    write_outputs(outputs, {
        "--profiles": csv_file(columns, lambda cols: {
            "written_by": "spectral-contact solve",
            "columns": {k: _PROFILE_NOTES[k] for k in cols},
            "result": record}),
        "--plot": staged(plot),
    }, lambda: (to_json(json_ready(record)) if args.json  # null, not NaN (no peak at zero load)
                else _summary_text(r, view)))
    return 0


def _inputs(args) -> dict:
    """The files ``solve`` reads (no output may name one of them)."""
    return {"--apparatus-zz": getattr(args, "apparatus_zz", None),
            "--apparatus-xz": getattr(args, "apparatus_xz", None)}


def _visco_text(s) -> list:
    """The viscoelastic film's line of a text summary (issue 23; none on an elastic film)."""
    if "speed_m_per_s" not in s:
        return []
    return [f"  viscoelastic film        V = {s['speed_m_per_s']:g} m/s, {len(s['prony_terms'])} "
            f"Prony term(s); mu_def = {s['deformation_friction']:.5g}, Q/P = mu + mu_def = "
            f"{s['Q_over_P']:.5g}"]


def _summary_text3d(r, sensor=None) -> str:
    s = r.summary()
    mm, kPa = 1e3, 1e-3
    extra = {"cylinder": f", length {s.get('length_m', 0) * mm:g} mm",
             "paraboloid": f", R_x = {s.get('radius_x_m', 0) * mm:g} mm, "
                           f"R_y = {s.get('radius_y_m', 0) * mm:g} mm"}.get(s["indenter"], "")
    lines = [
        f"{s['model']} model, {s['method']} method, {s['indenter']}{extra}: F = {s['force_N']:g} N, "
        f"{_law_text(s)}, E = {s['young_Pa'] / 1e6:g} MPa, R = {s['radius_m'] * mm:g} mm, "
        f"h = {s['thickness_m'] * mm:g} mm",
        f"  contact area             {s['contact_area_m2'] * 1e6:10.5f} mm^2 "
        f"(radius sqrt(A/pi) {s['contact_radius_m'] * mm:.5f} mm)",
        f"  contact x extent         {s['contact_x_min_m'] * mm:10.5f} .. "
        f"{s['contact_x_max_m'] * mm:.5f} mm (apex = 0), y half-width "
        f"{s['contact_y_half_width_m'] * mm:.5f} mm",
        f"  pressure centroid x      {s['pressure_centroid_x_m'] * mm:10.5f} mm",
        f"  indentation              {s['indentation_m'] * 1e6:10.5f} um",
        f"  peak pressure            {s['max_pressure_Pa'] * kPa:10.4f} kPa at "
        f"({s['max_pressure_x_m'] * mm:.4f}, {s['max_pressure_y_m'] * mm:.4f}) mm",
        f"  line load at y = 0       {s['line_load_y0_N_per_m']:10.4f} N/m",
        f"  grid {s['grid_points'][0]} x {s['grid_points'][1]} points over "
        f"{s['domain_length_m'][0] * mm:.2f} x {s['domain_length_m'][1] * mm:.2f} mm, "
        f"{s['iterations']} iterations, residual {s['residual']:.1e}, error estimate "
        f"{s['error_estimate']:.1e}, solve {s['wall_time_s'] * 1e3:.0f} ms "
        f"(+ planning {s['plan_time_s'] * 1e3:.0f} ms)",
    ] + _visco_text(s)
    if sensor is not None:  # the sensor peaks, as in the line summary (x, y of each peak)
        import numpy as np

        x, y = r.maps()["x_m"], r.maps()["y_m"]
        for c in ("zz", "xz"):
            S, U = sensor[f"S_{c}_Pa"], sensor[f"U_{c}_mV"]
            i, j = np.unravel_index(int(np.argmax(np.abs(S))), S.shape)
            lines.append(f"  sensor peak S_{c}         {S[i, j] * kPa:10.4f} kPa at ({x[i] * mm:.4f}, "
                         f"{y[j] * mm:.4f}) mm   (U_{c} = {U[i, j]:.4f} mV)")
    if r.scene.indenter == "cylinder":
        lines.append("  (sharp ends: the peak pressure there grows with the resolution; it is "
                     "reported, not controlled by --tol)")
    return "\n".join(lines)


def _cmd_solve3d(args, scene) -> int:
    import numpy as np

    from ..api import solve
    from .files import csv_file, plan_outputs, staged, to_json, write_outputs

    if args.method != "fft":
        raise InputError(f"--method {args.method} is for the line indenter; 3D indenters use fft")
    outputs = plan_outputs(inputs=_inputs(args), csvs=("--profiles",), plots=("--plot",),
                           npzs=("--maps",),
                           **{"--profiles": args.profiles, "--plot": args.plot, "--maps": args.maps})
    r = solve(scene, model=args.model, method="fft", tol=args.tol, grid_points=args.grid_points,
              domain_length=args.domain_length)
    if not r.tolerance_met:
        from ..solvers.fft3d import default_tol

        tol = args.tol if args.tol is not None else default_tol(scene)
        print(f"warning: error estimate {r.error_estimate:.1e} > --tol {tol:g} at the fixed "
              f"--grid-points {args.grid_points} (JSON: \"tolerance_met\": false); raise "
              f"--grid-points or leave it automatic", file=sys.stderr)
    sensor = None
    if args.sensor:
        from ..instruments.sensor import sensor_maps

        sensor = sensor_maps(r, A_zz_mV_per_bar=args.a_zz, A_xz_mV_per_bar=args.a_xz)
    def maps(path):
        arrays = r.maps()
        if sensor:
            arrays.update({k: sensor[k] for k in ("S_zz_Pa", "S_xz_Pa", "S_yz_Pa")})
        with open(path, "wb") as fh:  # a handle: no ".npz" added
            np.savez(fh, **arrays)

    def columns():
        cols = r.profiles()
        if sensor:
            j = int(np.argmin(np.abs(r.y)))
            cols.update({k: sensor[k][:, j] for k in ("S_zz_Pa", "S_xz_Pa", "U_zz_mV", "U_xz_mV")})
        return cols

    def plot(path):
        from .plots import plot_maps

        plot_maps(r, path, sensor=sensor)

    write_outputs(outputs, {
        "--maps": staged(maps),
        "--profiles": csv_file(columns, lambda cols: {
            "written_by": "spectral-contact solve",
            "columns": {k: _PROFILE_NOTES.get(k, "") + " (the line y = 0)" for k in cols},
            "result": r.summary()}),
        "--plot": staged(plot),
    }, lambda: to_json(r.summary()) if args.json else _summary_text3d(r, sensor))
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
    if args.workers is not None or args.serial:
        # the studies whose points run through sweep.map_tasks say so in their usage line
        if "[--workers N | --serial]" not in (mod.__doc__ or ""):
            raise InputError(f"study: {args.name!r} takes no --workers / --serial (it measures "
                             f"times or runs its own loop)")
        if args.workers is not None and args.workers < 1:
            raise InputError(f"study: --workers must be >= 1; got {args.workers}")
        argv += ["--serial"] if args.serial else ["--workers", str(args.workers)]
    return int(mod.main(argv) or 0)


def _study_lines() -> str:
    """One line per study: its name and the first line of its docstring (read, not imported:
    the opening string literal only, not the whole file's syntax tree, which cost every command
    ~0.15 s of start-up)."""
    import importlib.util
    import re
    from pathlib import Path

    spec = importlib.util.find_spec("studies")
    if spec is None or not spec.submodule_search_locations:
        return "  (studies/ not found: run from the project's checkout)"
    lines = []
    for path in sorted(Path(next(iter(spec.submodule_search_locations))).glob("[a-z]*.py")):
        try:
            with open(path, encoding="utf-8") as fh:
                head = fh.read(4096)
        except (OSError, UnicodeDecodeError):
            continue
        m = re.match(r'\s*[rRuU]?("""|\'\'\')\s*(.*)', head)
        doc = m.group(2).splitlines()[0].split(m.group(1))[0].strip() if m and m.group(2) else ""
        lines.append(f"  {path.stem:<18} {doc}")
    return "\n".join(lines)


def build_parser() -> argparse.ArgumentParser:
    from .._version import __version__

    parser = _Parser(prog="spectral-contact",
                     description="A rigid indenter (line, sphere, finite cylinder, paraboloid) "
                                 "sliding on a bonded elastic film: pressure, "
                                 "base stresses, MEMS view.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    p = sub.add_parser("solve", help="solve one scene (default: the paper's)")
    add_scene_options(p, "solve")
    add_solve_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    p.add_argument("--profiles", metavar="FILE.csv", help="write the profiles (SI) as CSV")
    p.add_argument("--plot", metavar="FILE.png", help="plot pressure and base stresses (3D: maps)")
    p.add_argument("--maps", metavar="FILE.npz", default=None,
                   help="3D indenters: write the surface and base maps (SI, arrays [x, y])")
    p.add_argument("--sensor", action="store_true",
                   help="add the MEMS sensor view: peak S_zz, S_xz, U in the summary and JSON, "
                        "S and U columns in --profiles, a panel in --plot (3D: S maps in "
                        "--maps and --plot)")
    p.add_argument("--a-zz", type=float, default=A_ZZ_MV_PER_BAR,
                   help=f"A_zz [mV/bar] (default {A_ZZ_MV_PER_BAR:.2f})")
    p.add_argument("--a-xz", type=float, default=A_XZ_MV_PER_BAR,
                   help=f"A_xz [mV/bar] (default {A_XZ_MV_PER_BAR:.2f})")
    p.add_argument("--apparatus-zz", metavar="G.csv", default=None,
                   help="radial G_zz (columns r_m and G or G_per_m2, as 'calibrate --out' writes) "
                        "instead of the paper's Gaussian; needs --sensor")
    p.add_argument("--apparatus-xz", metavar="G.csv", default=None,
                   help="radial G_xz instead of the paper's; needs --sensor")
    p.set_defaults(func=_cmd_solve)
    p = sub.add_parser("study", help="run a study from studies/ (python -m studies.NAME)",
                       description="Run one study (python -m studies.NAME): it prints its table, "
                                   "writes CSV + PNG into --out, progress on stderr.\n\nstudies:\n"
                                   + _study_lines(),
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("name", metavar="NAME", help="one of the studies listed above")
    p.add_argument("--quick", action="store_true", help="small version (under a minute; what the tests run)")
    p.add_argument("--out", default=None, metavar="DIR", help="output folder (default out/NAME)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--workers", type=int, default=None, metavar="N",
                   help="studies that sweep: a dask LocalCluster of N worker processes (default: "
                        "the cores; with --quick: this process)")
    g.add_argument("--serial", action="store_true", help="studies that sweep: run in this process")
    p.set_defaults(func=_cmd_study)
    for register in _plugins():
        register(sub)
    return parser


def _closed_pipe() -> int:
    """stdout's reader has gone: silence the interpreter's final flush; status 141 (128 +
    SIGPIPE), as a program ended by the signal."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass
    return 141


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
    option = getattr(message, "option", None)  # a physics.scene.UnitsWarning: the flag as typed
    if option and text.startswith(f"warning: {option} "):
        text = text.replace(option, "--" + option.replace("_", "-"), 1)
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
        if sys.stdout is None:  # started with stdout closed (>&-): the result has nowhere to go
            raise InputError("standard output is closed (>&-): nothing would receive the "
                             "result; redirect it to a file or /dev/null instead")
        from .progress import show_progress

        # solver steps on stderr once a command passes 2 s, on a terminal only: a failing
        # command's stderr is its one error line, however loaded the machine (studies print
        # their own progress; calibrate its bootstrap i/n)
        quiet = args.command in ("study", "calibrate") or not _is_terminal(sys.stderr)
        with show_progress(after=math.inf if quiet else 2.0,
                           skip=("spectral_contact.solvers",) if command == "compare" else ()):
            status = args.func(args)
        for text in _WARNINGS:
            print(text, file=sys.stderr)
        sys.stdout.flush()  # a closed pipe shows here, where it is handled
        return status
    except SystemExit:  # --help, --version: flush now, so that a closed pipe is handled too
        try:
            sys.stdout.flush()
        except BrokenPipeError:
            _closed_pipe()
        raise
    except BrokenPipeError:  # the reader went away (`| head`): end quietly
        return _closed_pipe()
    except InputError as exc:
        print(f"error: {as_options(_first_line(_as_typed(exc, options)), options)}",
              file=sys.stderr)
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


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):
        return False


def _written() -> str:
    """What an interrupted command leaves: nothing, or outputs completed before the signal."""
    done = _files.COMMITTED
    if not done:
        return "no output written"
    return "outputs were complete before the signal and kept: " + ", ".join(map(str, done))


def _as_typed(exc: InputError, options) -> str:
    """The message with the options it names (``errors.named``) as the command's flags, where
    the command has that flag (else the Python name: a value the command computed)."""
    def name_of(name):
        flag = "--" + name.replace("_", "-")
        return flag if options is None or flag in options else name

    return exc.as_typed(name_of)


def _first_line(exc) -> str:
    return " ".join(str(exc).split())


if __name__ == "__main__":
    sys.exit(main())
