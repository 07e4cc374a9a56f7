"""The reliability pass over the session's new commands (invert maps, onset, the viscoelastic
film): what the adversarial and new-user passes found, each fixed and kept fixed here.

All fast: every refusal happens before any solve (the output checks come first).
"""
from __future__ import annotations

import argparse
import math
import re

import numpy as np
import pytest

from spectral_contact.cli.main import main

from .test_reliability_outputs import refused


@pytest.fixture
def npz(tmp_path):
    n = 8
    x = np.arange(n) * 1e-3
    z = np.zeros((n, n))
    np.savez(tmp_path / "maps.npz", x_m=x, y_m=x, base_sigma_zz_Pa=z, base_sigma_xz_Pa=z,
             base_sigma_yz_Pa=z)
    return tmp_path


@pytest.mark.parametrize("argv", [
    # an NPZ written under another name: invert sends files to the maps' reader by the .npz
    # suffix, so `invert tractions.csv` would then read a zip archive as a line record
    ["invert", "maps.npz", "--out", "tractions.csv"],
    ["solve", "--indenter", "sphere", "--force", "1", "--maps", "m.csv"],
    ["onset", "--indenter", "sphere", "--force", "1", "--maps", "m.txt"],
])
def test_npz_outputs_must_be_named_npz(argv, npz, capsys, monkeypatch):
    opt = argv[-2]
    err = refused(argv, npz, capsys, monkeypatch, words=[f"{opt} {argv[-1]}", ".npz"])
    assert err.startswith("error:")


def test_npz_output_named_npz_still_planned(npz, capsys, monkeypatch):
    """The check does not refuse a proper name (case-insensitive suffix); the rest of the
    plan still applies (here: over the input, refused for that reason)."""
    from spectral_contact.cli.files import plan_outputs

    assert plan_outputs(npzs=("--maps",), **{"--maps": str(npz / "out.NPZ")})
    err = refused(["invert", "maps.npz", "--out", "maps.npz"], npz, capsys, monkeypatch)
    assert "overwrite the input" in err


def test_invert_text_undetermined_contact_sd_is_not_printed_as_nan():
    """A record that ends inside the contact (the contact prior's window at its search bound)
    has no Laplace sd for the window's edges: NaN in the record (null in the JSON).  The text
    summary printed `contact [-1.229 +- nan, 4.396 +- nan] mm`; now '?' and the reason."""
    from spectral_contact.cli.invert import _invert_text

    rec = {"points": 333, "nodes": 46, "load_N_per_m": 160.2, "load_sigma_N_per_m": 21.0,
           "tangential_load_N_per_m": 367.7, "tangential_load_sigma_N_per_m": 15.0,
           "Q_over_P": 2.295, "Q_over_P_sigma": 0.2, "contact_interval_m": [-1.229e-3, 4.396e-3],
           "contact_interval_sigma_m": [math.nan, None], "resolution_length_m": 6.06e-4,
           "noise_sd_zz_Pa": 158.0, "noise_sd_xz_Pa": 148.0, "log_evidence": -4318.35,
           "laws": {"note": "too few resolved nodes"}}
    args = argparse.Namespace(json=False, record="trail.csv")
    text = _invert_text(args, rec, "base")
    assert not re.search(r"\b(nan|none)\b", text.split("best law")[0], re.I), text
    assert "+- ?" in text and "not determined" in text
    rec["contact_interval_sigma_m"] = [6e-5, 2.2e-5]
    text = _invert_text(args, rec, "base")
    assert "+- 0.06," in text and "not determined" not in text


def test_onset_docstring_states_the_defaults():
    from spectral_contact.solvers import onset as mod
    from spectral_contact.solvers.onset3d import DEFAULT_TOL_3D

    def e(v):  # 0.01 -> "1e-2", as the docstrings write it
        return f"1e{round(math.log10(v))}"

    doc = " ".join(mod.onset.__doc__.split())
    assert f"``DEFAULT_TOL`` = {e(mod.DEFAULT_TOL)}" in doc
    assert f"``onset3d.DEFAULT_TOL_3D`` = {e(DEFAULT_TOL_3D)}" in doc
    assert f"``LOADING_STEPS`` = {mod.LOADING_STEPS}" in doc


def test_cli_onset_help_states_the_default_tol(capsys):
    from spectral_contact.solvers.onset import DEFAULT_TOL

    with pytest.raises(SystemExit):
        main(["onset", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert f"(default {DEFAULT_TOL:g})" in out


@pytest.mark.parametrize("scale, field, words", [
    (1.0, 1e300, ["largest |stress| is 1e+300 Pa", "1e-100 ... 1e+100"]),  # was exit 0, +- inf
    (1.0, 1e-310, ["largest |stress| is 1e-310 Pa"]),
    (1e3, 1.0, ["x_m spans 11 m", "--thickness"]),  # x in mm: was an internal ValueError, exit 1
])
def test_invert_maps_values_and_spans_out_of_range(scale, field, words, tmp_path, capsys,
                                                   monkeypatch):
    n = 12
    x = np.arange(n) * 1e-3 * scale
    z = np.zeros((n, n))
    np.savez(tmp_path / "m.npz", x_m=x, y_m=x, base_sigma_zz_Pa=z + field, base_sigma_xz_Pa=z,
             base_sigma_yz_Pa=z)
    refused(["invert", "m.npz", "--json"], tmp_path, capsys, monkeypatch, words=words)


def test_invert_flags_a_contact_beyond_the_record(capsys, tmp_path, monkeypatch):
    """A noise-free record ending at x = 0, inside the paper's contact [-1.3, 3.7] mm: the
    inversion answered P 86 +- 7 N/m (truth 200) with nothing said.  Now `contact_within_record`
    is false in the JSON and a warning names it; the whole record (|x| < 10 mm) stays unflagged."""
    import json

    from spectral_contact import solve

    r = solve(tol=1e-3)
    monkeypatch.chdir(tmp_path)
    for name, sel, inside in (("trail.csv", (r.x_m > -0.012) & (r.x_m < 0.0), False),
                              ("whole.csv", np.abs(r.x_m) < 0.01, True)):
        x, zz, xz = (a[sel][::4] for a in (r.x_m, r.base_sigma_zz_Pa, r.base_sigma_xz_Pa))
        (tmp_path / name).write_text("x_m,base_sigma_zz_Pa,base_sigma_xz_Pa\n" + "\n".join(
            f"{a:.17g},{b:.17g},{c:.17g}" for a, b, c in zip(x, zz, xz)) + "\n")
        capsys.readouterr()
        assert main(["invert", name, "--json", "--prior", "contact"]) == 0
        out, err = capsys.readouterr()
        rec = json.loads(out)
        assert rec["contact_within_record"] is inside
        assert rec["record_m"] == pytest.approx([x[0], x[-1]], abs=1e-4)
        assert ("reaches beyond the record" in err) is (not inside)


def test_onset_warning_names_every_share_above_tol(capsys):
    """A fixed coarse grid and few load steps: the warning named only the load steps (their
    share 4.1e-2 on the sphere at 48^2, the whole 1.7e-1) and hid the grid's.  Now each share
    above --tol is named (line at 128 points: 8.1e-2 load steps, 1.8e-2 grid)."""
    import re

    assert main(["onset", "--steps", "2", "--loading-steps", "2", "--grid-points", "128",
                 "--json"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    m = re.search(r"estimate (\S+) > --tol .*load steps' share (\S+):.*the grid's share (\S+) at "
                  r"the fixed --grid-points 128", err[0])
    assert m, err[0]
    total, step, grid = (float(v) for v in m.groups())
    assert step > 1e-2 and grid > 1e-2 and total == pytest.approx(step + grid, rel=0.1)


def test_invert_warns_on_a_tensile_record(capsys, tmp_path, monkeypatch):
    """base_sigma_zz with the wrong sign (> 0 in compression): the inversion answered P < 0
    (-114 +- 110 N/m on a 1 %-noise record) with nothing said; now a warning asks for the sign.
    The right sign gives no such warning."""
    from spectral_contact import solve

    r = solve(tol=1e-3)
    sel = np.abs(r.x_m) < 0.008
    x, zz, xz = (a[sel][::4] for a in (r.x_m, r.base_sigma_zz_Pa, r.base_sigma_xz_Pa))
    monkeypatch.chdir(tmp_path)
    for sign in (-1.0, 1.0):
        (tmp_path / "r.csv").write_text("x_m,base_sigma_zz_Pa,base_sigma_xz_Pa\n" + "\n".join(
            f"{a:.17g},{sign * b:.17g},{c:.17g}" for a, b, c in zip(x, zz, xz)) + "\n")
        capsys.readouterr()
        assert main(["invert", "r.csv", "--prior", "contact"]) == 0
        err = capsys.readouterr().err
        assert ("is its sign right?" in err) is (sign < 0), err
