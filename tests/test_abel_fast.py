"""The Abel method's fast paths (issue 13) against their direct forms and main's numbers.

Direct forms: Bessel functions and cosines/sines evaluated at every quadrature node (what the
interpolated and panel-factorised evaluations replace); numbers: the Abel results at tol 1e-8
as main computed them before the speed-up (golden-section peak, per-node trig and Bessel)."""
import numpy as np
import pytest
from scipy.special import j0, j1

from spectral_contact import solve
from spectral_contact.numerics.abel_kernels import (
    KMAX_M,
    KMAX_Z,
    bessel_on_rule,
    cos_sin_sums,
    film_on_rule,
    k_rule,
)
from spectral_contact.physics.transfer import F0_minus_1, transfer_functions


@pytest.mark.parametrize("kmax,omega,tmax", [(KMAX_M, 2.5, 1.25), (KMAX_M, 0.5, 0.2),
                                             (KMAX_Z, 11.3, 1.25), (KMAX_Z, 30.0, 12.0),
                                             (KMAX_M, 40.0, 20.0)])
def test_bessel_on_rule_equals_direct_evaluation(kmax, omega, tmax):
    rule = k_rule(kmax, omega)
    t = np.linspace(0.0, tmax, 23)
    kt = np.outer(rule[0], t)
    J0, J1 = bessel_on_rule(t, rule)
    assert J0.shape == kt.shape
    np.testing.assert_allclose(J0, j0(kt), rtol=0, atol=1.5e-14)
    np.testing.assert_allclose(J1, j1(kt), rtol=0, atol=1.5e-14)
    v0, v1 = np.cos(t), np.sin(3 * t)
    c, s = bessel_on_rule(t, rule, v0, v1)
    np.testing.assert_allclose(c, j0(kt) @ v0, rtol=0, atol=5e-14)
    np.testing.assert_allclose(s, j1(kt) @ v1, rtol=0, atol=5e-14)


def test_cos_sin_sums_equal_direct_sums():
    rng = np.random.default_rng(2)
    for omega, xmax in ((11.3, 10.0), (3.0, 2.0), (80.0, 70.0)):
        rule = k_rule(KMAX_Z, omega)
        k = rule[0]
        x = np.concatenate([np.linspace(-xmax, xmax, 1500), [0.0]])  # > one chunk
        pairs = [(rng.standard_normal(k.size) * np.exp(-k), rng.standard_normal(k.size)),
                 (np.exp(-k), -k * np.exp(-k))]
        got = cos_sin_sums(x, rule, pairs)
        for (gc, gs), g in zip(pairs, got):
            ref = np.cos(np.outer(x, k)) @ gc + np.sin(np.outer(x, k)) @ gs
            scale = np.sum(np.abs(gc)) + np.sum(np.abs(gs))
            assert np.max(np.abs(g - ref)) < 1e-14 * max(1.0, omega) * scale


def test_film_tabulated_on_the_rule_is_the_film():
    rule = k_rule(KMAX_M, 3.0)
    F0m1, F1, A, B, C = film_on_rule(rule)
    _, F1r, Ar, Br, Cr = transfer_functions(np.array(rule[0]))
    assert np.array_equal(F0m1, F0_minus_1(np.array(rule[0])))
    for a, b in ((F1, F1r), (A, Ar), (B, Br), (C, Cr)):
        assert np.array_equal(a, b)
    assert k_rule(KMAX_M, 3.0) is rule  # cached


def test_abel_results_unchanged_from_main_at_tol_1e8():
    r = solve(method="abel", tol=1e-8)
    # main at 2ff6ba6 (before the fast paths)
    assert r.half_width == pytest.approx(1.2450466391835109, rel=1e-12)
    assert r.center == pytest.approx(0.5977637234028055, rel=1e-12)
    assert r.indentation == pytest.approx(1.6729098448013682, rel=1e-12)
    assert r.max_pressure == pytest.approx(10.560060429610433, rel=1e-12)
    # main's golden-section search left x_max ~2e-8 a off (p is flat there to round-off)
    assert r.max_pressure_x == pytest.approx(1.0435940105458794, abs=5e-8)


@pytest.mark.parametrize("model,load", [("exact", 380.0), ("goodman", 200.0)])
def test_symmetric_peak_found_at_the_centre(model, load):
    """mu = 0 (or Goodman): p is even about the contact centre, so is its maximum; main's
    bracket search stopped at 1e-8 - 3e-8 a from it."""
    r = solve(method="abel", model=model, load=load, mu=0.0, tol=1e-6)
    assert abs(r.max_pressure_x - r.center) < 1e-10 * r.half_width


@pytest.mark.parametrize("load,mu", [(5.0, -10.0), (200.0, 2.0), (1000.0, 10.0), (5000.0, 0.5)])
def test_peak_is_the_maximum_of_a_dense_sampling(load, mu):
    from spectral_contact.physics.scene import Scene
    from spectral_contact.solvers.abel import abel_fields

    s = abel_fields(Scene(load=load, mu=mu), mu, 20)
    sol = s.sol
    dense = sol.pressure(np.linspace(-sol.a, sol.a, 20001)[1:-1]).max()
    assert dense <= s.pmax * (1 + 1e-14)
    pm, xm = sol.peak(s.xmax + 0.01 * sol.a)  # Newton steps from a previous level's peak
    assert xm == pytest.approx(s.xmax, abs=1e-9 * sol.a) and pm == pytest.approx(s.pmax, rel=1e-13)
