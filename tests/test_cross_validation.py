"""FFT against the paper's Abel formulation: two independent solutions of the same model.

Scenes: Hertz half-widths 0.1 ... 4.5 h (film half-widths 0.1 ... 3.1 h) x mu_d 0 ... 3.
The Abel solution converges spectrally in its node count (1e-9 here), so the differences below
are the FFT method's error: they must stay within 1e-4 and within the FFT's own error estimate.
"""
import json
import warnings

import numpy as np
import pytest

from spectral_contact import solve
from spectral_contact.cli.main import main
from spectral_contact.solvers.abel import solve_abel

from .conftest import scene_for

SCENES = [(aH, mu) for aH in (0.1, 0.5, 1.0, 2.0, 4.5) for mu in (0.0, 0.5, 1.0, 2.0, 3.0)]


@pytest.mark.parametrize("aH,mu", SCENES)
def test_fft_agrees_with_abel(aH, mu):
    scene = scene_for(aH, mu)
    f = solve(scene, tol=2e-5)
    window = np.abs(f.x - f.center) < f.half_width + 6.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the Abel solver must not doubt itself on these scenes
        ab = solve_abel(scene, tol=1e-9, x=f.x[window])
    diffs = {
        "a": abs(f.half_width - ab.half_width) / ab.half_width,
        "x0": abs(f.center - ab.center) / ab.half_width,
        "indentation": abs(f.indentation - ab.indentation) / ab.indentation,
        "p_max": abs(f.max_pressure - ab.max_pressure) / ab.max_pressure,
    }
    for name, d in diffs.items():
        assert d <= 1e-4, (name, d)
    assert max(diffs.values()) <= 2 * f.error_estimate  # the estimate is honest
    for fft_field, abel_field in ((f.base_sigma_zz, ab.base_sigma_zz), (f.base_sigma_xz, ab.base_sigma_xz)):
        peak = np.abs(abel_field).max()
        assert np.abs(fft_field[window] - abel_field).max() <= 1e-4 * peak
    # same sign conventions: the friction pushes the contact toward +x
    if mu > 0:
        assert f.center > 0 and ab.center > 0


def test_goodman_agrees_with_abel():
    scene = scene_for(2.0, 2.0)
    f = solve(scene, model="goodman", tol=2e-5)
    window = np.abs(f.x - f.center) < f.half_width + 6.0
    ab = solve_abel(scene, model="goodman", tol=1e-9, x=f.x[window])
    assert abs(f.half_width / ab.half_width - 1) <= 1e-4
    for fft_field, abel_field in ((f.base_sigma_zz, ab.base_sigma_zz), (f.base_sigma_xz, ab.base_sigma_xz)):
        assert np.abs(fft_field[window] - abel_field).max() <= 1e-4 * np.abs(abel_field).max()


def test_cli_abel_method_json(capsys):
    assert main(["solve", "--method", "abel", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["method"] == "abel"
    assert main(["solve", "--json"]) == 0
    fft = json.loads(capsys.readouterr().out)
    assert rec["half_width_m"] == pytest.approx(fft["half_width_m"], rel=1e-4)
    assert rec["x0_m"] == pytest.approx(fft["x0_m"], rel=1e-4)


def test_abel_accepts_few_nodes():
    r = solve(method="abel", grid_points=12)
    assert r.grid_points == 12
