"""Issue 24, the adversarial pass over the newer commands (invert, onset, the viscoelastic film)
and the shared write step: each refused input is one line, exit 2, nothing written, no
traceback; negative numbers in any notation are values."""
from __future__ import annotations

import os

import numpy as np
import pytest

from spectral_contact import InputError
from spectral_contact.cli.files import csv_file, plan_outputs, staged, write_outputs
from spectral_contact.cli.main import main


def _record(path, x, zz, xz, names=("x_m", "base_sigma_zz_Pa", "base_sigma_xz_Pa")):
    rows = "\n".join(f"{a:.17g},{b:.17g},{c:.17g}" for a, b, c in zip(x, zz, xz))
    path.write_text(",".join(names) + "\n" + rows + "\n")
    return path


@pytest.fixture
def records(tmp_path):
    """Line records of base stresses (a smooth bump, 2 mm film), with the defects under test."""
    x = np.linspace(-0.01, 0.01, 81)
    zz = -5e4 * np.exp(-(x / 2e-3) ** 2)
    xz = 2e4 * np.exp(-(x / 2e-3) ** 2)
    return {"ok": (x, zz, xz),
            "huge": (x, zz * 1e300, xz * 1e300),        # was OverflowError, exit 1
            "subnormal": (x, zz * 1e-310, xz * 1e-310),  # was ZeroDivisionError, exit 1
            "millimetres": (x * 1e3, zz, xz),            # was ValueError (L-BFGS-B bounds), exit 1
            "tiny_span": (x * 1e-300, zz, xz)}           # was exit 0 with a meaningless P


def _refused(argv, tmp_path, capsys, monkeypatch, words=()):
    monkeypatch.chdir(tmp_path)
    before = set(os.listdir(tmp_path))
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and "Traceback" not in err[0], err
    for w in words:
        assert w in err[0], err
    assert set(os.listdir(tmp_path)) == before  # nothing written
    return err[0]


@pytest.mark.parametrize("kind, words", [
    ("huge", ("1e-100 ... 1e+100 Pa",)), ("subnormal", ("1e-100 ... 1e+100 Pa",)),
    ("millimetres", ("0.5 ... 100 thicknesses", "--thickness")),
    ("tiny_span", ("0.5 ... 100 thicknesses",))])
def test_invert_refuses_records_outside_its_range(kind, words, records, tmp_path, capsys,
                                                  monkeypatch):
    _record(tmp_path / "r.csv", *records[kind])
    _refused(["invert", "r.csv", "--out", "t.csv", "--plot", "t.png"], tmp_path, capsys,
             monkeypatch, words)


def test_invert_refuses_a_support_outside_the_record(records, tmp_path, capsys, monkeypatch):
    # was: 0.5 .. 1 m on a 20 mm record built 4000 nodes (1.4 GB, minutes)
    _record(tmp_path / "r.csv", *records["ok"])
    _refused(["invert", "r.csv", "--support", "0.5", "1"], tmp_path, capsys, monkeypatch,
             ("--support 0.5 1", "within the record"))


def test_invert_thickness_that_makes_the_record_implausible(records, tmp_path, capsys, monkeypatch):
    _record(tmp_path / "r.csv", *records["ok"])
    for h in ("1e308", "5e-324", "0.2"):
        _refused(["invert", "r.csv", "--thickness", h], tmp_path, capsys, monkeypatch,
                 ("--thickness",))


def test_invert_from_python_names_the_parameter(records):
    x, zz, xz = records["millimetres"]
    from spectral_contact.instruments.inverse import invert_line

    with pytest.raises(InputError, match=r"\(thickness 0.002 m\)"):
        invert_line(x, -zz, xz)


@pytest.mark.parametrize("argv", [
    ["onset", "--mu", "1e-300", "--steps", "2"],             # was IndexError, exit 1
    ["onset", "--mu", "-5e-324", "--steps", "2", "--indenter", "sphere"],  # was ValueError
    ["onset", "--mu", "1e-200", "--steps", "2", "--loading", "frictionless"],
])
def test_onset_refuses_a_vanishing_friction(argv, tmp_path, capsys, monkeypatch):
    _refused(argv, tmp_path, capsys, monkeypatch, ("--mu", "1e-06"))


def test_onset_messages_name_the_option_once(tmp_path, capsys, monkeypatch):
    msg = _refused(["onset", "--amplitude", "2"], tmp_path, capsys, monkeypatch)
    assert msg.startswith("error: --amplitude must be in (0, 1]"), msg  # was "amplitude (--amplitude)"
    msg = _refused(["onset", "--grid-points", "63"], tmp_path, capsys, monkeypatch)
    assert msg.count("--grid-points") == 1, msg  # was "--grid-points (--grid-points (--grid-points))"


@pytest.mark.parametrize("prony, speed, words", [
    ("5e-324,0.01", "0.05", ("E_i / E_inf",)),    # was "math domain error", exit 1
    ("1e308,0.01", "0.05", ("E_i / E_inf",)),     # was exit 0 after overflow warnings
    ("2.2e6,5e-324", "0.05", ("|V| tau / h",)),   # was "cannot convert float NaN", exit 1
    ("2.2e6,1e308", "0.05", ("|V| tau / h",)),    # was "math domain error", exit 1
    ("2.2e6,0.01", "1e308", ("|V| tau / h",)),    # was "math domain error", exit 1
])
def test_viscoelastic_terms_outside_the_arithmetic_are_refused(prony, speed, words, tmp_path,
                                                               capsys, monkeypatch):
    _refused(["solve", "--tol", "1e-2", "--speed", speed, "--prony", prony, "--profiles", "p.csv"],
             tmp_path, capsys, monkeypatch, ("--prony", *words))


@pytest.mark.parametrize("argv, words", [
    (["solve", "--mu", "-1e4"], ("--mu", "[-1000, 1000]")),     # was "expected one argument"
    (["solve", "--mu", "-inf"], ("--mu", "finite")),
    (["compare", "m.csv", "--poisson", "-1e-3"], ("--poisson", "[0, 0.5]")),
    (["onset", "--mu", "-1E-300"], ("--mu", "1e-06")),
])
def test_negative_numbers_in_any_notation_are_values(argv, words, tmp_path, capsys, monkeypatch):
    (tmp_path / "m.csv").write_text("x_m,S_zz_Pa,S_xz_Pa\n" + "\n".join(
        f"{i * 1e-4},{i},{i}" for i in range(10)) + "\n")
    _refused(argv, tmp_path, capsys, monkeypatch, words)


def test_a_negative_scientific_mu_solves(capsys):
    assert main(["solve", "--mu", "-1e-3", "--tol", "1e-2", "--json"]) == 0
    assert '"mu": -0.001' in capsys.readouterr().out


def test_the_shared_write_step(tmp_path, capsys):
    """plan_outputs checks, write_outputs writes the given outputs (CSV with its metadata, a
    staged file) with stdout, in one commit; an absent option's writer is never called."""
    out = plan_outputs(inputs={"IN": None}, csvs=("--out",), plots=("--plot",),
                       **{"--out": str(tmp_path / "a.csv"), "--plot": None,
                          "--maps": str(tmp_path / "m.bin")})
    called = []
    write_outputs(out, {"--out": csv_file(lambda: {"x_m": [1.0, 2.0]}, lambda c: {"cols": list(c)}),
                        "--plot": staged(lambda p: called.append(p)),
                        "--maps": staged(lambda p: open(p, "wb").write(b"x"))}, lambda: "done")
    assert not called
    assert (tmp_path / "a.csv").read_text().startswith("x_m\n1")
    assert '"cols"' in (tmp_path / "a.meta.json").read_text()
    assert (tmp_path / "m.bin").read_bytes() == b"x"
    assert capsys.readouterr().out == "done\n"
    with pytest.raises(InputError, match="unsupported format"):
        plan_outputs(plots=("--plot",), **{"--plot": str(tmp_path / "p.nope")})

    def broken(path):
        open(path, "w").write("partial")
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError, match="b.csv"):  # the user's file named, nothing left
        write_outputs(plan_outputs(**{"--x": str(tmp_path / "b.csv")}),
                      {"--x": staged(broken)}, "never printed")
    assert sorted(os.listdir(tmp_path)) == ["a.csv", "a.meta.json", "m.bin"]
    assert capsys.readouterr().out == ""
