"""``spectral-contact invert FILE.npz``: base-stress maps (or the MEMS S maps) to the interface
tractions p, q_x, q_y with their uncertainty (``instruments.inverse_maps``).  ``cli.invert``
sends .npz files here; input problems raise InputError (one line, exit 2); every input is read
and checked before any file is written, and the outputs are written whole or not at all."""
from __future__ import annotations

from ..errors import InputError
from .files import plan_outputs, staged, to_json, write_outputs
from .mems import _apparatus

__all__ = ["cmd_invert_maps"]


def cmd_invert_maps(args) -> int:
    import numpy as np

    from ..instruments.inverse_maps import invert_maps, read_maps
    from ..physics.scene import check_poisson

    check_poisson(args.poisson)
    for opt, given in (("--positive", args.positive), ("--support", args.support is not None)):
        if given:
            raise InputError(f"{opt}: not available for maps ({args.record}); line records only")
    outputs = plan_outputs(inputs={"FILE": args.record, "--apparatus-zz": args.apparatus_zz,
                                   "--apparatus-xz": args.apparatus_xz},
                           plots=("--plot",), npzs=("--out",),
                           **{"--out": args.out, "--plot": args.plot})
    x, y, (zz, xz, yz), view = read_maps(args.record)
    apparatus = _apparatus(args)
    if view == "base" and apparatus is not None:
        opt = "--apparatus-zz" if args.apparatus_zz else "--apparatus-xz"
        raise InputError(f"{opt}: {args.record} holds base stresses (no apparatus); drop the "
                         f"option or give the S maps")
    inv = invert_maps(x, y, zz, xz, yz, thickness=args.thickness, poisson=args.poisson,
                      view=view, apparatus=apparatus, prior=args.prior)
    rec = inv.summary()
    rec["input"] = str(args.record)

    def write_npz(path):
        with open(path, "wb") as fh:  # a handle: no ".npz" appended
            np.savez(fh, **inv.maps())

    write_outputs(outputs, {"--out": staged(write_npz),
                            "--plot": staged(lambda path: inv.plot().savefig(path, dpi=120))},
                  lambda: to_json(rec) if args.json else _text(args, rec, view))
    return 0


def _text(args, rec, view) -> str:
    mm = 1e3
    reg = rec["regularisation"]
    lines = [
        f"{args.record}: {rec['points'][0]} x {rec['points'][1]} points ({view} view)",
        f"  F   = {rec['force_N']:.5g} +- {rec['force_sigma_N']:.2g} N",
        f"  Q_x = {rec['tangential_force_x_N']:.5g} +- {rec['tangential_force_x_sigma_N']:.2g} N, "
        f"Q_y = {rec['tangential_force_y_N']:.3g} +- {rec['tangential_force_y_sigma_N']:.2g} N, "
        f"Q_x/F = {rec['Q_over_P']:.4g} +- {rec['Q_over_P_sigma']:.2g}",
        f"  resolution {rec['resolution_length_m'] * mm:.3g} mm; prior "
        f"{reg['prior_choice']['chosen']} (by evidence: "
        + ", ".join(f"{k} {v:.1f}" for k, v in reg["prior_choice"]["log_evidence"].items())
        + f"), Matern nu = {reg['smoothness_nu']:g}, lengths p {reg['length_p_m'] * mm:.3g} mm, "
        f"q {reg['length_q_m'] * mm:.3g} mm",
        f"  noise sd zz {rec['noise_sd_zz_Pa']:.3g} Pa, xz {rec['noise_sd_xz_Pa']:.3g} Pa, "
        f"yz {rec['noise_sd_yz_Pa']:.3g} Pa (by evidence; log-evidence "
        f"{rec['log_evidence']:.2f})"]
    if "optimizer_step_sd" in reg:  # the contact prior's fit (instruments.inverse_maps_contact)
        state = ("converged" if reg["optimizer_converged"] else
                 "NOT converged: the answer may move with rounding or the start")
        lines.append(f"  contact prior's fit: {state} ({reg['optimizer_iterations']} iterations; "
                     f"step left {reg['optimizer_step_sd']:.1g} sd of its hyperparameters)")
    elif not reg.get("optimizer_converged", True):
        lines.append("  smooth prior's fit: NOT converged (its optimiser stopped early)")
    laws = rec["laws"]
    from ..instruments.inverse_laws import best_line, law_lines

    lines += law_lines(laws)
    lines.append(best_line(laws))
    return "\n".join(lines)
