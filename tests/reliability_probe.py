"""Adversarial inputs for issues 11 and 24: run each through the command line and tally the outcomes.

    python tests/reliability_probe.py [--jobs 2]

Each case: argv, the accepted exit codes, and checks applied to every run: one stderr line on a
non-zero exit, no traceback, no NaN/Infinity in stdout, no file left behind on a non-zero exit,
no timeout (60 s), every input (the fixtures, linked into the case's folder) unchanged.  A case
may set up its folder (a spec that is the summary a sweep writes; a sweep whose profile is then
truncated, checked to be recomputed), run with stdout closed or full (/dev/full), or run Python
(``["py", CODE]``: the API).  Prints one line per failing case and the tallies.  Runs in a scratch folder.
``--src DIR`` runs another checkout (e.g. ``git archive de44ce0 | tar -x -C DIR``: "before").
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

S = "solve"
SRC = None  # --src: PYTHONPATH of the package under test
MEAS = "meas.csv"  # a small measured profile written by _fixtures
RAD = "rad.csv"
REC = "rec.csv"  # a line record of base stresses (invert)
EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "synthetic_sliding_profile.csv"

CASES = [
    # (argv, accepted exit codes, note)
    ([S, "--domain-length", "0.006"], {2}, "period too short"),
    ([S, "--domain-length", "0.02"], {2}, "period too short for tol 1e-4"),
    ([S, "--domain-length", "0.03", "--tol", "0.01", "--json"], {0}, "period ok at tol 1e-2"),
    ([S, "--grid-points", "64", "--json"], {0}, "fixed N, estimate > tol: flagged",
     '"tolerance_met": false'),
    ([S, "--mu", "1000", "--method", "abel"], {3}, "abel beyond validity"),
    ([S, "--mu", "96", "--method", "abel"], {3}, "abel beyond validity"),
    ([S, "--mu", "-1000", "--method", "abel"], {3}, "abel beyond validity"),
    ([S, "--load", "70.8872", "--mu", "100", "--method", "abel"], {3}, "abel beyond validity"),
    ([S, "--radius", "1e-308"], {2}, "underflow"),
    ([S, "--radius", "1e-308", "--json"], {2}, "underflow json"),
    ([S, "--load", "1e308"], {2}, "overflow"),
    ([S, "--mu", "1e308"], {2, 3}, "huge mu"),
    ([S, "--young", "1e-308"], {2}, "tiny E"),
    ([S, "--young", "1e-100"], {2}, "tiny E"),
    ([S, "--radius", "1e308"], {2}, "huge R"),
    ([S, "--thickness", "1e-308"], {2}, "tiny h"),
    ([S, "--thickness", "1e308"], {2}, "huge h"),
    ([S, "--tol", "1e-308"], {2}, "tiny tol"),
    ([S, "--domain-length", "1e308"], {2}, "huge period"),
    ([S, "--young", "0"], {2}, "zero E"),
    ([S, "--load", "-0"], {0}, "-0 load", "P_L = 0 N/m"),
    ([S, "--profiles", "p.png", "--plot", "p.png"], {2}, "same path"),
    ([S, "--profiles", "p.csv", "--plot", "/proc/x.png"], {2}, "plot fails after csv"),
    ([S, "--profiles", "nodir/p.csv"], {2}, "missing folder"),
    ([S, "--profiles", ""], {2}, "empty path"),
    ([S, "--load", "57", "--mu", "10", "--thickness", "0.0002", "--tol", "0.01"], {0}, "level list"),
    ([S, "--load", "57", "--mu", "10", "--thickness", "0.0002", "--tol", "0.01", "--model", "auto"],
     {0}, "level list auto"),
    ([S, "--load", "300855", "--mu", "30"], {0}, "auto domain wide contact"),
    ([S, "--load", "300855", "--mu", "30", "--tol", "1e-3"], {0, 3}, "wide contact, loose tol"),
    ([S, "--grid-points", "16777216"], {2}, "unbounded N"),
    ([S, "--grid-points", "64.5"], {2}, "fractional N"),
    (["study", "_common"], {2}, "private study"),
    (["study", "__init__"], {2}, "private study"),
    (["compare", "fifo.csv"], {2}, "FIFO"),
    (["compare", "bom.csv", "--tol", "1e-3", "--no-fit"], {0}, "BOM header"),
    (["compare", MEAS, "--young", "1e-308", "--no-fit"], {2}, "compare tiny E"),
    (["compare", MEAS, "--thickness", "1e308", "--no-fit"], {2}, "compare huge h"),
    (["compare", "big.csv", "--no-fit"], {2}, "compare huge cells"),
    (["compare", MEAS, "--no-fit", "--plot", "c.png", "--json"], {0}, "compare ok"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--seed", "-1"], {2}, "seed -1"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--n-boot", "100000000000"], {2},
     "n-boot unbounded"),
    (["calibrate", "--measured", RAD, "--punch-load", "1e308"], {2}, "calibrate huge load"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--thickness", "1e-308"], {0, 2},
     "calibrate tiny h (the h -> 0 limit: base stress = surface pressure)"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--out", "G.png", "--plot",
      "G.png"], {2}, "calibrate same path"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--out", "G.csv", "--plot",
      "/proc/x.png"], {2}, "calibrate plot fails after csv"),
    (["calibrate", "--measured", "fifo.csv", "--punch-load", "0.1"], {2}, "calibrate FIFO"),
    # --- more of the same classes ---
    ([S, "--load", "0", "--json"], {0}, "no load"),
    ([S, "--load", "nan"], {2}, "nan"), ([S, "--load", "inf"], {2}, "inf"),
    ([S, "--mu", "nan"], {2}, "nan mu"), ([S, "--mu", "1001"], {2}, "mu beyond 1e3"),
    ([S, "--mu", "-1000", "--tol", "1e-2"], {0, 3}, "mu -1e3"),
    ([S, "--tol", "0"], {2}, "tol 0"), ([S, "--tol", "0.1"], {2}, "tol 0.1"),
    ([S, "--tol", "-1"], {2}, "tol < 0"), ([S, "--tol", "1e-14"], {2, 3}, "tol at the floor"),
    ([S, "--grid-points", "0"], {2}, "N 0"), ([S, "--grid-points", "-64"], {2}, "N < 0"),
    ([S, "--grid-points", "65"], {2}, "odd N"), ([S, "--grid-points", "1e3"], {2}, "N as float"),
    ([S, "--domain-length", "0"], {2}, "L 0"), ([S, "--domain-length", "-1"], {2}, "L < 0"),
    ([S, "--domain-length", "nan"], {2}, "L nan"),
    ([S, "--domain-length", "0.03"], {2}, "L below the minimum at tol 1e-4"),
    ([S, "--domain-length", "0.04", "--json"], {0}, "L above the minimum"),
    ([S, "--method", "abel", "--domain-length", "0.05"], {2}, "abel with L"),
    ([S, "--method", "abel", "--grid-points", "5"], {2}, "abel nodes"),
    ([S, "--method", "abel", "--grid-points", "3000"], {2}, "abel nodes"),
    ([S, "--model", "hertz", "--load", "1e-12", "--json"], {0}, "hertz tiny load"),
    ([S, "--model", "auto", "--mu", "1000", "--tol", "1e-2"], {0, 3}, "auto huge mu"),
    ([S, "--mu", "30", "--load", "300855", "--tol", "1e-3", "--json"], {0, 3}, "strong friction"),
    ([S, "--mu", "100", "--load", "300855", "--tol", "1e-3"], {0, 3}, "stronger friction"),
    ([S, "--plot", "x.txt"], {2}, "plot format"), ([S, "--plot", "nodir/x.png"], {2}, "plot dir"),
    ([S, "--profiles", "/proc/x.csv"], {2}, "unwritable dir"), ([S, "--profiles", "."], {2}, "dir"),
    ([S, "--json", "--sensor", "--profiles", "s.csv"], {0}, "sensor"),
    ([S, "--sensor", "--a-zz", "nan", "--profiles", "s.csv"], {2}, "sensor gain nan"),
    ([S, "--sensor", "--a-zz", "0", "--profiles", "s.csv"], {2}, "sensor gain 0"),
    ([S, "--model", "foo"], {2}, "model"), ([S, "--bogus"], {2}, "option"), (["nosuch"], {2}, "cmd"),
    (["study", "nosuch"], {2}, "study"), (["study", ""], {2}, "study ''"),
    (["study", "../tests"], {2}, "study path"),
    (["compare", "missing.csv"], {2}, "missing"), (["compare", "empty.csv"], {2}, "empty"),
    (["compare", "header.csv"], {2}, "header only"), (["compare", "nonuni.csv"], {2}, "non-uniform"),
    (["compare", "."], {2}, "directory"), (["compare", MEAS, "--tol", "0.5"], {2}, "tol"),
    (["compare", MEAS, "--a-zz", "0"], {2}, "gain"),
    (["compare", MEAS, "--apparatus-zz", "fifo.csv"], {2}, "apparatus FIFO"),
    (["compare", MEAS, "--plot", "c.csv"], {2}, "plot format"),
    (["compare", "u.csv", "--no-fit", "--json"], {0}, "U file"),
    (["calibrate", "--measured", "missing.csv", "--punch-load", "0.1"], {2}, "missing"),
    (["calibrate", "--measured", RAD, "--computed", "missing.csv"], {2}, "missing computed"),
    (["calibrate", "--measured", RAD], {2}, "no source"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--punch-radius", "0"], {2}, "radius"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--method", "foo"], {2}, "method"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--component", "yy"], {2}, "comp"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--noise-sd", "-1"], {2}, "sd"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--n-boot", "0", "--json"], {0}, "0"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--out", "."], {2}, "out dir"),
    (["calibrate", "--measured", "rad8.csv", "--punch-load", "0.1"], {2}, "short profile"),
    (["calibrate", "--measured", "radbig.csv", "--punch-load", "0.1"], {2}, "cells of 1e300"),
    (["calibrate", "--measured", RAD, "--computed", "radbig.csv"], {2}, "computed 1e300"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--thickness", "1e308"], {2}, "h"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--thickness", "0.02"], {2},
     "plane grid of 19 GB"),
    (["calibrate", "--measured", RAD, "--punch-load", "1e-308"], {2}, "tiny load"),
    (["calibrate", "--measured", RAD, "--punch-load", "0.1", "--punch-radius", "1e300"], {2},
     "punch wider than the scan"),
    (["compare", "mtiny.csv", "--no-fit"], {2}, "x in steps of 1e-303 m"),
    (["compare", MEAS, "--radius", "1e-300", "--no-fit"], {2}, "compare tiny R"),
    (["compare", MEAS, "--tol", "1e-308", "--no-fit"], {2}, "compare tiny tol"),
    (["compare", MEAS, "--apparatus-zz", "missing.csv"], {2}, "apparatus missing"),
    # --- issue 24: outputs naming inputs, metadata collisions, stdout, subnormals, laws, sweeps ---
    ([S, "--sensor", "--apparatus-zz", "G.csv", "--profiles", "G.csv"], {2}, "output over input"),
    ([S, "--sensor", "--apparatus-xz", "G.csv", "--plot", "G.png", "--profiles", "./G.csv"], {2},
     "output over input (./)"),
    ([S, "--sensor", "--apparatus-zz", "hl.csv", "--profiles", "G.csv"], {2}, "hard link"),
    (["calibrate", "--measured", RAD, "--punch-load", "1", "--out", RAD], {2}, "--out over input"),
    (["calibrate", "--measured", RAD, "--punch-load", "1", "--plot", RAD], {2}, "plot over input"),
    (["calibrate", "--measured", "radm.meta.json", "--punch-load", "1", "--out", "radm"], {2},
     "implicit metadata over the input"),
    (["compare", MEAS, "--plot", MEAS], {2}, "compare plot over measured"),
    (["compare", MEAS, "--apparatus-zz", "G.csv", "--plot", "G.csv"], {2}, "plot over apparatus"),
    ([S, "--indenter", "sphere", "--profiles", "p.csv", "--maps", "p.meta.json"], {2},
     "maps over implicit metadata"),
    ([S, "--tol", "1e-3", "--profiles", "d.csv", "--plot", "d.png"], {2},
     "metadata path is a directory"),
    ([S, "--tol", "1e-3", "--json", "--profiles", "p.csv"], {2}, "full stdout", None,
     {"stdout": "full"}),
    ([S, "--tol", "1e-3", "--json", "--profiles", "p.csv"], {2}, "closed stdout", None,
     {"stdout": "closed"}),
    ([S, "--tol", "1e-3", "--json"], {2}, "closed stdout, no file", None, {"stdout": "closed"}),
    (["calibrate", "--measured", RAD, "--punch-load", "0.01", "--n-boot", "0", "--out", "g.csv"],
     {2}, "calibrate full stdout", None, {"stdout": "full"}),
    ([S, "--load", "4.9e-324"], {2}, "subnormal load"),
    ([S, "--load", "4.9e-324", "--json"], {2}, "subnormal load json"),
    ([S, "--load", "2e-310", "--model", "hertz", "--json"], {0}, "subnormal load hertz (closed form)"),
    ([S, "--friction-law", "power", "--friction-pref", "4.9e-324", "--tol", "1e-2"], {2},
     "subnormal p_ref"),
    ([S, "--friction-law", "power", "--friction-pref", "1e300", "--tol", "1e-2"], {2}, "huge p_ref"),
    ([S, "--friction-law", "linear", "--shear-strength", "1e300", "--shear-slope", "1"], {2},
     "huge tau_0"),
    ([S, "--indenter", "cylinder", "--length", "4.9e-324"], {2}, "subnormal length"),
    ([S, "--indenter", "paraboloid", "--radius-x", "4.9e-324"], {2}, "subnormal radius_x"),
    ([S, "--indenter", "sphere", "--force", "4.9e-324"], {2}, "subnormal force"),
    ([S, "--friction-law", "linear"], {2}, "law without its parameters"),
    ([S, "--friction-law", "linear", "--shear-slope", "1", "--tol", "1e-2"], {0},
     "linear law: its parameters in the header", "alpha = 1"),
    (["compare", "mm.csv", "--json", "--tol", "1e-3"], {0}, "x in millimetres: fits failed",
     '"best_model": null'),
    (["sweep", "--workers", "1000", "--load", "100", "--out", "o"], {2}, "workers unbounded"),
    (["sweep", "--load", "1:1000:1", "--mu", "1:1000:1", "--young", "1e6:1e7:1e6", "--out", "o",
      "--serial"], {2}, "product uncapped"),
    (["sweep", "--load", "100", "--out", "", "--serial"], {2}, "--out ''"),
    (["sweep", "--spec", "spec.toml", "--out", "."], {2}, "spec among the outputs (--out .)",
     None, {"setup": "summary"}),
    (["sweep", "--load", "100", "--out", "o", "--scheduler", "{HTTP}", "--scheduler-timeout", "2"],
     {2}, "scheduler is an HTTP server"),
    (["sweep", "--load", "100", "--out", "o", "--scheduler", "{HUGE}", "--scheduler-timeout", "2"],
     {2}, "bytes like a huge frame"),
    (["sweep", "--load", "100", "--out", "o", "--scheduler", "tcp://127.0.0.1:"], {2},
     "scheduler without a port"),
    (["sweep", "--load", "100,200", "--tol", "1e-2", "--out", "o", "--serial", "--profiles"], {0},
     "resume after a truncated profile", None, {"setup": "resume"}),
    (["py", "import numpy as np, spectral_contact as sc\ntry:\n    sc.solve(indenter='function', "
      "height=lambda x, y: np.full(np.broadcast(x, y).shape, 'a'), force=0.5, tol=1e-2)\n"
      "except sc.InputError:\n    print('InputError')"], {0}, "API: height returns text",
     "InputError"),
    (["py", "import numpy as np, spectral_contact as sc\ntry:\n    sc.solve(indenter='function', "
      "height=lambda x, y: np.where(x > 0, np.nan, x * x + y * y), force=0.5, tol=1e-2)\n"
      "except sc.InputError:\n    print('InputError')"], {0}, "API: height returns NaN",
     "InputError"),
    (["py", "import spectral_contact as sc\ntry:\n    sc.sensor('x')\n"
      "except sc.InputError:\n    print('InputError')"], {0}, "API: sensor('x')", "InputError"),
    # --- issue 24, second pass: the newer commands (invert, onset, the viscoelastic film) ---
    # invert: the three line views, bad files, values and spans outside its range
    (["invert", REC, "--json", "--out", "t.csv", "--plot", "t.png"], {0}, "invert base view"),
    (["py", "import spectral_contact as sc\nfrom pathlib import Path\n"
      f"s = sc.invert({str(EXAMPLE)!r}).summary()\n"
      "print('recovered' if abs(s['load_N_per_m'] - 200) < 3 * s['load_sigma_N_per_m'] + 2 "
      "else s['load_N_per_m'])"], {0}, "invert the example U profile: P_L = 200 N/m",
     "recovered"),
    (["py", "import spectral_contact as sc\n"
      "s = sc.invert(sc.solve(tol=1e-3)).summary()\n"
      "print('recovered' if abs(s['load_N_per_m'] - 200) < 3 * s['load_sigma_N_per_m'] + 2 "
      "else s['load_N_per_m'])"], {0}, "invert the paper's scene (noise-free base stresses)",
     "recovered"),
    (["invert", MEAS, "--json"], {0}, "invert S view"),
    (["invert", "u.csv"], {0}, "invert U view", "sensor view"),
    (["invert", "rec_nan.csv"], {2}, "invert NaN cell"),
    (["invert", "rec_one.csv"], {2}, "invert one row"),
    (["invert", "rec_rev.csv"], {2}, "invert unsorted x"),
    (["invert", "rec_mixed.csv"], {2}, "invert mixed views"),
    (["invert", "rec_huge.csv"], {2}, "invert huge values"),
    (["invert", "rec_sub.csv"], {2}, "invert subnormal values"),
    (["invert", "rec_mm.csv"], {2}, "invert x in millimetres"),
    (["invert", "mtiny.csv"], {2}, "invert subnormal x span"),
    (["invert", "empty.csv"], {2}, "invert empty file"),
    (["invert", "header.csv"], {2}, "invert header only"),
    (["invert", "fifo.csv"], {2}, "invert FIFO"),
    (["invert", "nonuni.csv"], {2}, "invert non-uniform x"),
    (["invert", REC, "--thickness", "5e-324"], {2}, "invert subnormal thickness"),
    (["invert", REC, "--thickness", "1e308"], {2}, "invert huge thickness"),
    (["invert", REC, "--support", "0.5", "1"], {2}, "invert support outside the record"),
    (["invert", REC, "--support", "nan", "1"], {2}, "invert NaN support"),
    (["invert", REC, "--apparatus-zz", "G.csv"], {2}, "invert apparatus on base stresses"),
    (["invert", REC, "--load", "100"], {2}, "invert takes no --load"),
    (["invert", REC, "--out", REC], {2}, "invert output over its input"),
    (["invert", REC, "--out", "hl_rec.csv"], {2}, "invert output a hard link to its input"),
    (["invert", REC, "--out", "t.csv", "--plot", "t.meta.json"], {2}, "invert plot over metadata"),
    (["invert", REC, "--json", "--out", "t.csv"], {2}, "invert closed stdout", None,
     {"stdout": "closed"}),
    (["invert", REC, "--out", "t.csv"], {2}, "invert full stdout", None, {"stdout": "full"}),
    # onset
    (["onset", "--steps", "2", "--json", "--profiles", "o.csv", "--plot", "o.png"], {0}, "onset"),
    (["onset", "--mu", "1e-300", "--steps", "2"], {2}, "onset vanishing mu"),
    (["onset", "--indenter", "sphere", "--mu", "-5e-324"], {2}, "onset subnormal mu, sphere"),
    (["onset", "--mu", "0.03", "--steps", "4"], {0}, "onset small mu, frictional loading"),
    (["onset", "--steps", "0"], {2}, "onset no step"),
    (["onset", "--steps", "2.5"], {2}, "onset fractional steps"),
    (["onset", "--amplitude", "nan"], {2}, "onset NaN amplitude"),
    (["onset", "--indenter", "cylinder"], {2}, "onset finite cylinder"),
    (["onset", "--speed", "0.1"], {2}, "onset takes no --speed"),
    (["onset", "--maps", "m.npz"], {2}, "onset takes no --maps"),
    (["onset", "--model", "goodman"], {2}, "onset takes no --model"),
    (["onset", "--profiles", "o.csv", "--plot", "o.meta.json"], {2}, "onset plot over metadata"),
    (["onset", "--steps", "2", "--json", "--profiles", "o.csv"], {2}, "onset closed stdout", None,
     {"stdout": "closed"}),
    (["onset", "--steps", "2", "--profiles", "o.csv"], {2}, "onset full stdout", None,
     {"stdout": "full"}),
    # the viscoelastic film
    ([S, "--speed", "0.05", "--prony", "2.2e6,0.01", "--tol", "1e-2", "--json"], {0}, "visco"),
    ([S, "--speed", "0.05", "--prony", "5e-324,0.01"], {2}, "visco subnormal E_i"),
    ([S, "--speed", "0.05", "--prony", "1e308,0.01"], {2}, "visco huge E_i"),
    ([S, "--speed", "0.05", "--prony", "2.2e6,5e-324"], {2}, "visco subnormal tau"),
    ([S, "--speed", "0.05", "--prony", "2.2e6,1e308"], {2}, "visco huge tau"),
    ([S, "--speed", "1e308", "--prony", "2.2e6,0.01"], {2}, "visco huge speed"),
    ([S, "--speed", "0.05", "--prony", "2.2e6,0.01,1"], {2}, "visco odd prony"),
    ([S, "--speed", "0.05", "--prony", "nan,0.01"], {2}, "visco NaN prony"),
    ([S, "--prony", "2.2e6,0.01"], {2}, "visco prony without speed"),
    ([S, "--speed", "0.05"], {2}, "visco speed without prony"),
    ([S, "--speed", "-0.05", "--prony", "2.2e6,0.01"], {2}, "visco speed against mu"),
    ([S, "--speed", "0.05", "--prony", "2.2e6,0.01", "--method", "abel"], {2}, "visco abel"),
    ([S, "--speed", "0.05", "--prony", "2.2e6,0.01", "--poisson", "0.3"], {2}, "visco nu < 1/2"),
    ([S, "--speed", "0.05", "--prony", "2.2e6,0.01", "--tol", "1e-2", "--profiles", "p.csv"],
     {2}, "visco closed stdout", None, {"stdout": "closed"}),
    # reliab pass (this session): NPZ names, maps' ranges, a record ending inside the contact
    (["invert", "m.npz", "--out", "t.csv"], {2}, "invert maps: --out not .npz"),
    ([S, "--indenter", "sphere", "--maps", "m.csv"], {2}, "solve --maps not .npz"),
    (["onset", "--indenter", "sphere", "--maps", "m.txt"], {2}, "onset --maps not .npz"),
    (["invert", "m_huge.npz"], {2}, "invert maps huge values"),
    (["invert", "m_sub.npz"], {2}, "invert maps subnormal values"),
    (["invert", "m_mm.npz"], {2}, "invert maps axes in millimetres"),
    (["invert", "m_nan.npz"], {2}, "invert maps NaN cell"),
    (["invert", "m_mixed.npz"], {2}, "invert maps mixed views"),
    (["invert", "m_text.npz"], {2}, "invert maps not an NPZ"),
    (["invert", "m.npz", "--positive"], {2}, "invert maps --positive"),
    (["invert", "rec_trail.csv", "--json", "--prior", "contact"], {0},
     "invert a record ending inside the contact: flagged", '"contact_within_record": false'),
    # negative numbers in any notation are values (argparse < 3.13 took -1e-3 for an option)
    ([S, "--mu", "-1e-3", "--tol", "1e-2"], {0}, "negative scientific mu", "mu_d = -0.001"),
    ([S, "--mu", "-1e4"], {2}, "negative scientific mu out of range"),
    (["compare", MEAS, "--poisson", "-1e-3", "--no-fit"], {2}, "negative scientific poisson"),
]


def _fixtures(d: Path):
    import numpy as np

    from spectral_contact import solve
    from spectral_contact.instruments.sensor import sensor_view

    r = solve(tol=1e-3)
    s = sensor_view(r)
    sel = np.abs(r.x_m) < 0.01
    x, zz, xz = r.x_m[sel][::8], s["S_zz_Pa"][sel][::8], s["S_xz_Pa"][sel][::8]
    rows = "\n".join(f"{a:.17g},{b:.17g},{c:.17g}" for a, b, c in zip(x, zz, xz))
    (d / MEAS).write_text("x_m,S_zz_Pa,S_xz_Pa\n" + rows + "\n")
    (d / "bom.csv").write_text("\ufeffx_m,S_zz_Pa,S_xz_Pa\n" + rows + "\n", encoding="utf-8")
    big = "\n".join(f"{a:.17g},{b * 1e300:.17g},{c * 1e300:.17g}" for a, b, c in zip(x, zz, xz))
    (d / "big.csv").write_text("x_m,S_zz_Pa,S_xz_Pa\n" + big + "\n")
    rr = np.arange(40) * 50e-6
    U = 5.0 * np.exp(-0.5 * (rr / 0.6e-3) ** 2)
    (d / RAD).write_text("r_m,U_zz_mV\n" + "\n".join(f"{a:.17g},{b:.17g}" for a, b in zip(rr, U)) + "\n")
    os.mkfifo(d / "fifo.csv")
    (d / "empty.csv").write_text("")
    (d / "mtiny.csv").write_text("x_m,S_zz_Pa,S_xz_Pa\n" + "\n".join(
        f"{a * 1e-300:.17g},{b:.17g},{c:.17g}" for a, b, c in zip(x, zz, xz)) + "\n")
    (d / "header.csv").write_text("x_m,S_zz_Pa,S_xz_Pa\n")
    xs = np.r_[np.arange(10) * 1e-3, 0.0105]
    (d / "nonuni.csv").write_text("x_m,S_zz_Pa,S_xz_Pa\n" + "\n".join(f"{a:.6g},1,1" for a in xs))
    (d / "u.csv").write_text("x_m,U_zz_mV,U_xz_mV\n" + "\n".join(
        f"{a:.17g},{b * 19e-5:.17g},{c * 7.95e-5:.17g}" for a, b, c in zip(x, zz, xz)) + "\n")
    (d / "radbig.csv").write_text("r_m,U_zz_mV,S_zz_Pa\n" + "\n".join(
        f"{a:.17g},{b * 1e300:.17g},{b * 1e300:.17g}" for a, b in zip(rr, U)) + "\n")
    r8 = rr[:8]
    (d / "rad8.csv").write_text("r_m,U_zz_mV\n" + "\n".join(f"{a:.17g},1" for a in r8) + "\n")
    (d / "radm.meta.json").write_bytes((d / RAD).read_bytes())  # a radial profile, odd name
    (d / "G.csv").write_text("r_m,G_per_m2\n0,1e6\n1e-4,9e5\n2e-4,5e5\n3e-4,1e5\n4e-4,0\n")
    os.link(d / "G.csv", d / "hl.csv")
    (d / "d.meta.json").mkdir()
    base = -r.base_sigma_zz_Pa[np.abs(r.x_m) < 0.01][::8], r.base_sigma_xz_Pa[np.abs(r.x_m) < 0.01][::8]

    def rec(name, xs, zz, xz, cols=("x_m", "base_sigma_zz_Pa", "base_sigma_xz_Pa")):
        (d / name).write_text(",".join(cols) + "\n" + "\n".join(
            f"{a:.17g},{-b:.17g},{c:.17g}" for a, b, c in zip(xs, zz, xz)) + "\n")

    rec(REC, x, *base)
    os.link(d / REC, d / "hl_rec.csv")
    rec("rec_one.csv", x[:1], base[0][:1], base[1][:1])
    rec("rec_rev.csv", x[::-1], base[0][::-1], base[1][::-1])
    rec("rec_huge.csv", x, base[0] * 1e300, base[1] * 1e300)
    rec("rec_sub.csv", x, base[0] * 1e-310, base[1] * 1e-310)
    rec("rec_mm.csv", x * 1e3, *base)
    rec("rec_mixed.csv", x, *base, cols=("x_m", "base_sigma_zz_Pa", "S_xz_Pa"))
    nan = base[0].copy()
    nan[5] = np.nan
    rec("rec_nan.csv", x, nan, base[1])
    tr = (r.x_m > -0.012) & (r.x_m < 0.0)
    rec("rec_trail.csv", r.x_m[tr][::4], -r.base_sigma_zz_Pa[tr][::4], r.base_sigma_xz_Pa[tr][::4])
    n = 12
    xm, zm = np.arange(n) * 1e-3, np.zeros((n, n))
    one = zm.copy()
    one[6, 6] = 1e3
    nanm = one.copy()
    nanm[3, 3] = np.nan
    for name, kw in (("m.npz", {"base_sigma_zz_Pa": one}), ("m_huge.npz", {"base_sigma_zz_Pa": one * 1e300}),
                     ("m_sub.npz", {"base_sigma_zz_Pa": one * 1e-313}),
                     ("m_nan.npz", {"base_sigma_zz_Pa": nanm}),
                     ("m_mixed.npz", {"base_sigma_zz_Pa": one, "S_zz_Pa": one, "S_xz_Pa": zm,
                                      "S_yz_Pa": zm})):
        np.savez(d / name, **{"x_m": xm, "y_m": xm, "base_sigma_xz_Pa": zm,
                              "base_sigma_yz_Pa": zm, **kw})
    np.savez(d / "m_mm.npz", x_m=xm * 1e3, y_m=xm * 1e3, base_sigma_zz_Pa=one,
             base_sigma_xz_Pa=zm, base_sigma_yz_Pa=zm)
    (d / "m_text.npz").write_text("x_m,a\n1,2\n")
    sel = np.abs(r.x_m) < 0.016
    (d / "mm.csv").write_text("x_m,S_zz_Pa,S_xz_Pa\n" + "\n".join(
        f"{a * 1e3:.17g},{b:.17g},{c:.17g}" for a, b, c in
        zip(r.x_m[sel][::8], s["S_zz_Pa"][sel][::8], s["S_xz_Pa"][sel][::8])) + "\n")


_SERVERS = {}


def _servers():
    """{HTTP}: an HTTP server; {HUGE}: a server answering 64 bytes of 0xff (127.0.0.1 only)."""
    import http.server
    import socket
    import threading

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *a):
            pass

    web = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Quiet)
    threading.Thread(target=web.serve_forever, daemon=True).start()
    raw = socket.socket()
    raw.bind(("127.0.0.1", 0))
    raw.listen(16)

    def serve():
        while True:
            c, _ = raw.accept()
            try:
                c.sendall(b"\xff" * 64)
            finally:
                c.close()

    threading.Thread(target=serve, daemon=True).start()
    _SERVERS.update({"{HTTP}": f"tcp://127.0.0.1:{web.server_address[1]}",
                     "{HUGE}": f"tcp://127.0.0.1:{raw.getsockname()[1]}"})


def _digests(d: Path) -> dict:
    """What each entry of a case folder is: (is a link, sha256 of what it leads to)."""
    import hashlib

    out = {}
    for n in os.listdir(d):
        p = d / n
        h = hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else None
        out[n] = (p.is_symlink(), h)
    return out


def _setup(kind, d: Path, env, argv):
    """Extra preparation of a case (in its folder); returns a check run after the case."""
    if kind == "summary":
        (d / "spec.toml").write_text("load = 100\n")
        os.link(d / "spec.toml", d / "summary.csv")  # the spec is the summary the sweep writes
        return None
    if kind == "resume":
        subprocess.run([sys.executable, "-m", "spectral_contact.cli.main", *argv], cwd=d,
                       capture_output=True, timeout=120, env=env)
        prof = sorted((d / "o" / "profiles").glob("*.csv"))
        whole = prof[0].read_bytes()
        prof[0].write_bytes(whole[: len(whole) // 2])

        def check():
            return [] if prof[0].read_bytes() == whole else ["truncated profile kept on resume"]
        return check
    raise ValueError(kind)


def _run(case, root: Path):
    argv, ok_codes, note = case[:3]
    opts = case[4] if len(case) > 4 else {}
    argv = [_SERVERS.get(a, a) for a in argv]
    d = Path(tempfile.mkdtemp(dir=root))
    for f in root.glob("fix/*"):
        os.symlink(f, d / f.name)
    env = dict(os.environ, **({"PYTHONPATH": SRC} if SRC else {}))
    after_check = _setup(opts["setup"], d, env, argv) if "setup" in opts else None
    before = set(os.listdir(d))
    inputs = _digests(d)
    cmd = ([sys.executable, "-c", argv[1]] if argv[0] == "py" else
           [sys.executable, "-m", "spectral_contact.cli.main", *argv])
    kw = {}
    if opts.get("stdout") == "closed":
        kw = {"stdout": None, "stderr": subprocess.PIPE, "preexec_fn": lambda: os.close(1)}
    elif opts.get("stdout") == "full":
        kw = {"stdout": open("/dev/full", "w"), "stderr": subprocess.PIPE}
    else:
        kw = {"capture_output": True}
    try:
        p = subprocess.run(cmd, cwd=d, text=True, timeout=60, env=env, **kw)
    except subprocess.TimeoutExpired:
        return case, ["timeout (60 s)"], None
    if p.stdout is None:
        p.stdout = ""
    problems = []
    changed = [n for n, v in inputs.items() if _digests(d).get(n) != v and n not in ("o",)]
    if changed:
        problems.append(f"inputs replaced or changed: {sorted(changed)}")
    if after_check is not None:
        problems += after_check()
    err = p.stderr.strip().splitlines()
    if p.returncode not in ok_codes:
        problems.append(f"exit {p.returncode} (want {sorted(ok_codes)})")
    if "Traceback" in p.stderr:
        problems.append("traceback")
    if p.returncode != 0 and len(err) != 1:
        problems.append(f"{len(err)} stderr lines")
    if any(w in p.stdout for w in ("NaN", "Infinity", " nan", " inf")):
        problems.append("NaN/inf in output")
    if len(case) > 3 and case[3] and p.returncode == 0 and case[3] not in p.stdout:
        problems.append(f"stdout lacks {case[3]!r}")
    left = set(os.listdir(d)) - before
    if p.returncode != 0 and left:
        problems.append(f"left {sorted(left)}")
    if "--json" in argv and p.returncode == 0:
        try:
            json.loads(p.stdout)
        except ValueError:
            problems.append("invalid JSON")
    return case, problems, (p.returncode, err[-1] if err else "")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("-v", action="store_true", help="print every case's outcome")
    ap.add_argument("-k", default="", help="only cases whose command line contains this")
    ap.add_argument("--src", default=None,
                    help="run another checkout of the package (e.g. an exported older commit)")
    args = ap.parse_args(argv)
    global SRC
    SRC = str(Path(args.src).resolve()) if args.src else None
    cases = [c for c in CASES if args.k in " ".join(c[0])]
    _servers()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "fix").mkdir()
        _fixtures(root / "fix")
        bad = 0
        with cf.ThreadPoolExecutor(args.jobs) as ex:
            for case, problems, out in ex.map(lambda c: _run(c, root), cases):
                if problems:
                    bad += 1
                if problems or args.v:
                    print(f"{'FAIL' if problems else 'ok  '} {' '.join(case[0])}  [{case[2]}]: "
                          f"{'; '.join(problems) or ''} -> {out}")
        print(f"{len(cases)} inputs: {len(cases) - bad} as promised, {bad} not")
    return 0


if __name__ == "__main__":
    sys.exit(main())
