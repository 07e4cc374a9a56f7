"""Tests of the Abel / Nystrom solver (spectral_contact.solvers.abel).

References are independent of the solver's own outputs: scipy.integrate.quad for the kernels,
closed forms (Hertz), global equilibrium, symmetry, and physics.md's Fourier-domain compliance
and base transfer applied to the Abel pressure on a periodic grid.
"""
import math
import warnings

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import jv

from spectral_contact.errors import ConvergenceError, InputError
from spectral_contact.numerics.abel_kernels import (
    aposteriori_kernels,
    gauss_legendre,
    legendre_log_weights,
    m_kernels,
    z_kernels,
)
from spectral_contact.physics.scene import Scene
from spectral_contact.physics.transfer import F0_minus_1, transfer_functions
from spectral_contact.solvers import abel as abel_mod
from spectral_contact.solvers.abel import AbelAccuracyWarning, abel_fields, solve_abel

from .conftest import scene_for

PAPER = Scene()


def _tf(k):
    F0, F1, A, B, C = transfer_functions(np.array([k]))
    return F0[0], F1[0], A[0], B[0], C[0]


def _quad(f, kmax=60.0, pieces=120):
    edges = np.linspace(0.0, kmax, pieces + 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return sum(quad(f, lo, hi, epsabs=1e-15, epsrel=1e-13, limit=100)[0]
                   for lo, hi in zip(edges[:-1], edges[1:]))


# --- kernels ---------------------------------------------------------------------------------
@pytest.mark.parametrize("x,t", [(0.37, 1.9), (4.1, 0.08)])
def test_m_kernels_against_quad(x, t):
    M00, M01, M10, M11 = (m[0, 0] for m in m_kernels([x], [t]))
    f0m1 = lambda k: F0_minus_1(np.array([k]))[0]
    ref = {
        "M00": x * _quad(lambda k: k * f0m1(k) * jv(0, k * t) * jv(0, k * x)),
        "M01": -_quad(lambda k: k * _tf(k)[1] * jv(0, k * t) * jv(1, k * x)),
        "M10": x * t * _quad(lambda k: k * _tf(k)[1] * jv(1, k * t) * jv(0, k * x)),
        "M11": -t * _quad(lambda k: k * f0m1(k) * jv(1, k * t) * jv(1, k * x)),
    }
    got = {"M00": M00, "M01": M01, "M10": M10, "M11": M11}
    for name in ref:
        assert abs(got[name] - ref[name]) < 1e-12, (name, got[name], ref[name])


@pytest.mark.parametrize("x,t", [(-2.3, 0.9), (7.5, 3.2)])
def test_z_kernels_against_quad(x, t):
    Z = z_kernels([x], [t])[:, 0, 0]
    A = lambda k: _tf(k)[2]
    B = lambda k: _tf(k)[3]
    C = lambda k: _tf(k)[4]
    ref = [
        _quad(lambda k: A(k) * math.cos(k * x) * jv(0, k * t)),
        _quad(lambda k: B(k) * math.cos(k * x) * jv(1, k * t)),
        _quad(lambda k: B(k) * math.sin(k * x) * jv(0, k * t)),
        _quad(lambda k: A(k) * math.sin(k * x) * jv(1, k * t)),
        _quad(lambda k: C(k) * math.cos(k * x) * jv(0, k * t)),
        _quad(lambda k: C(k) * math.sin(k * x) * jv(1, k * t)),
    ]
    np.testing.assert_allclose(Z, ref, rtol=0, atol=1e-12)


def test_aposteriori_kernels_against_quad():
    t = 0.6
    K = aposteriori_kernels([t])
    f0m1 = lambda k: F0_minus_1(np.array([k]))[0]
    ref = {
        "K_F1J0": _quad(lambda k: _tf(k)[1] * jv(0, k * t)),
        "K_F0m1J1": _quad(lambda k: f0m1(k) * jv(1, k * t)),
        "L_rem": _quad(lambda k: (f0m1(k) + math.exp(-2 * k)) / (2 * k) * jv(0, k * t)),
        "K_F1J1_2k": _quad(lambda k: _tf(k)[1] / (2 * k) * jv(1, k * t)),
    }
    for name, v in ref.items():
        assert abs(K[name][0] - v) < 1e-12, name
    # the analytic split of the singular part: Int (1 - e^{-2k}) J0(kt)/k dk = asinh(2/t)
    split = _quad(lambda k: -math.expm1(-2 * k) / k * jv(0, k * t), kmax=400.0, pieces=800)
    assert abs(split - math.asinh(2.0 / t)) < 2e-3  # slowly convergent tail: loose check only


def test_log_product_integration_weights():
    n = 14
    s, _ = gauss_legendre(n)
    W = legendre_log_weights(n)
    f = lambda u: np.cos(1.3 * u) * np.exp(0.4 * u)
    ref = quad(lambda u: f(u) * math.log((1 + u) / 2), -1, 1, points=[-1], limit=200)[0]
    assert abs(W @ f(s) - ref) < 1e-12


# --- solver ----------------------------------------------------------------------------------
def _quantities(r):
    return np.array([r.sol.a, r.x0, r.inv_alpha, r.pmax])


def test_spectral_convergence_in_nodes():
    ref = _quantities(abel_fields(PAPER, PAPER.mu, 40))
    errs = []
    for n in (6, 8, 10, 12, 16):
        q = _quantities(abel_fields(PAPER, PAPER.mu, n))
        errs.append(np.max(np.abs(q - ref) / np.abs(ref)))
    # geometric decay: at least two decades per four nodes, down to ~1e-11 at 16 nodes
    assert errs[0] < 1e-3
    assert errs[-1] < 1e-11
    for e_small, e_big in zip(errs[1:], errs[:-1]):
        assert e_small < 0.3 * e_big or e_small < 1e-12


def test_error_estimate_is_honest():
    r = solve_abel(PAPER, tol=1e-4)
    ref = abel_fields(PAPER, PAPER.mu, 40)
    true = max(abs(r.half_width - ref.sol.a) / ref.sol.a,
               abs(r.center + ref.x0) / ref.sol.a,
               abs(r.indentation - ref.inv_alpha) / ref.inv_alpha,
               abs(r.max_pressure - ref.pmax) / ref.pmax)
    assert r.error_estimate <= 1e-4
    assert true <= r.error_estimate


def test_load_matched_to_1e_12():
    for mu in (0.0, 2.0, -7.0):
        r = abel_fields(PAPER, mu, 16)
        assert abs(r.sol.load / PAPER.P - 1) < 1e-12
        assert r.residual < 1e-12
        # the load carried by the pressure profile itself (x = a sin theta: smooth integrand)
        th, wth = gauss_legendre(80, -math.pi / 2, math.pi / 2)
        a = r.sol.a
        Pp = wth @ (r.sol.pressure(a * np.sin(th)) * a * np.cos(th))
        assert abs(Pp / PAPER.P - 1) < 1e-11
    res = solve_abel(PAPER)
    assert res.residual < 1e-12


@pytest.mark.parametrize("a_hertz", [0.01, 0.03])
def test_hertz_limit(a_hertz):
    r = solve_abel(scene_for(a_hertz, 1.0), tol=1e-8)
    # the film correction is O((a/h)^2): measured ~0.5 (a/h)^2 on a, ~1 (a/h)^2 on p/4a
    assert abs(r.half_width / a_hertz - 1) < 1.0 * a_hertz**2
    assert abs(r.max_pressure / (4 * a_hertz) - 1) < 1.0 * a_hertz**2
    assert abs(r.center) < 0.5 * r.half_width**2
    # the pressure profile itself against 4 sqrt(a^2 - x^2) (on its own window)
    xs = r.center + r.half_width * np.linspace(-0.99, 0.99, 41)
    rr = solve_abel(scene_for(a_hertz, 1.0), tol=1e-8, x=xs)
    hertz = 4.0 * np.sqrt(np.maximum(r.half_width**2 - (xs - r.center) ** 2, 0.0))
    assert np.max(np.abs(rr.pressure - hertz)) < 4.0 * a_hertz**2 * (4 * a_hertz)


@pytest.mark.parametrize("mu", [0.0, 2.0, -3.0])
def test_equilibrium(mu):
    s = PAPER.with_(mu=mu)
    x = np.linspace(-30.0, 30.0, 1201)  # wide: base stresses decay like exp(-0.75 |x|/h)
    r = solve_abel(s, x=x)
    P = s.P
    assert abs(np.trapezoid(r.base_sigma_zz, x) / -P - 1) < 1e-7
    assert abs(np.trapezoid(r.base_sigma_xz, x) - mu * P) < 1e-7 * P
    # default grid (contact +- 8 h): equilibrium to the accuracy of its extent
    rd = solve_abel(s)
    assert abs(np.trapezoid(rd.base_sigma_zz, rd.x) / -P - 1) < 3e-3
    assert abs(np.trapezoid(rd.base_sigma_xz, rd.x) - mu * P) < 1e-2 * P
    assert rd.x[0] < rd.center - rd.half_width - 7.9 and rd.x[-1] > rd.center + rd.half_width + 7.9


def test_mirror_symmetry():
    x = np.linspace(-6.0, 6.0, 241)
    rp = solve_abel(PAPER.with_(mu=2.0), x=x)
    rm = solve_abel(PAPER.with_(mu=-2.0), x=-x)
    assert abs(rp.half_width - rm.half_width) < 1e-12
    assert abs(rp.center + rm.center) < 1e-12
    assert abs(rp.indentation - rm.indentation) < 1e-11
    assert abs(rp.max_pressure_x + rm.max_pressure_x) < 1e-7
    np.testing.assert_allclose(rm.pressure, rp.pressure, atol=1e-11)
    np.testing.assert_allclose(rm.base_sigma_zz, rp.base_sigma_zz, atol=1e-11)
    np.testing.assert_allclose(rm.base_sigma_xz, -rp.base_sigma_xz, atol=1e-11)


def test_friction_moves_contact_and_peak_to_leading_edge():
    r = solve_abel(PAPER.with_(mu=2.0))
    assert r.center > 0.1 * r.half_width
    assert r.max_pressure_x > r.center  # the peak sits ahead of the contact centre
    r0 = solve_abel(PAPER.with_(mu=0.0))
    assert abs(r0.center) < 1e-12 and abs(r0.max_pressure_x) < 1e-6


@pytest.mark.parametrize("mu", [2.0, -1.0])
def test_signs_against_physics_md_fourier_formulas(mu):
    """Abel pressure on a wide periodic grid through physics.md's compliance reproduces the
    indenter in the contact; its base transfer (A, B, C) reproduces the Abel base stresses."""
    s = PAPER.with_(mu=mu)
    L, N = 40.0, 2**14
    x = (np.arange(N) - N // 2) * (L / N)
    near = np.abs(x) < 6.0  # holds the contact; p = 0 elsewhere
    r = solve_abel(s, tol=1e-8, x=x[near])
    p = np.zeros(N)
    p[near] = r.pressure
    k = 2 * np.pi * np.fft.fftfreq(N, L / N)
    F0, F1, A, B, C = transfer_functions(k)
    szz = np.fft.fft(-p)
    sxz = np.fft.fft(mu * p)
    kk = np.where(k == 0, 1.0, np.abs(k))
    G = np.where(k == 0, 0.0, (F0 + 1j * mu * np.sign(k) * F1) / (2 * kk))
    uz = np.real(np.fft.ifft(G * szz))
    indenter = -(r.indentation - x**2)
    inside = np.abs(x - r.center) < 0.98 * r.half_width
    outside = np.abs(x - r.center) > 1.02 * r.half_width
    assert np.max(np.abs(uz - indenter)[inside]) < 2e-4 * r.indentation
    assert np.min((indenter - uz)[outside & (np.abs(x) < 10)]) > 0  # gap open outside
    # the opposite coupling sign is clearly wrong
    Gw = np.where(k == 0, 0.0, (F0 - 1j * mu * np.sign(k) * F1) / (2 * kk))
    uzw = np.real(np.fft.ifft(Gw * szz))
    assert np.max(np.abs(uzw - indenter)[inside]) > 0.1 * r.indentation
    # base stresses (physics.md) at a subset of points
    bzz = np.real(np.fft.ifft(A * szz + 1j * np.sign(k) * B * sxz))
    bxz = np.real(np.fft.ifft(C * sxz + 1j * np.sign(k) * B * szz))
    scale = np.max(np.abs(bzz))  # FFT of a square-root-edged pressure: ~3e-5 relative here
    assert np.max(np.abs(r.base_sigma_zz - bzz[near])) < 6e-5 * scale
    assert np.max(np.abs(r.base_sigma_xz - bxz[near])) < 6e-5 * scale
    bzz_w = np.real(np.fft.ifft(A * szz - 1j * np.sign(k) * B * sxz))
    assert np.max(np.abs(r.base_sigma_zz - bzz_w[near])) > 0.05 * scale


def test_base_stresses_equal_explicit_z_kernel_sums():
    r = abel_fields(PAPER, 2.0, 16)
    sol, mu = r.sol, 2.0
    xp = np.array([-5.0, -1.1, 0.0, 0.4, 2.2, 7.0])
    szz, sxz = sol.base_stresses(xp, mu)
    tf, wf, phif, psif = sol.fine()
    Z1, Z2, Z3, Z4, Z5, Z6 = z_kernels(xp, tf)
    ref_zz = (Z1 + mu * Z3) @ (wf * phif) - (mu * Z2 - Z4) @ (wf * tf * psif)
    ref_xz = -(mu * Z5 + Z3) @ (wf * phif) + (Z2 - mu * Z6) @ (wf * tf * psif)
    np.testing.assert_allclose(szz, ref_zz, atol=1e-12)
    np.testing.assert_allclose(sxz, ref_xz, atol=1e-12)


def test_goodman_window_is_the_frictionless_one():
    g = solve_abel(PAPER, model="goodman")
    e0 = solve_abel(PAPER.with_(mu=0.0), x=g.x)
    assert g.half_width == pytest.approx(e0.half_width, rel=1e-12)
    assert g.center == 0.0 or abs(g.center) < 1e-12
    assert g.indentation == pytest.approx(e0.indentation, rel=1e-12)
    np.testing.assert_allclose(g.pressure, e0.pressure, atol=1e-12)
    P, mu = PAPER.P, PAPER.mu
    x = np.linspace(-30.0, 30.0, 1201)
    gw = solve_abel(PAPER, model="goodman", x=x)
    assert abs(np.trapezoid(gw.base_sigma_zz, x) / -P - 1) < 1e-7
    assert abs(np.trapezoid(gw.base_sigma_xz, x) - mu * P) < 1e-7 * P
    ex = solve_abel(PAPER, model="exact", x=x)
    assert np.max(np.abs(gw.base_sigma_zz - ex.base_sigma_zz)) > 0.05 * P / 10


def test_zero_load_and_result_fields():
    r0 = solve_abel(PAPER.with_(load=0.0))
    assert r0.half_width == 0.0 and np.all(r0.pressure == 0) and np.all(r0.base_sigma_zz == 0)
    r = solve_abel(PAPER)
    assert r.method == "abel" and r.model == "exact"
    assert r.grid_points == r.info["n_nodes"] and r.info["n_nodes_compared"] < r.grid_points
    assert r.domain_length == pytest.approx(r.x[-1] - r.x[0])
    assert r.info["condition_number"] >= 1.0
    assert np.all(r.pressure >= 0)
    assert r.max_pressure == pytest.approx(np.max(r.pressure), rel=1e-3)
    i = int(np.argmax(r.pressure))
    assert abs(r.max_pressure_x - r.x[i]) <= r.x[1] - r.x[0]


def test_input_errors():
    with pytest.raises(InputError):
        solve_abel(PAPER, model="hertz")
    with pytest.raises(InputError):
        solve_abel(PAPER, tol=0.5)
    with pytest.raises(InputError):
        solve_abel(PAPER, n_nodes=3)
    with pytest.raises(InputError):
        solve_abel(PAPER, x=np.array([0.0, np.nan]))


def test_too_wide_contact_raises():
    with pytest.raises(ConvergenceError):
        solve_abel(scene_for(2048.0, 10.0))


def test_ill_conditioning_warns(monkeypatch):
    monkeypatch.setattr(abel_mod, "COND_WARN", 1.5)
    with pytest.warns(AbelAccuracyWarning):
        solve_abel(PAPER)
