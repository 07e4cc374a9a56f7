"""The front door (issue 12): files any reader opens, the notebook API, the command line."""
import json
import math
import subprocess
import sys

import numpy as np
import pytest

import spectral_contact
from spectral_contact import Scene, solve
from spectral_contact.cli.main import _plural, main
from spectral_contact.instruments.measured_io import read_measured_profile
from spectral_contact.result import JSON_KEYS, PROFILE_COLUMNS

from .conftest import assert_opens_plainly


@pytest.fixture(scope="module")
def fft_result():
    return solve(tol=1e-3)


# --- files ------------------------------------------------------------------------------------

def test_profiles_csv_opens_with_plain_readers_and_meta_json_beside(tmp_path, capsys):
    csv = tmp_path / "p.csv"
    assert main(["solve", "--tol", "1e-3", "--sensor", "--profiles", str(csv)]) == 0
    capsys.readouterr()
    assert_opens_plainly(csv)
    a = np.genfromtxt(csv, delimiter=",", names=True)
    assert a.dtype.names[:5] == PROFILE_COLUMNS
    assert {"S_zz_Pa", "S_xz_Pa", "U_zz_mV", "U_xz_mV"} <= set(a.dtype.names)
    dx = a["x_m"][1] - a["x_m"][0]
    assert np.sum(a["base_sigma_zz_Pa"]) * dx == pytest.approx(-200.0, rel=1e-8)
    meta = json.loads((tmp_path / "p.meta.json").read_text())
    assert set(meta["columns"]) == set(a.dtype.names)
    assert meta["result"]["load_N_per_m"] == 200.0 and "S_zz_peak_Pa" in meta["result"]


def test_measured_reader_accepts_bom_and_comments(tmp_path):
    x = np.arange(20) * 1e-4
    body = "\n".join(f"{v:.6g},{math.exp(-v * v / 1e-6):.6g},{0.1 * v:.6g}" for v in x)
    f = tmp_path / "m.csv"
    f.write_bytes(("\ufeff# measured by hand, 2009\nx_m,S_zz_Pa,S_xz_Pa\n" + body + "\n").encode("utf-8"))
    prof = read_measured_profile(f)
    assert prof.kind == "S" and prof.x_m.size == 20


def test_split_contact_reported_as_intervals(capsys):
    r = solve(mu=120.0, tol=1e-3)  # beyond mu_d ~ 95 the paper's contact splits (studies/stability)
    iv = r.contact_intervals_m
    assert len(iv) == 2 and iv[0][1] < iv[1][0]  # two disjoint intervals, sorted
    assert iv[0][0] == pytest.approx(r.contact_center_m - r.half_width_m, abs=1e-12)
    assert iv[-1][1] == pytest.approx(r.contact_center_m + r.half_width_m, abs=1e-12)
    assert main(["solve", "--mu", "120", "--tol", "1e-3"]) == 0
    assert "contact in 2 intervals" in capsys.readouterr().out


# --- Python API -------------------------------------------------------------------------------

@pytest.mark.parametrize("kw", [dict(), dict(method="abel"), dict(model="hertz"),
                                dict(model="auto", tol=1e-2)])
def test_every_json_key_is_an_attribute(kw):
    r = solve(**({"tol": 1e-3} | kw))
    rec = r.to_dict()
    assert set(JSON_KEYS) <= set(rec)
    for key, value in rec.items():
        assert getattr(r, key) == value, key
    json.dumps(rec)  # plain Python types only
    assert len(r.contact_intervals_m) == 1


def test_cli_json_is_to_dict_plus_sensor_keys(capsys, fft_result):
    assert main(["solve", "--tol", "1e-3", "--json", "--sensor"]) == 0
    rec = json.loads(capsys.readouterr().out)
    view = spectral_contact.sensor(fft_result)
    for key, value in rec.items():
        owner = fft_result if hasattr(fft_result, key) else view
        if key not in ("wall_time_s", "plan_time_s"):
            assert getattr(owner, key) == value, key  # deterministic solve: the same numbers
    assert rec["S_zz_peak_Pa"] > 0 and rec["U_zz_peak_mV"] == pytest.approx(
        rec["S_zz_peak_Pa"] * 19.0 / 1e5)
    # the peak sits where the profile is largest, within a grid step
    j = int(np.argmax(view.S_zz_Pa))
    assert abs(view.S_zz_peak_x_m - view.x_m[j]) <= view.x_m[1] - view.x_m[0]


def test_repr_is_short_si_and_profiles_named_like_csv(fft_result):
    text = repr(fft_result)
    assert len(text) < 250 and "\n" not in text
    assert "mm" in text and "kPa" in text and "N/m" in text
    prof = fft_result.profiles()
    assert tuple(prof) == PROFILE_COLUMNS
    assert all(v.shape == fft_result.x.shape for v in prof.values())
    assert len(repr(spectral_contact.sensor(fft_result))) < 300


def test_equality_does_not_raise(fft_result):
    again = solve(tol=1e-3)
    assert fft_result == again  # deterministic: same numbers, timings ignored
    assert fft_result != solve(tol=1e-3, mu=1.0)
    assert fft_result != "a string"
    with pytest.raises(TypeError):
        hash(fft_result)


def test_plot_returns_a_figure_and_takes_axes(fft_result):
    from matplotlib.figure import Figure

    fig = fft_result.plot()
    assert isinstance(fig, Figure)
    axes = [a for a in fig.axes if a.get_ylabel()]
    # issue 24: pressure and shear on one axis (a right axis scaled by mu_d added nothing)
    assert [a.get_ylabel() for a in axes] == ["surface stress [kPa]", "base stress [kPa]"]
    fig3 = fft_result.plot(sensor=spectral_contact.sensor(fft_result))
    assert any(a.get_ylabel() == "MEMS view S [kPa]" for a in fig3.axes)
    mine = Figure()
    ax = mine.add_subplot()
    assert fft_result.plot(ax=ax) is mine


# --- command line -----------------------------------------------------------------------------

def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert spectral_contact.__version__ in capsys.readouterr().out


def test_study_help_lists_every_study(capsys):
    with pytest.raises(SystemExit):
        main(["study", "--help"])
    out = capsys.readouterr().out
    for name in ("paper_figures", "paper_numbers", "speed_vs_accuracy", "model_map", "stability",
                 "large_domain", "peers", "benchmark"):
        assert name in out


def test_help_texts_of_choices(capsys):
    for argv, flags in ((["solve", "--help"], ("--model", "--method")),
                        (["calibrate", "--help"], ("--component", "--seed"))):
        with pytest.raises(SystemExit):
            main(argv)
        out = capsys.readouterr().out
        for flag in flags:
            line = out[out.index(flag):].split("\n  -")[0]
            assert len(line.split()) > 3, flag  # a flag with a sentence after it


def test_grammar_and_zero_load(capsys):
    assert _plural(1, "iteration") == "1 iteration" and _plural(2, "iteration") == "2 iterations"
    assert main(["solve", "--load", "0"]) == 0
    out = capsys.readouterr().out
    assert "peak pressure" in out and " at x = " not in out
    assert main(["solve", "--load", "0", "--sensor", "--json"]) == 0
    out = capsys.readouterr().out
    assert "NaN" not in out and json.loads(out)["S_zz_peak_x_m"] is None  # strict JSON


def test_closed_pipe_ends_quietly():
    code = ("import sys, spectral_contact.cli.main as m; sys.exit(m.main(['study', '--help']))")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    p.stdout.close()  # the reader went away (as `| head` does)
    err = p.stderr.read().decode()
    p.wait()
    assert "Traceback" not in err and "Broken pipe" not in err


def test_solve_does_not_import_matplotlib():
    code = ("import sys; from spectral_contact.cli.main import main; main(['solve', '--tol', '1e-2']);"
            "print('matplotlib' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "False"


def test_scene_defaults_match_readme():
    assert Scene().load == 200.0


def test_progress_lines_on_stderr_after_the_delay():
    import io
    import logging
    import time

    from spectral_contact.cli.progress import show_progress

    log = logging.getLogger("spectral_contact.solvers.fft")
    quiet, late = io.StringIO(), io.StringIO()
    with show_progress(after=60.0, stream=quiet):
        log.info("level 1, grid 2048 points")  # a fast command: nothing shown
    with show_progress(after=0.05, stream=late):
        log.info("level 1, grid 2048 points")
        time.sleep(0.3)  # the delay passes: the latest step is shown, then every later one
        log.info("level 2, grid 4096 points")
    assert quiet.getvalue() == ""
    lines = late.getvalue().splitlines()
    assert len(lines) == 2 and "grid 2048" in lines[0] and "grid 4096" in lines[1]
    assert all(ln.strip().startswith("[") and " s]" in ln for ln in lines)  # elapsed time
    assert not logging.getLogger("spectral_contact").handlers  # removed afterwards
