"""Issue 24, classes 4-6: subnormal inputs, laws without their parameters, the Python API's
errors.  Each refused input: InputError (Python) or exit 2 with one line (command line)."""
from __future__ import annotations

import numpy as np
import pytest

import spectral_contact
from spectral_contact import InputError, Scene, Scene3D, solve
from spectral_contact.cli.main import main

TINY = "4.9e-324"  # the smallest subnormal double


@pytest.mark.parametrize("argv", [
    ["--load", TINY], ["--radius", TINY], ["--young", TINY], ["--thickness", TINY],
    ["--load", "1e-310"], ["--model", "hertz", "--load", TINY],
    ["--friction-law", "power", "--friction-pref", TINY],
    ["--friction-law", "power", "--friction-pref", "1e300"],
    ["--friction-law", "linear", "--shear-strength", "1e300", "--shear-slope", "1"],
    ["--indenter", "cylinder", "--length", TINY],
    ["--indenter", "paraboloid", "--radius-x", TINY],
    ["--indenter", "sphere", "--force", TINY],
])
def test_subnormal_and_extreme_values_are_one_line_exit_2(argv, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["solve", "--tol", "1e-2", *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:"), err


def test_extreme_parameter_names_a_subnormal_load():
    with pytest.raises(InputError, match=r"load = 4.94066e-324"):
        Scene(load=5e-324)


def test_a_law_without_its_parameters_is_refused(capsys):
    with pytest.raises(InputError, match="needs its parameters: shear_strength"):
        Scene(friction_law="linear")
    with pytest.raises(InputError, match="needs its parameters: shear_strength"):
        Scene3D(indenter="sphere", friction_law="linear")
    assert main(["solve", "--friction-law", "linear"]) == 2
    err = capsys.readouterr().err
    assert "--friction-law linear needs its parameters: --shear-strength" in err  # as typed
    Scene(friction_law="linear", shear_slope=1.0)  # one of them is a law (Amontons, mu = alpha)
    Scene(friction_law="linear", shear_strength=1e3)


def _bowl(x, y):
    return (x * x + y * y) / 0.26


@pytest.mark.parametrize("height, words", [
    (lambda x, y: np.full(np.broadcast(x, y).shape, "a"), "must return numbers"),
    (lambda x, y: "abc", "must return numbers"),
    (lambda x, y: np.where(x > 0, np.nan, _bowl(x, y)), "NaN"),
    (lambda x, y: np.where(x > 0, -np.inf, _bowl(x, y)), "-inf"),
    (lambda x, y: np.zeros(3), "shape"),
    (lambda x, y: np.full(np.broadcast(x, y).shape, np.inf), "no finite one"),
])
def test_an_indenter_callable_returning_nonsense_is_an_input_error(height, words):
    with pytest.raises(InputError, match=words):
        solve(indenter="function", height=height, force=0.5, tol=1e-2)


@pytest.mark.parametrize("arg", ["x", 3, None])
def test_sensor_of_something_else_is_an_input_error(arg):
    with pytest.raises(InputError, match="result of solve"):
        spectral_contact.sensor(arg)


def test_compare_whose_fits_failed_says_so_and_warns_about_units(tmp_path, capsys, monkeypatch):
    """x in millimetres under the x_m header: a units warning; both direct fits fail (one
    raises, one explains nothing: chi = 1), so there is no best model and JSON says why."""
    import json

    from spectral_contact.instruments.sensor import sensor_view

    r = solve(tol=1e-3)
    s = sensor_view(r)
    sel = np.flatnonzero(np.abs(r.x_m) < 0.016)[::8]
    rows = "\n".join(f"{r.x_m[i] * 1e3:.17g},{s['S_zz_Pa'][i]:.17g},{s['S_xz_Pa'][i]:.17g}"
                     for i in sel)
    (tmp_path / "mm.csv").write_text("x_m,S_zz_Pa,S_xz_Pa\n" + rows + "\n")
    monkeypatch.chdir(tmp_path)
    assert main(["compare", "mm.csv", "--json", "--tol", "1e-3"]) == 0
    out, err = capsys.readouterr()
    rec = json.loads(out)
    assert rec["best_model"] is None and rec["fits"] == {}
    assert set(rec["fits_failed"]) == {"exact", "goodman"}
    lines = err.strip().splitlines()
    assert any("is x_m in metres?" in ln for ln in lines)
    assert any("every direct fit failed" in ln for ln in lines)


def test_compliant_interface_estimate_covers_the_recorded_slow_edges():
    """C = 1e-9 m/Pa at the paper's scene, tol 1e-4: the last three levels (2^15, 2^16, 2^17
    points; info["levels"]) and the half-width of a tol 1e-5 solve (2^21 points; its estimate
    4e-6).  The rigid rule gave 2.9e-5 against a true error of 4.8e-5; the soft-edge rule
    covers it (studies/interface_estimate.py: 1.25-3.8 x at tol 1e-4 and 1e-3)."""
    from spectral_contact.solvers.fft import _discretisation_error, _steps

    keys = ("a", "c", "d", "pmax")
    lv = [dict(zip(keys, v)) for v in (
        (1.894800809547934, 0.3369090555033749, 3.3677506645705853, 7.07350449992685),
        (1.8949781428458883, 0.33684495887167243, 3.3677506677429383, 7.0735045030347745),
        (1.8950131878495753, 0.3368452304276752, 3.367750669782396, 7.073504509126864))]
    a_ref = 3.79020645113645e-3 / 2e-3
    true = abs(lv[2]["a"] - a_ref) / a_ref
    step, last = _steps(lv[2], lv[1]), _steps(lv[1], lv[0])
    rigid = _discretisation_error(step, last, 7.5e-6)
    soft = _discretisation_error(step, last, 7.5e-6, soft_edges=True)
    assert rigid < true < soft  # 2.8e-5 < 4.8e-5 < 9.4e-5
    r = solve(interface_compliance=1e-9, tol=1e-3)
    assert r.info["estimate_parts"]["previous_difference"] <= r.error_estimate


def test_the_example_data_runs_as_readme_says(capsys):
    """examples/: compare (integral estimates, no fit: fast) and calibrate recover the values
    the synthetic files were made with."""
    import json
    from pathlib import Path

    ex = Path(__file__).resolve().parent.parent / "examples"
    assert main(["compare", str(ex / "synthetic_sliding_profile.csv"), "--no-fit", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert abs(rec["load_N_per_m"] / 200 - 1) < 0.02 and abs(rec["mu"] / 2 - 1) < 0.02
    assert abs(rec["offset_m"] - 0.5e-3) < 0.02e-3
    assert main(["calibrate", "--measured", str(ex / "synthetic_punch_scan.csv"), "--punch-load",
                 "0.1", "--n-boot", "0", "--json"]) == 0
    assert abs(json.loads(capsys.readouterr().out)["A_mV_per_bar"] / 19.0 - 1) < 0.01


def test_start_up_imports_neither_dask_array_nor_scipy_fftpack():
    """pyfftw is imported without its drop-in interfaces (numerics.fft._import_pyfftw): a fresh
    solve imports neither dask.array nor scipy.fftpack (85 % of `import pyfftw`), and both
    still import afterwards."""
    import subprocess
    import sys

    code = ("import sys, spectral_contact as sc; sc.solve(tol=1e-2); "
            "print('dask.array' in sys.modules, 'scipy.fftpack' in sys.modules); "
            "import dask.array.fft, pyfftw.interfaces.scipy_fft; print('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300).stdout.split()
    assert out == ["False", "False", "ok"]


def test_progress_on_a_terminal_is_one_line_rewritten_and_erased():
    import io
    import logging

    from spectral_contact.cli.progress import show_progress

    class Tty(io.StringIO):
        def isatty(self):
            return True

    tty = Tty()
    with show_progress(after=0.0, stream=tty, skip=("spectral_contact.solvers",)):
        import time

        time.sleep(0.05)
        logging.getLogger("spectral_contact.instruments.compare").info("fit: solve 2")
        logging.getLogger("spectral_contact.solvers.fft").info("level 3")  # skipped
        logging.getLogger("spectral_contact.instruments.compare").info("fit: solve 3")
    text = tty.getvalue()
    assert "\n" not in text and "level 3" not in text and "fit: solve 3" in text
    assert text.endswith("\r\x1b[K")  # erased when done


def test_line_plot_window_holds_the_base_stress_tails():
    """The plotted x range reaches where both base stresses are below 1 % of their peak (it
    was the contact +- 2 h, cutting S_xz at a quarter of its peak)."""
    from spectral_contact.result import TAIL_FRACTION

    r = solve(tol=1e-3)
    fig = r.plot()
    lo, hi = fig.axes[1].get_xlim()
    x = r.x_m * 1e3
    base = np.maximum(np.abs(r.base_sigma_zz_Pa), np.abs(r.base_sigma_xz_Pa))
    outside = (x < lo) | (x > hi)
    assert np.max(base[outside], initial=0.0) < TAIL_FRACTION * base.max() * 1.01
    assert fig.texts and fig.texts[0].get_fontsize() >= 10  # a readable title


def test_surface_maps_clip_singular_ends_and_show_the_line_y0():
    """Finite cylinder: the pressure's colour scale ends at the 99.5th percentile (its ends
    are singular) and the title says so; the MEMS iso-lines have a colour bar; a y = 0 panel."""
    from spectral_contact.instruments.sensor import sensor_maps
    from spectral_contact.result import MAP_CLIP_PERCENTILE

    r = solve(indenter="cylinder", force=1.0, tol=1e-2, grid_points=128)
    fig = r.plot(sensor=sensor_maps(r))
    title = fig._suptitle.get_text()
    assert f"{MAP_CLIP_PERCENTILE:g}th percentile" in title and "pressure" in title
    titles = [a.get_title() for a in fig.axes]
    assert any(t.startswith("the line y = ") for t in titles)
    assert sum(a.get_ylabel() == "kPa" for a in fig.axes) == 7  # a colour bar per map


def test_surface_solves_log_their_levels(caplog):
    """A surface solve tells the progress log its levels (the command line shows them on a
    terminal once past 2 s; they printed nothing before)."""
    import logging

    with caplog.at_level(logging.INFO, logger="spectral_contact"):
        solve(indenter="sphere", force=1.0, tol=1e-2)
    assert any("level 1:" in r.getMessage() and r.name == "spectral_contact.solvers.fft3d"
               for r in caplog.records)
