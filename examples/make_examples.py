"""Make the SYNTHETIC example data of examples/ (not measurements: computed, with added noise).

    python -m examples.make_examples      (from the project folder; seeded: the same bytes)

* ``synthetic_sliding_profile.csv`` -- what the paper's MEMS sensor would read under the paper's
  sliding cylinder (P_L = 200 N/m, mu_d = 2, E = 2.2 MPa, R = 130 mm, h = 2 mm, nu = 0.5): the
  exact model's sensor view U_zz, U_xz [mV] (A_zz = 19.00, A_xz = 7.95 mV/bar), sensor 0.5 mm
  ahead of the apex, x from -16 to 16 mm in 0.1 mm steps, white noise of 0.5 % of each
  component's peak (seed 1).  ``spectral-contact compare examples/synthetic_sliding_profile.csv``
  recovers P_L, mu_d and the offset.
* ``synthetic_punch_scan.csv`` -- a rod-scan calibration: U_zz [mV] of the paper's Gaussian
  apparatus G_zz (A_zz = 19.00 mV/bar) over the base stress of a rigid flat punch (P = 0.1 N,
  radius 250 um, h = 2 mm; ``instruments.axisym.flat_punch_base_stresses``), r from 0 to 4 mm
  in 50 um steps, white noise of 0.5 % of the peak (seed 2).  ``spectral-contact calibrate
  --measured examples/synthetic_punch_scan.csv --punch-load 0.1`` recovers A_zz and G_zz.

Each file has a ``.meta.json`` beside it saying it is synthetic and how it was made.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
A_ZZ, A_XZ = 19.00, 7.95  # mV/bar (the paper's gains)
PA_PER_BAR = 1e5


def sliding_profile():
    from spectral_contact import solve
    from spectral_contact.instruments.sensor import sensor_view

    r = solve(load=200.0, mu=2.0, tol=1e-4)
    v = sensor_view(r)
    x = np.round(np.arange(-160, 161) * 1e-4, 10)
    offset = 0.5e-3
    rng = np.random.default_rng(1)
    cols = {"x_m": x}
    for c, A in (("zz", A_ZZ), ("xz", A_XZ)):
        U = np.interp(x - offset, r.x_m, v[f"S_{c}_Pa"]) * A / PA_PER_BAR
        cols[f"U_{c}_mV"] = U + 0.005 * np.abs(U).max() * rng.standard_normal(x.size)
    return cols, {"scene": {"load_N_per_m": 200.0, "mu": 2.0, "young_Pa": 2.2e6,
                            "radius_m": 0.130, "thickness_m": 0.002, "poisson": 0.5},
                  "model": "exact", "sensor_offset_m": offset, "A_zz_mV_per_bar": A_ZZ,
                  "A_xz_mV_per_bar": A_XZ, "noise": "0.5 % of each component's peak, seed 1"}


def punch_scan():
    from spectral_contact.instruments.apparatus import default_apparatus
    from spectral_contact.instruments.axisym import base_stresses_axisym, flat_punch_transform

    gzz, _ = default_apparatus()
    P, a, h, dr, r_max = 0.1, 250e-6, 2e-3, 50e-6, 4e-3
    # G (*) sigma: the punch's pressure transform times G's transform (all linear, axisymmetric)
    b = base_stresses_axisym(h, pressure_transform=lambda k: flat_punch_transform(k, P, a)
                             * gzz.transform(k), dx_m=dr, r_max_m=r_max)
    U = -b["sigma_zz_Pa"] * A_ZZ / PA_PER_BAR  # compression > 0
    U = U + 0.005 * np.abs(U).max() * np.random.default_rng(2).standard_normal(U.size)
    return {"r_m": b["r_m"], "U_zz_mV": U}, {
        "punch": {"load_N": P, "radius_m": a, "thickness_m": h}, "apparatus": repr(gzz),
        "A_zz_mV_per_bar": A_ZZ, "noise": "0.5 % of the peak, seed 2"}


def _write(name, cols, meta):
    path = HERE / name
    names = list(cols)
    rows = zip(*(cols[n] for n in names))
    path.write_text(",".join(names) + "\n" + "\n".join(",".join(f"{v:.10g}" for v in row)
                                                       for row in rows) + "\n")
    meta = {"SYNTHETIC": "computed by spectral_contact with added noise, not a measurement",
            "made_by": "python -m examples.make_examples", **meta}
    path.with_name(path.stem + ".meta.json").write_text(json.dumps(meta, indent=2) + "\n")
    print(f"wrote {path.relative_to(HERE.parent)}")


def main() -> int:
    _write("synthetic_sliding_profile.csv", *sliding_profile())
    _write("synthetic_punch_scan.csv", *punch_scan())
    return 0


if __name__ == "__main__":
    sys.exit(main())
