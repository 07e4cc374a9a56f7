"""The Hertz model (closed form, base transfer exact) and --model auto."""
import json
import math

import numpy as np
import pytest

from spectral_contact import MODELS, solve
from spectral_contact.cli.main import main
from spectral_contact.numerics.fft import get_rfft
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.film import base_stresses
from spectral_contact.reference.hertz import hertz_base_stresses, hertz_film_sinking, hertz_pressure
from spectral_contact.result import JSON_KEYS
from spectral_contact.solvers import auto

from .conftest import scene_for


def test_models_registered():
    assert "hertz" in MODELS and "auto" in MODELS


def test_hertz_matches_closed_form():
    sc = scene_for(0.7, 1.5)
    r = solve(sc, model="hertz", tol=1e-4)
    a = math.sqrt(sc.P / (2 * math.pi))
    assert r.model == "hertz" and r.method == "closed-form"
    assert r.half_width == pytest.approx(0.7, rel=1e-12) and r.half_width == pytest.approx(a)
    assert r.max_pressure == pytest.approx(4 * a, rel=1e-12) and r.max_pressure_x == 0.0
    assert r.center == 0.0  # friction does not couple into a half-space with Dundurs beta = 0
    dx = r.x[1] - r.x[0]
    assert np.sum(r.pressure) * dx == pytest.approx(sc.P, rel=2e-3)  # sampled sqrt edges
    np.testing.assert_allclose(r.pressure, 4 * np.sqrt(np.maximum(a * a - r.x**2, 0)))
    # the base stresses carry the load exactly (closed-form spectrum, A(0) = C(0) = 1)
    assert np.sum(r.base_sigma_zz) * dx == pytest.approx(-sc.P, rel=1e-10)
    assert np.sum(r.base_sigma_xz) * dx == pytest.approx(1.5 * sc.P, rel=1e-10)
    rec = r.summary()
    assert all(k in rec for k in JSON_KEYS) and rec["model"] == "hertz"
    assert rec["half_width_m"] == pytest.approx(0.7 * sc.thickness)


def test_hertz_base_stresses_are_the_film_symbols_on_the_pressure():
    """The closed-form spectrum agrees with the film's base_stresses applied to the sampled
    pressure on a fine grid (which carries an O(dx^1.5) sampling error of the sqrt edges)."""
    a, mu = 0.4, 2.0
    g = Grid.centered(2**15, 24.0, 0.3)
    szz, sxz = base_stresses(get_rfft(g.n), g.k, -hertz_pressure(g.x, a),
                             mu * hertz_pressure(g.x, a))
    hzz, hxz = hertz_base_stresses(g, a, mu)
    assert np.max(np.abs(hzz - szz)) < 1e-4 * np.max(np.abs(szz))
    assert np.max(np.abs(hxz - sxz)) < 1e-4 * np.max(np.abs(sxz))
    mirror_zz, _ = hertz_base_stresses(g, a, -mu)
    assert not np.allclose(mirror_zz, hzz)  # the friction enters the base stresses


def test_hertz_indentation_is_the_films_response():
    """w(0) under the Hertz pressure tends to the exact model's indentation for a thin contact,
    and differs from it by O((a/h)^2)."""
    thin = solve(scene_for(0.05, 0.0), tol=1e-4)
    assert hertz_film_sinking(0.05) == pytest.approx(thin.indentation, rel=1e-3)
    thick = solve(scene_for(1.0, 0.0), tol=1e-4)
    assert abs(hertz_film_sinking(1.0) / thick.indentation - 1) > 0.1


def test_auto_picks_hertz_for_a_tiny_contact_at_loose_tol():
    r = solve(scene_for(0.05, 0.2), model="auto", tol=0.05)
    assert r.model == "hertz" and r.info["auto"] == "hertz"
    assert "hertz" in r.info["auto_reason"] and r.summary()["auto_reason"] == r.info["auto_reason"]


def test_auto_picks_exact_for_a_thick_contact_at_tight_tol():
    sc = scene_for(2.0, 2.0)
    r = solve(sc, model="auto", tol=1e-4)
    assert r.model == "exact" and r.info["auto"] == "exact"
    assert r.half_width == pytest.approx(solve(sc, model="exact", tol=1e-4).half_width)


def test_auto_without_friction_picks_goodman_which_is_exact_there():
    r = solve(scene_for(0.5, 0.0), model="auto", tol=1e-3)
    assert r.model == "goodman"
    assert auto.model_error_bound("goodman", 0.5, 0.0) == 0.0


def test_auto_does_not_extrapolate_beyond_the_map():
    assert auto.choose_model(0.05, 6.0, 0.09)[0] == "exact"
    assert auto.choose_model(12.0, 0.0, 0.09)[0] == "exact"
    # below the map the bound is clamped to its edge (errors grow with s and |mu|)
    assert auto.model_error_bound("hertz", 0.001, 0.01) == auto.model_error_bound("hertz", 0.05, 0.05)


def test_cli_auto_json_reports_the_chosen_model(capsys):
    sc = scene_for(0.05, 0.2)
    assert main(["solve", "--model", "auto", "--json", "--tol", "0.05", "--load", str(sc.load),
                 "--mu", "0.2"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["model"] == "hertz" and rec["method"] == "closed-form" and "auto_reason" in rec
    assert main(["solve", "--model", "auto", "--json", "--tol", "1e-3"]) == 0  # paper's scene
    rec = json.loads(capsys.readouterr().out)
    assert rec["model"] == "exact" and rec["auto_reason"].startswith("exact")


def test_cli_hertz_text_summary(capsys):
    assert main(["solve", "--model", "hertz"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("hertz model, closed-form method")
