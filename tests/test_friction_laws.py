"""Friction laws (issue 14, --friction-law): Amontons as an exact special case, the converged
state checked against the coupled equations recomputed independently, equilibrium of the base
stresses for every law, Goodman's model with a law, one-line errors."""
import json

import numpy as np
import pytest

from spectral_contact import Scene, solve
from spectral_contact.cli.main import main
from spectral_contact.numerics.friction import solve_contact_law
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.film import Film
from spectral_contact.physics.friction import FrictionLaw, ShearLaw
from spectral_contact.physics.indenters import Cylinder
from spectral_contact.physics.transfer import compressible_transfer_functions, transfer_functions

_FIELDS = ("pressure", "base_sigma_zz", "base_sigma_xz", "x")


@pytest.mark.parametrize("law", [
    dict(friction_law="power", friction_exponent=0.0, friction_pref=1e4),
    dict(friction_law="linear", shear_strength=0.0, shear_slope=2.0),
])
def test_proportional_laws_are_amontons_bit_for_bit(law):
    ref = solve(load=200.0, mu=2.0, tol=1e-3)
    r = solve(load=200.0, mu=2.0, tol=1e-3, **law)
    for name in _FIELDS:
        np.testing.assert_array_equal(getattr(r, name), getattr(ref, name))
    assert (r.half_width, r.center, r.indentation) == (ref.half_width, ref.center, ref.indentation)
    np.testing.assert_array_equal(r.surface_shear, ref.surface_shear)
    assert r.friction_ratio == pytest.approx(2.0, rel=1e-14)


def _independent_sinking(grid, p, q, nu):
    """w = H0 p + H1 q by numpy's FFT with the symbols written from the transfer functions."""
    k = 2 * np.pi * np.fft.fftfreq(grid.n, grid.dx)
    K = np.abs(k)
    F0, F1 = (transfer_functions(K)[:2] if nu == 0.5 else compressible_transfer_functions(K, nu)[:2])
    safe = np.where(K > 0, K, 1.0)
    H0 = np.where(K > 0, F0 / (2 * safe), (1 - 2 * nu) / (2 * (1 - nu)))
    H1 = np.where(K > 0, 1j * np.sign(k) * F1 / (2 * safe), 0.0)
    return np.fft.ifft(H0 * np.fft.fft(p) + H1 * np.fft.fft(q)).real


@pytest.mark.parametrize("law,nu", [
    (ShearLaw("power", mu=2.0, exponent=0.3, pref=3.0), 0.5),
    (ShearLaw("power", mu=-1.5, exponent=0.5, pref=1.0), 0.5),
    (ShearLaw("power", mu=2.0, exponent=0.2, pref=3.0), 0.3),
    (ShearLaw("linear", mu=1.0, tau0=1.5), 0.5),
])
def test_converged_state_satisfies_the_coupled_equations(law, nu):
    g = Grid.centered(1024, 24.0, 0.5)
    sol, q, info = solve_contact_law(g, law, [Cylinder(0.0, 10.0)], film=Film(poisson=nu),
                                     accept=1e-8, law_tol=1e-9)
    p = sol.pressure
    assert info["law_iterations"] > 1
    assert np.sum(p) * g.dx == pytest.approx(10.0, rel=1e-9)
    # the law holds away from the cells next to the contact edge
    edge = np.zeros(g.n, bool)
    for s in (1, -1):
        edge |= sol.active != np.roll(sol.active, s)
    np.testing.assert_allclose(q[~edge], law.shear(p)[~edge], rtol=0, atol=1e-8 * np.abs(q).max())
    # contact conditions with the sinking recomputed independently
    w = _independent_sinking(g, p, q, nu)
    gap = g.x**2 - sol.indentations[0] + w
    scale = np.abs(w).max()
    assert np.max(np.abs(gap[sol.active])) < 1e-7 * scale
    assert gap[~sol.active].min() > -1e-7 * scale
    assert p.min() >= 0.0


@pytest.mark.parametrize("kw", [
    dict(friction_law="power", friction_exponent=0.2, friction_pref=3e4),
    dict(friction_law="power", friction_exponent=0.2, friction_pref=3e4, poisson=0.45),
    dict(friction_law="linear", shear_strength=1e4, shear_slope=1.2),
    dict(friction_law="linear", shear_strength=-1e4, shear_slope=-1.2),
    dict(friction_law="linear", shear_strength=0.0, shear_slope=1.2, poisson=0.3),
])
@pytest.mark.parametrize("model", ["exact", "goodman"])
def test_equilibrium_for_every_law(kw, model):
    r = solve(load=200.0, mu=2.0, tol=1e-3, model=model, **kw)
    dx = r.x[1] - r.x[0]
    P = r.scene.P
    Q = np.sum(r.surface_shear) * dx
    assert -np.sum(r.base_sigma_zz) * dx == pytest.approx(P, rel=1e-10)
    assert np.sum(r.base_sigma_xz) * dx == pytest.approx(Q, rel=1e-10)
    assert r.friction_ratio == pytest.approx(Q / (np.sum(r.pressure) * dx), rel=1e-12)
    assert np.all(r.surface_shear[r.pressure <= 0] == 0.0)
    assert np.all(np.sign(r.surface_shear[r.pressure > 0]) == np.sign(r.friction_ratio))
    if model == "goodman":  # the frictionless pressure, and the law's shear on it
        ref = solve(load=200.0, mu=0.0, tol=1e-3, model="goodman", poisson=kw.get("poisson", 0.5))
        np.testing.assert_array_equal(r.pressure, ref.pressure)
        law = r.scene.friction.dimensionless(r.scene.stress_unit, r.scene.mu)
        np.testing.assert_array_equal(r.surface_shear, law.shear(r.pressure))


def test_power_law_lowers_q_over_p_when_the_pressure_exceeds_p_ref():
    """mu(p) = mu_d (p/p_ref)^-n: with p_ref below every contact pressure that matters, Q/P < mu_d;
    with p_ref far above, Q/P > mu_d."""
    low = solve(load=200.0, mu=2.0, tol=1e-3, friction_law="power", friction_exponent=0.1,
                friction_pref=1e3)
    high = solve(load=200.0, mu=2.0, tol=1e-3, friction_law="power", friction_exponent=0.1,
                 friction_pref=1e6)
    assert low.friction_ratio < 2.0 < high.friction_ratio
    # the paper's range: Q/P of a power law at two loads falls with the load
    small = solve(load=20.0, mu=2.0, tol=1e-3, friction_law="power", friction_exponent=0.1,
                  friction_pref=3e4)
    assert small.friction_ratio > low.friction_ratio


@pytest.mark.parametrize("argv,word", [
    (["--friction-law", "coulomb"], "friction-law"),
    (["--friction-law", "power", "--friction-pref", "1e4", "--friction-exponent", "1"], "exponent"),
    (["--friction-law", "power", "--friction-pref", "1e4", "--friction-exponent", "-0.1"], "exponent"),
    (["--friction-law", "power", "--friction-pref", "0"], "pref"),
    (["--friction-law", "power"], "pref"),
    (["--friction-exponent", "0.2"], "power"),
    (["--friction-law", "power", "--friction-pref", "1e4", "--shear-slope", "1"], "linear"),
    (["--friction-law", "linear", "--shear-strength=-1e3", "--shear-slope", "1"], "same sign"),
    (["--friction-law", "linear", "--shear-strength", "inf"], "shear strength"),
    (["--friction-law", "linear", "--shear-strength", "1e3", "--poisson", "0.4"], "poisson"),
    (["--friction-law", "power", "--friction-pref", "1e4", "--method", "abel"], "abel"),
    (["--friction-law", "power", "--friction-pref", "1e4", "--model", "hertz"], "hertz"),
])
def test_cli_refuses_bad_friction_laws_in_one_line(argv, word, capsys, tmp_path):
    out = tmp_path / "p.csv"
    assert main(["solve", *argv, "--profiles", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and word in err and not out.exists()


def test_cli_json_reports_law_and_q_over_p(capsys):
    assert main(["solve", "--json", "--tol", "1e-3", "--friction-law", "linear",
                 "--shear-strength", "5e3", "--shear-slope", "1.5"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["friction_law"] == "linear" and rec["shear_strength_Pa"] == 5e3
    assert 1.5 < rec["Q_over_P"] < 2.5
    assert main(["solve", "--json", "--tol", "1e-3"]) == 0
    rec = json.loads(capsys.readouterr().out)
    # Q/P = mu + mu_def (issue 23: the pressure on the inclined indenter, (h/R) x_p, one
    # definition for every film; > 0 with mu > 0: the pressure leans to the leading side)
    assert rec["friction_law"] == "amontons"
    assert rec["Q_over_P"] == rec["mu"] + rec["deformation_friction"]
    assert 0 < rec["deformation_friction"] < 0.05 * rec["mu"]


def test_friction_law_object_validation():
    assert FrictionLaw().is_amontons
    with pytest.raises(Exception, match="exponent"):
        FrictionLaw("power", exponent=1.5, pref=1.0)
    assert Scene(friction_law="power", friction_pref=2e4).friction.exponent == 0.0


def test_friction_laws_and_interface_in_three_d():
    """3D (a sphere): power with n = 0 is Amontons bit for bit; equilibrium of the base shear
    with Int q for the laws; a compliant interface widens the contact."""
    base = solve(indenter="sphere", force=0.5, mu=1.0, tol=1e-2)
    r0 = solve(indenter="sphere", force=0.5, mu=1.0, tol=1e-2, friction_law="power",
               friction_exponent=0.0, friction_pref=1e4)
    np.testing.assert_array_equal(r0.pressure, base.pressure)
    np.testing.assert_array_equal(r0.base_sigma_xz, base.base_sigma_xz)
    for kw in (dict(friction_law="power", friction_exponent=0.2, friction_pref=2e4),
               dict(friction_law="linear", shear_strength=5e3, shear_slope=0.8)):
        r = solve(indenter="sphere", force=0.5, mu=1.0, tol=1e-2, **kw)
        assert np.sum(r.base_sigma_xz) == pytest.approx(np.sum(r.shear), rel=1e-10)
        assert np.sum(r.base_sigma_yz) == pytest.approx(0.0, abs=1e-10 * np.sum(r.shear))
        assert r.summary()["Q_over_P"] == pytest.approx(np.sum(r.shear) / np.sum(r.pressure)
                                                        + r.summary()["deformation_friction"])
        assert r.summary()["friction_law"] == kw["friction_law"]
    soft = solve(indenter="sphere", force=0.5, mu=1.0, tol=1e-2, interface_compliance=1e-10)
    assert soft.summary()["contact_radius_m"] > base.summary()["contact_radius_m"]


def test_three_d_cli_takes_the_laws_and_refuses_the_exponential_interface(capsys):
    assert main(["solve", "--indenter", "sphere", "--force", "0.5", "--tol", "1e-2", "--json",
                 "--friction-law", "power", "--friction-pref", "2e4",
                 "--friction-exponent", "0.1"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["friction_law"] == "power" and rec["Q_over_P"] - rec["deformation_friction"] < rec["mu"]
    assert main(["solve", "--indenter", "sphere", "--interface-law", "exponential",
                 "--interface-pressure", "1e5", "--interface-length", "1e-6"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "line indenter only" in err
