"""A compliant interface (issue 14, --interface-compliance): op + c, C -> 0 gives back the rigid
interface, the contact equations with the closure c p, the Winkler limit in SI, one-line errors."""
import json

import numpy as np
import pytest

from spectral_contact import Scene, solve
from spectral_contact.cli.main import main
from spectral_contact.numerics.friction import solve_contact_law
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.film import Film
from spectral_contact.physics.friction import ShearLaw
from spectral_contact.physics.indenters import Cylinder
from spectral_contact.physics.transfer import transfer_functions


def test_zero_compliance_is_the_rigid_interface_bit_for_bit():
    ref = solve(load=200.0, mu=2.0, tol=1e-3)
    r = solve(load=200.0, mu=2.0, tol=1e-3, interface_compliance=0.0)
    for name in ("pressure", "base_sigma_zz", "base_sigma_xz"):
        np.testing.assert_array_equal(getattr(r, name), getattr(ref, name))


def test_small_compliance_tends_to_the_rigid_interface_linearly():
    """On a fixed grid the change from the rigid interface is linear in C: C -> 0 recovers it
    (measured: c = 3.7e-7 moves a, d by ~1e-6 and the edge node's pressure by 2e-5 of p_max)."""
    kw = dict(load=200.0, mu=2.0, grid_points=4096, domain_length=0.05, tol=1e-3)
    ref = solve(**kw)
    d = []
    for C in (1e-15, 1e-14):
        r = solve(interface_compliance=C, **kw)
        d.append(np.array([np.max(np.abs(r.pressure - ref.pressure)) / ref.max_pressure,
                           abs(r.half_width / ref.half_width - 1),
                           abs(r.indentation / ref.indentation - 1)]))
        assert r.scene.interface == pytest.approx(C * r.scene.stress_unit / r.scene.displacement_unit)
    assert np.all(d[0] > 0) and np.all(d[0] < [1e-4, 1e-5, 1e-5])
    np.testing.assert_allclose(d[1] / d[0], 10.0, rtol=0.02)


@pytest.mark.parametrize("law,nu", [(ShearLaw("amontons", mu=2.0), 0.5),
                                    (ShearLaw("amontons", mu=1.0), 0.3),
                                    (ShearLaw("power", mu=2.0, exponent=0.2, pref=3.0), 0.5)])
def test_contact_equations_include_the_closure(law, nu):
    """gap = f - d + H0 p + H1 q + c p: zero on the contact, >= 0 outside (H recomputed here)."""
    g = Grid.centered(1024, 24.0, 0.5)
    c = 0.3
    sol, q, _ = solve_contact_law(g, law, [Cylinder(0.0, 10.0)], film=Film(poisson=nu),
                                  interface=c, accept=1e-8, law_tol=1e-9)
    p = sol.pressure
    k = 2 * np.pi * np.fft.fftfreq(g.n, g.dx)
    film = Film(poisson=nu)
    H = film.surface_compliance((np.sign(k),), np.abs(k), 0.0)
    H1 = film.shear_compliance((np.sign(k),), np.abs(k), (1.0,))
    if nu == 0.5:  # and the incompressible symbol written out once more
        F0 = transfer_functions(np.abs(k))[0]
        np.testing.assert_allclose(H[1:], F0[1:] / (2 * np.abs(k[1:])), rtol=1e-14)
    w = np.fft.ifft(H * np.fft.fft(p) + H1 * np.fft.fft(q)).real
    np.testing.assert_allclose(sol.sinking, w, atol=1e-9 * np.abs(w).max())
    gap = g.x**2 - sol.indentations[0] + w + c * p
    scale = np.abs(w).max()
    assert np.max(np.abs(gap[sol.active])) < 1e-7 * scale
    assert gap[~sol.active].min() > -1e-7 * scale
    assert np.sum(p) * g.dx == pytest.approx(10.0, rel=1e-9)


@pytest.mark.parametrize("C", [2e-8, 1e-7])
def test_soft_interface_tends_to_the_winkler_contact_in_si(C):
    """C >> the film's compliance at the contact's scale: p = (d - x^2/2R)/C, so
    a = (3 P_L R C / 2)^(1/3) and p_max = a^2 / (2 R C)."""
    s = Scene(load=200.0, mu=0.0, interface_compliance=C)
    r = solve(s, tol=1e-3)
    a = (1.5 * s.load * s.radius * C) ** (1 / 3)
    assert r.half_width_m == pytest.approx(a, rel=0.01)
    assert r.max_pressure * s.stress_unit == pytest.approx(a * a / (2 * s.radius * C), rel=0.01)


def test_compliance_widens_the_contact_and_keeps_equilibrium():
    rigid = solve(load=200.0, mu=2.0, tol=1e-3)
    r = solve(load=200.0, mu=2.0, tol=1e-3, interface_compliance=1e-9, poisson=0.45)
    dx = r.x[1] - r.x[0]
    assert r.half_width > rigid.half_width and r.max_pressure < rigid.max_pressure
    assert -np.sum(r.base_sigma_zz) * dx == pytest.approx(r.scene.P, rel=1e-10)
    assert np.sum(r.base_sigma_xz) * dx == pytest.approx(2.0 * r.scene.P, rel=1e-10)


@pytest.mark.parametrize("argv,word", [
    (["--interface-compliance=-1e-9"], "interface compliance"),
    (["--interface-compliance", "nan"], "interface compliance"),
    (["--interface-compliance", "1e-9", "--method", "abel"], "abel"),
    (["--interface-compliance", "1e-9", "--model", "hertz"], "hertz"),
])
def test_cli_refuses_bad_compliance_in_one_line(argv, word, capsys, tmp_path):
    out = tmp_path / "p.csv"
    assert main(["solve", *argv, "--profiles", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and word in err and not out.exists()


def test_cli_json_reports_compliance(capsys):
    assert main(["solve", "--json", "--tol", "1e-3", "--interface-compliance", "1e-9"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["interface_compliance_m_per_Pa"] == 1e-9


# --- exponential interface law ---------------------------------------------------------------
_EXP = dict(load=200.0, mu=2.0, interface_law="exponential", interface_pressure=1e5)


def test_exponential_law_holds_at_every_node():
    """p = p0 exp(-g/lambda) with g = f - d + H p recomputed independently (numpy FFT)."""
    from spectral_contact.numerics.interface import solve_exponential_contact

    g = Grid.centered(2048, 24.0, 0.5)
    for nu, mu, lam in ((0.5, 2.0, 0.1), (0.4, -1.0, 0.01)):
        sol = solve_exponential_contact(g, mu, Cylinder(0.0, 10.0), 10.0, lam,
                                        film=Film(poisson=nu), rtol=1e-10)
        p = sol.pressure
        k = 2 * np.pi * np.fft.fftfreq(g.n, g.dx)
        H = Film(poisson=nu).surface_compliance((np.sign(k),), np.abs(k), mu)
        w = np.fft.ifft(H * np.fft.fft(p)).real
        gap = g.x**2 - sol.indentations[0] + w
        law = 10.0 * np.exp(-gap / lam)
        big = p > 1e-10 * p.max()
        np.testing.assert_allclose(p[big], law[big], rtol=1e-7)
        assert np.all(p > 0) and np.sum(p) * g.dx == pytest.approx(10.0, rel=1e-10)


def test_exponential_p0_only_shifts_the_indentation():
    a = solve(tol=1e-3, interface_length=1e-7, **_EXP)
    b = solve(tol=1e-3, interface_length=1e-7, **(_EXP | {"interface_pressure": 1e6}))
    np.testing.assert_allclose(a.pressure, b.pressure, rtol=1e-6, atol=1e-9 * a.max_pressure)
    # a larger p0 closes the gap less at the same pressure: d falls by lambda ln(10)
    assert a.indentation_m - b.indentation_m == pytest.approx(1e-7 * np.log(10.0), rel=1e-3)


def test_exponential_law_tends_to_the_rigid_interface():
    """lambda -> 0: the window where p >= 1 % p_max tends to the rigid contact's."""
    rigid = solve(load=200.0, mu=2.0, tol=1e-4)
    errs = []
    for lam in (1e-7, 1e-8):
        r = solve(tol=1e-4, interface_length=lam, **_EXP)
        errs.append(abs(r.half_width / rigid.half_width - 1))
        assert r.max_pressure == pytest.approx(rigid.max_pressure, rel=30 * lam / 1.54e-5)
        dx = r.x[1] - r.x[0]
        assert np.sum(r.base_sigma_xz) == pytest.approx(2.0 * np.sum(r.pressure), rel=1e-10)
        assert np.sum(r.pressure) * dx == pytest.approx(r.scene.P, rel=2e-6)  # Newton's accept
        assert "p >= 0.01 p_max" in r.info["width_definition"]
    assert errs[1] < 0.005 and errs[1] < 0.3 * errs[0]


@pytest.mark.parametrize("argv,word", [
    (["--interface-law", "exponential", "--interface-length", "1e-6"], "interface-pressure"),
    (["--interface-law", "exponential", "--interface-pressure", "1e5"], "interface-length"),
    (["--interface-law", "exponential", "--interface-pressure", "0", "--interface-length", "1e-6"],
     "interface-pressure"),
    (["--interface-law", "exponential", "--interface-pressure", "1e5", "--interface-length=-1e-6"],
     "interface-length"),
    (["--interface-pressure", "1e5"], "exponential only"),
    (["--interface-law", "exponential", "--interface-pressure", "1e5", "--interface-length", "1e-6",
      "--interface-compliance", "1e-9"], "linear only"),
    (["--interface-law", "exponential", "--interface-pressure", "1e5", "--interface-length", "1e-6",
      "--friction-law", "power", "--friction-pref", "1e4"], "amontons only"),
    (["--interface-law", "exponential", "--interface-pressure", "1e5", "--interface-length", "1e-6",
      "--method", "abel"], "abel"),
])
def test_cli_refuses_bad_exponential_law_in_one_line(argv, word, capsys, tmp_path):
    out = tmp_path / "p.csv"
    assert main(["solve", *argv, "--profiles", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and word in err and not out.exists()


def test_cli_json_reports_exponential_law(capsys):
    assert main(["solve", "--json", "--tol", "1e-3", "--interface-law", "exponential",
                 "--interface-pressure", "1e5", "--interface-length", "1e-6"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["interface_law"] == "exponential" and rec["interface_length_m"] == 1e-6
