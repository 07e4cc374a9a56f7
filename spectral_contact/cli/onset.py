"""The ``onset`` subcommand: partial slip under a growing tangential load (issue 22).

    spectral-contact onset [scene options of solve] [--steps N] [--tol T] [--loading L]
        [--amplitude A] [--cycle] [--json] [--profiles FILE.csv] [--plot FILE.png] [--sensor]

The normal load first, then Q = mu P k/N, k = 1..N (``solvers.onset``).  Text summary: one line
per step; ``--json``: the record of ``OnsetResult.summary()``; ``--profiles``: one tidy table, a
row per step (0 = after the normal load) and grid node; ``--plot``: tractions and base stresses
at a few steps, the stick zone against Q/(mu P), Q against the tangential displacement.  Bad
input: one line, exit 2, nothing written; outputs whole or not at all (``cli.files``).
"""
from __future__ import annotations

import sys

from ..errors import InputError

__all__ = ["register"]

_NOTES = {
    "step": "load step: 0 after the normal load, k = 1..N at Q = mu P k/N",
    "Q_over_muP": "Q / (mu P) of the step",
    "x_m": "position [m] from the indenter apex, +x the direction of Q for mu > 0",
    "pressure_Pa": "contact pressure p = -sigma_zz(x, h) >= 0 [Pa]",
    "shear_Pa": "surface shear q = sigma_xz(x, h) [Pa], |q| <= |mu| p",
    "slip_m": "accumulated slip of the indenter over the surface since the node came into "
              "contact [m] (0 in stick from the start, off the contact)",
    "base_sigma_zz_Pa": "normal stress at the rigid base sigma_zz(x, 0) [Pa], < 0 in compression",
    "base_sigma_xz_Pa": "shear stress at the rigid base sigma_xz(x, 0) [Pa]",
    "S_zz_Pa": "MEMS view S_zz = -G_zz (*) sigma_zz(x, 0) [Pa], > 0 in compression",
    "S_xz_Pa": "MEMS view S_xz = G_xz (*) sigma_xz(x, 0) [Pa]",
    "S_yz_Pa": "MEMS view S_yz = G_xz (*) sigma_yz(x, y, 0) [Pa]",
}


def register(subparsers) -> None:
    """Add ``onset`` to the main parser's subcommands."""
    from ..solvers.onset import DEFAULT_TOL, LOADING_STEPS, LOADINGS, MAX_STEPS
    from .scene_options import add_scene_options

    p = subparsers.add_parser(
        "onset", help="partial slip: the tangential load raised from 0 to mu P (lines and 3D indenters)",
        description="The normal load first (with friction acting, --loading), then the "
                    "tangential load Q raised from 0 to mu P in --steps equal steps, "
                    "quasi-static, with the slip history kept (incremental Coulomb friction). "
                    "The last step is gross sliding: solve's steady state.")
    add_scene_options(p)
    p.add_argument("--steps", type=int, default=20,
                   help=f"N, tangential steps: Q/(mu P) = 1/N, ..., 1 (1 ... {MAX_STEPS}; "
                        "default 20)")
    p.add_argument("--loading", choices=LOADINGS, default="frictional",
                   help="frictional: the normal load applied with Coulomb friction acting "
                        "(default); frictionless: a lubricated approach (q = 0 at Q = 0)")
    p.add_argument("--loading-steps", type=int, default=LOADING_STEPS,
                   help=f"steps of the frictional normal loading (default {LOADING_STEPS})")
    p.add_argument("--amplitude", type=float, default=1.0,
                   help="largest Q/(mu P), in (0, 1] (default 1: up to gross sliding)")
    p.add_argument("--cycle", action="store_true",
                   help="then unload to -amplitude and reload to +amplitude (2 --steps each): "
                        "Mindlin's hysteresis loop")
    p.add_argument("--tol", type=float, default=None,
                   help=f"relative accuracy target of each step's a, centre, indentation, peak "
                        f"pressure and tangential displacement (default {DEFAULT_TOL:g})")
    p.add_argument("--grid-points", type=int, default=None, help="fix N instead of --tol")
    p.add_argument("--domain-length", type=float, default=None, help="fix the period L [m]")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    p.add_argument("--profiles", metavar="FILE.csv", help="write the tidy per-step profiles (SI)")
    p.add_argument("--plot", metavar="FILE.png", help="plot the loading")
    p.add_argument("--sensor", action="store_true",
                   help="add the MEMS view S_zz, S_xz (the paper's apparatus functions) to "
                        "--profiles and --plot (spheres: the 2D apparatus, as solve; the "
                        "y = 0 line in --profiles, S maps in --maps)")
    p.add_argument("--maps", metavar="FILE.npz", default=None,
                   help="3D indenters: every step's surface and base maps in one NPZ (SI, "
                        "arrays [step, x, y]; keys as solve --maps writes them, plus "
                        "shear_x_Pa, shear_y_Pa, slip_x_m, slip_y_m, stick, contact, step, "
                        "Q_over_muP)")
    p.set_defaults(func=_cmd_onset)


def _sensor(r) -> dict:
    """S_zz, S_xz [Pa] per step (rows) of the base stresses, through the paper's apparatus
    functions (periodic grid)."""
    import numpy as np

    from ..instruments.sensor import sensor_profiles

    sc = r.scene
    x_m = r.x * sc.length_unit
    zz, xz = [], []
    for szz, sxz in zip(r.base_sigma_zz, r.base_sigma_xz):
        v = sensor_profiles(x_m, szz * sc.stress_unit, sxz * sc.stress_unit, periodic=True)
        zz.append(v["S_zz_Pa"])
        xz.append(v["S_xz_Pa"])
    return {"S_zz_Pa": np.array(zz), "S_xz_Pa": np.array(xz)}


class _Step:
    """One step's maps in the form ``instruments.sensor.sensor_maps`` reads (a 3D result)."""

    def __init__(self, r, maps, k):
        self.scene, self.domain_length = r.scene, r.grid.lengths
        self._maps = {key: (v if key in ("x_m", "y_m") else v[k]) for key, v in maps.items()
                      if key.startswith(("x_", "y_", "base_"))}

    def maps(self):
        return self._maps


def _sensor3d(r, maps) -> dict:
    """S_zz, S_xz, S_yz [Pa] and U [mV] maps per step (a leading step axis) of a 3D onset,
    through the paper's 2D apparatus functions on the solver's periodic grid (as solve)."""
    import numpy as np

    from ..instruments.sensor import sensor_maps

    per = [sensor_maps(_Step(r, maps, k)) for k in range(len(r.states))]
    return {key: np.stack([v[key] for v in per]) for key in ("S_zz_Pa", "S_xz_Pa", "S_yz_Pa")}


def _text(r) -> str:
    s = r.summary()
    mm, um = 1e3, 1e6
    lines = [f"onset of sliding: P_L = {s['load_N_per_m']:g} N/m, mu = {s['mu']:g}, E = "
             f"{s['young_Pa'] / 1e6:g} MPa, R = {s['radius_m'] * mm:g} mm, h = "
             f"{s['thickness_m'] * mm:g} mm; {s['loading']} loading; N = {s['grid_points']} "
             f"points, error estimate {s['error_estimate']:.1e}",
             "  Q/(mu P)   Q [N/m]   stick zone [mm]        a [mm]   centre [mm]  "
             "d [um]    p_max [kPa]  delta [um]"]
    for st in [s["loaded"]] + s["steps"]:
        lines.append(
            f"  {st['Q_over_muP']:7.3f} {st['tangential_load_N_per_m']:9.3f}  "
            f"[{st['stick_x_min_m'] * mm:8.4f}, {st['stick_x_max_m'] * mm:8.4f}]  "
            f"{st['half_width_m'] * mm:8.4f}  {st['contact_center_m'] * mm:9.4f}  "
            f"{st['indentation_m'] * um:8.4f}  {st['max_pressure_Pa'] / 1e3:9.4f}  "
            f"{st['tangential_displacement_m'] * um:9.4f}")
    return "\n".join(lines)


def _text3d(r) -> str:
    s = r.summary()
    mm, um = 1e3, 1e6
    lines = [f"onset of sliding: {s['indenter']}, F = {s['force_N']:g} N, mu = {s['mu']:g}, "
             f"R = {s['radius_m'] * mm:g} mm, h = {s['thickness_m'] * mm:g} mm; {s['loading']} "
             f"loading; {s['grid_points'][0]} x {s['grid_points'][1]} points, error estimate "
             f"{s['error_estimate']:.1e}",
             "  Q/(mu P)   Q [N]    stick radius [mm]  contact radius [mm]  centre [mm]  "
             "d [um]   p_max [kPa]  delta [um]"]
    for st in [s["loaded"]] + s["steps"]:
        lines.append(
            f"  {st['Q_over_muP']:7.3f} {st['tangential_force_N']:8.4f}  "
            f"{st['stick_radius_m'] * mm:12.4f}  {st['contact_radius_m'] * mm:18.4f}  "
            f"{st['contact_center_m'] * mm:11.4f}  {st['indentation_m'] * um:7.3f}  "
            f"{st['max_pressure_Pa'] / 1e3:10.4f}  {st['tangential_displacement_m'] * um:9.4f}")
    return "\n".join(lines)


def _cmd_onset(args) -> int:
    from ..physics.scene import Scene
    from ..solvers.onset import MAX_STEPS, onset
    from .files import csv_file, plan_outputs, staged, to_json, write_outputs

    if not 1 <= args.steps <= MAX_STEPS:
        raise InputError(f"--steps must be an integer in [1, {MAX_STEPS}]; got {args.steps}")
    if not 1 <= args.loading_steps <= MAX_STEPS:
        raise InputError(f"--loading-steps must be an integer in [1, {MAX_STEPS}]; got "
                         f"{args.loading_steps}")
    from .scene_options import scene_args

    given = scene_args(args)  # the options the user gave, checked against the indenter
    indenter = given.pop("indenter", "line")
    if indenter not in ("line", "sphere", "paraboloid"):
        raise InputError(f"--indenter {indenter}: onset takes line, sphere or paraboloid "
                         f"(smooth indenters)")
    if indenter == "line" and args.maps is not None:
        raise InputError("--maps is for 3D indenters (--indenter sphere, paraboloid); lines "
                         "write their profiles with --profiles")
    law = given.get("friction_law", "amontons")
    if law != "amontons":
        raise InputError(f"--friction-law {law}: onset takes amontons only "
                         f"(Coulomb's |q| <= mu p)")
    for opt in ("friction_exponent", "friction_pref", "shear_strength", "shear_slope",
                "interface_pressure", "interface_length"):
        if opt in given:
            raise InputError(f"--{opt.replace('_', '-')}: onset takes Amontons friction on a "
                             f"rigid interface only")
    if given.get("interface_compliance") or given.get("interface_law", "linear") != "linear":
        raise InputError("--interface-compliance/--interface-law: onset takes a rigid interface "
                         "only")
    if indenter == "line":
        scene = Scene(**given)
    else:
        from ..physics.scene import Scene3D

        scene = Scene3D(indenter=indenter, **given)
    if scene.mu == 0:
        raise InputError("--mu must be != 0 for onset (the tangential load goes up to mu P)")
    outputs = plan_outputs(csvs=("--profiles",), plots=("--plot",), npzs=("--maps",),
                           **{"--profiles": args.profiles, "--plot": args.plot,
                              "--maps": args.maps})

    tty = sys.stderr is not None and sys.stderr.isatty()

    def progress(k, n, npts):  # on a terminal only, one line rewritten (as every command's)
        if tty and (k == n or k % max(1, n // 4) == 0):
            end = "\r\x1b[K" if k == n else ""
            size = npts if indenter == "line" else f"{npts}^2"
            sys.stderr.write(f"\r\x1b[Konset: step {k}/{n} on {size} points{end}")
            sys.stderr.flush()

    r = onset(scene, steps=args.steps, tol=args.tol, loading=args.loading,
              loading_steps=args.loading_steps, grid_points=args.grid_points,
              domain_length=args.domain_length, amplitude=args.amplitude, cycle=args.cycle,
              progress=progress)
    maps = r.maps() if indenter != "line" and (args.sensor or args.maps) else None
    view = None
    if args.sensor:
        view = _sensor(r) if indenter == "line" else _sensor3d(r, maps)

    def write_maps(path):
        import numpy as np

        arrays = dict(maps)
        arrays.update(view or {})
        with open(path, "wb") as fh:  # a handle: no ".npz" added
            np.savez(fh, **arrays)

    record = r.summary()
    write_outputs(outputs, {  # stdout with the files, or nothing
        "--profiles": csv_file(lambda: r.profiles(sensor=view), lambda cols: {
            "written_by": "spectral-contact onset",
            "columns": {k: _NOTES[k] for k in cols},
            "result": record}),
        "--plot": staged(lambda path: r.plot(sensor=view).savefig(path, dpi=120)),
        "--maps": staged(write_maps),
    }, lambda: (to_json(record) if args.json else
                (_text(r) if indenter == "line" else _text3d(r))))
    if not r.tolerance_met:  # after the outputs: a failed write prints its one error line only
        step = max(r.load_step_estimates)
        grid = max(e - s for e, s in zip(r.error_estimates, r.load_step_estimates))  # additive
        why = []
        if step > r.tol:
            why.append(f"the load steps' share {step:.1e}: raise --steps (and --loading-steps)")
        if args.grid_points is not None and (grid > r.tol or not why):
            why.append(f"the grid's share {grid:.1e} at the fixed --grid-points "
                       f"{args.grid_points}")
        if not why:  # not met with the grid chosen from --tol: the per-step estimates say where
            why.append("see the per-step error_estimate")
        print(f"warning: error estimate {max(r.error_estimates):.1e} > --tol {r.tol:g}, "
              f"{'; '.join(why)} (JSON: \"tolerance_met\": false)", file=sys.stderr)
    return 0
