"""``spectral-contact invert``: from a measured line record of base stresses (or the MEMS view
of them) to the interface tractions p(x), q(x) with their uncertainty, and the local friction
law (``instruments.inverse``).

``register(subparsers)`` adds the subcommand (``cli.main``); input problems raise InputError
(one line, exit 2); every input is read and checked before any file is written, and the outputs
are written whole or not at all, never over an input.
"""
from __future__ import annotations

import math

from ..errors import InputError
from ..units import A_XZ_MV_PER_BAR, A_ZZ_MV_PER_BAR
from .files import csv_file, plan_outputs, staged, to_json, write_outputs
from .mems import _apparatus, _positive, _scene_options

__all__ = ["register", "CSV_COLUMNS"]

CSV_COLUMNS = ("x_m", "pressure_Pa", "pressure_sd_Pa", "shear_Pa", "shear_sd_Pa", "mu_local",
               "mu_local_sd")


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "invert", help="from measured base stresses to the interface tractions p, q with bands",
        description="Infer the surface pressure p(x) and shear q(x) with posterior standard "
                    "deviations from a line record of base stresses (x_m,base_sigma_zz_Pa,"
                    "base_sigma_xz_Pa) or of the MEMS view (x_m,S_zz_Pa,S_xz_Pa or x_m,U_zz_mV,"
                    "U_xz_mV, through the apparatus functions). Gaussian-process prior and noise "
                    "chosen by the evidence; totals P, Q, Q/P with sigmas, mu_local = q/p where "
                    "p > 3 sd, contact interval, resolution length, and fits of Amontons, "
                    "q = tau0 + alpha p and a power law to the local (p, q) pairs (JSON 'laws').")
    p.add_argument("record", metavar="FILE", help="CSV line record (uniform x_m, >= 8 rows), or "
                                                  "NPZ maps (x_m, y_m, base_sigma_*_Pa or "
                                                  "S_*_Pa [x, y], as solve --maps writes them)")
    _scene_options(p, ("thickness", "poisson"),
                   {"thickness": "base stresses do not depend on E or R"})
    p.add_argument("--a-zz", type=_positive("--a-zz"), default=None,  # None: the paper's
                   help=f"A_zz [mV/bar] for U files only ({A_ZZ_MV_PER_BAR:.2f})")
    p.add_argument("--a-xz", type=_positive("--a-xz"), default=None,
                   help=f"A_xz [mV/bar] for U files only ({A_XZ_MV_PER_BAR:.2f})")
    p.add_argument("--apparatus-zz", metavar="G.csv", default=None,
                   help="radial G_zz (columns r_m, G or G_per_m2) instead of the paper's; "
                        "S/U files only")
    p.add_argument("--apparatus-xz", metavar="G.csv", default=None,
                   help="radial G_xz instead of the paper's; S/U files only")
    p.add_argument("--positive", action="store_true", help="constrain p >= 0")
    p.add_argument("--prior", choices=("auto", "contact", "envelope"), default="auto",
                   help="the prior: contact (shaped on a contact window, maps: an ellipse), envelope "
                        "(maps: the smooth stationary prior) or auto (default: fits both and "
                        "keeps the one of higher evidence; the choice is in the JSON's "
                        "regularisation.prior_choice)")
    p.add_argument("--support", type=float, nargs=2, metavar=("A_M", "B_M"), default=None,
                   help="known contact interval [m] (p = q = 0 outside)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--out", metavar="OUT.csv", help="write x_m, pressure_Pa, pressure_sd_Pa, "
                                                    "shear_Pa, shear_sd_Pa, mu_local, mu_local_sd"
                                                    " (maps: an NPZ of x_m, y_m, pressure_Pa, "
                                                    "shear_x_Pa, shear_y_Pa and each *_sd_Pa)")
    p.add_argument("--plot", metavar="FILE.png", help="tractions, mu_local, data fit, laws")
    p.set_defaults(func=_cmd_invert)


def _cmd_invert(args) -> int:
    import math

    if str(args.record).lower().endswith(".npz"):  # maps: instruments.inverse_maps
        if args.a_zz is not None or args.a_xz is not None:
            opt = "--a-zz" if args.a_zz is not None else "--a-xz"
            raise InputError(f"{opt}: the gains apply to line records with U_zz_mV,U_xz_mV "
                             f"columns only; {args.record} holds maps (no U_ columns)")
        from .invert_maps import cmd_invert_maps

        return cmd_invert_maps(args)
    from ..instruments.inverse import invert_line, read_record
    from ..physics.scene import check_poisson

    check_poisson(args.poisson)
    # the shared check (issue 24): no output, implicit .meta.json included, over an input
    # (resolved path or inode) or over another output
    outputs = plan_outputs(inputs={"FILE": args.record, "--apparatus-zz": args.apparatus_zz,
                                   "--apparatus-xz": args.apparatus_xz},
                           csvs=("--out",), plots=("--plot",),
                           **{"--out": args.out, "--plot": args.plot})
    if args.support is not None:
        a, b = args.support
        if not (math.isfinite(a) and math.isfinite(b) and b > a):
            raise InputError(f"--support: need A_M < B_M, finite [m]; got {a:g} {b:g}")
    x, zz, xz, view = read_record(args.record, args.a_zz, args.a_xz)
    apparatus = _apparatus(args)
    if view == "base" and apparatus is not None:
        opt = "--apparatus-zz" if args.apparatus_zz else "--apparatus-xz"
        raise InputError(f"{opt}: {args.record} holds base stresses (no apparatus); drop the "
                         f"option or give the S/U record")
    inv = invert_line(x, zz, xz, thickness=args.thickness, poisson=args.poisson, view=view,
                      apparatus=apparatus, positive=args.positive, support=args.support,
                      prior=args.prior)
    rec = inv.summary()
    rec["input"] = str(args.record)
    write_outputs(outputs, {  # stdout with the files, or nothing
        "--out": csv_file(inv.profiles, {
            "written_by": "spectral-contact invert",
            "columns": {"x_m": "traction node [m], the record's frame",
                        "pressure_Pa": "p = -sigma_zz(x, h), posterior mean [Pa]",
                        "pressure_sd_Pa": "posterior sd of p [Pa]",
                        "shear_Pa": "q = sigma_xz(x, h), posterior mean [Pa]",
                        "shear_sd_Pa": "posterior sd of q [Pa]",
                        "mu_local": "q/p where p > 3 sd(p), else empty (nan)",
                        "mu_local_sd": "first-order sd of q/p"},
            **rec}),
        "--plot": staged(lambda path: inv.plot().savefig(path, dpi=120)),
    }, lambda: _invert_text(args, rec, view))
    if not rec.get("contact_within_record", True):  # after the outputs, as onset's warning
        import sys

        ci = rec["contact_interval_m"]
        print(f"warning: the contact interval [{ci[0] * 1e3:.3g}, {ci[1] * 1e3:.3g}] mm reaches "
              f"beyond the record [{rec['record_m'][0] * 1e3:.3g}, {rec['record_m'][1] * 1e3:.3g}]"
              f" mm: P, Q and the edge there are the prior's extrapolation (JSON: "
              f"\"contact_within_record\": false)", file=sys.stderr)
    names = {"base": "base_sigma_zz_Pa < 0", "sensor": "S_zz_Pa > 0 (U_zz_mV > 0)"}
    if rec["load_N_per_m"] < 0 and float(zz.sum()) < 0:  # the record itself pulls
        import sys

        print(f"warning: P = {rec['load_N_per_m']:.4g} N/m < 0 and the record's normal stress "
              f"is tensile on the whole: is its sign right? ({names.get(view, view)} in "
              f"compression)", file=sys.stderr)
    return 0


def _sd(v, scale) -> str:
    """An sd for the text summary: '?' when it is not determined (NaN or None), never 'nan'."""
    return f"{v * scale:.2g}" if v is not None and math.isfinite(v) else "?"


def _invert_text(args, rec, view) -> str:
    """invert's summary: the JSON record, or the text."""
    if args.json:
        return to_json(rec)
    else:
        mm = 1e3
        ci, cs = rec["contact_interval_m"], rec["contact_interval_sigma_m"]
        laws = rec["laws"]
        lines = [
            f"{args.record}: {rec['points']} samples ({view} view), {rec['nodes']} traction nodes",
            f"  P   = {rec['load_N_per_m']:.5g} +- {rec['load_sigma_N_per_m']:.2g} N/m",
            f"  Q   = {rec['tangential_load_N_per_m']:.5g} +- "
            f"{rec['tangential_load_sigma_N_per_m']:.2g} N/m, Q/P = {rec['Q_over_P']:.4g} +- "
            f"{rec['Q_over_P_sigma']:.2g}",
            f"  contact [{ci[0] * mm:.3f} +- {_sd(cs[0], mm)}, {ci[1] * mm:.3f} +- "
            f"{_sd(cs[1], mm)}] mm; resolution {rec['resolution_length_m'] * mm:.3g} mm",
            f"  noise sd zz {rec['noise_sd_zz_Pa']:.3g} Pa, xz {rec['noise_sd_xz_Pa']:.3g} Pa "
            f"(by evidence; log-evidence {rec['log_evidence']:.2f})"]
        if not all(v is not None and math.isfinite(v) for v in cs):
            lines.append("  (?: the contact edge's sd is not determined: the window's Laplace step "
                         "was not taken or an edge is at its search bound, e.g. beyond the record;"
                         " JSON null)")
        from ..instruments.inverse_laws import best_line, law_lines

        lines += law_lines(laws)
        lines.append(best_line(laws))
        return "\n".join(lines)
