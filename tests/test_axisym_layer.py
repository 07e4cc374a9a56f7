"""Tests of the axisymmetric sphere-on-film reference (spectral_contact.reference.axisym_layer).

References independent of the Fredholm solution: closed forms (Hertz on the incompressible
half-space, the first layer correction through kappa0 = Int (F0 - 1) dk by scipy's quad, the
thin-film limit), global equilibrium by adaptive quadrature, and the 2D periodic-grid compliance
and base transfer of physics.film.Film applied to the reference pressure.
"""
import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import j0

from spectral_contact.errors import InputError
from spectral_contact.numerics.abel_kernels import gauss_legendre, k_rule
from spectral_contact.numerics.fft import get_rfft
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.film import Film
from spectral_contact.physics.transfer import F0_minus_1, transfer_functions
from spectral_contact.reference import axisym_layer as ax
from spectral_contact.reference.axisym_layer import (
    KAPPA0,
    hertz_sphere,
    sphere_on_layer,
    sphere_with_radius,
    thin_film_sphere,
    unit_scales,
)


def hertz_load(a):
    return 32.0 * a**3 / 3.0


@pytest.fixture(scope="module")
def contacts():
    return {a: sphere_with_radius(a) for a in (0.3, 1.0, 3.0, 5.0)}


# --- closed-form limits ----------------------------------------------------------------------
def test_kappa0_against_quad():
    ref, err = quad(lambda k: float(F0_minus_1(np.array([k]))[0]), 0.0, np.inf,
                    epsabs=1e-14, epsrel=1e-13)
    assert abs(KAPPA0 - ref) < 1e-12
    assert KAPPA0 == pytest.approx(-1.7702167733659, abs=1e-12)


def test_hertz_limit_small_contact():
    """a -> 0: a and p_max are Hertz's to O(a^3) (1e-6 at a = 0.01); d carries the O(a) layer
    correction kappa0 P/(4 pi), beyond which it is Hertz's to O(a^3) as well."""
    dev = {}
    for aH in (0.01, 0.02):
        P = hertz_load(aH)
        c = sphere_on_layer(P)
        H = hertz_sphere(P)
        assert H["a"] == pytest.approx(aH, rel=1e-14)
        d_corr = H["indentation"] + KAPPA0 * P / (4.0 * math.pi)
        dev[aH] = np.array([c.a / H["a"] - 1.0, c.max_pressure / H["max_pressure"] - 1.0,
                            c.indentation / d_corr - 1.0])
        # p(r) is the Hertz profile
        r = np.linspace(0.0, aH, 9)[:-1]
        ph = H["max_pressure"] * np.sqrt(1.0 - (r / H["a"]) ** 2)
        assert np.max(np.abs(c.pressure(r) - ph)) < 3e-6 * H["max_pressure"] * (aH / 0.01) ** 3
    assert np.all(np.abs(dev[0.01]) < 1.2e-6), dev[0.01]
    # the uncorrected indentation is off by -4 kappa0 a/(3 pi) ~ 7.5e-3: the correction is real
    c = sphere_on_layer(hertz_load(0.01))
    assert c.indentation / (2e-4) - 1.0 == pytest.approx(4.0 * KAPPA0 * 0.01 / (3.0 * math.pi),
                                                         rel=1e-3)
    # deviations are O(a^3): doubling a multiplies them by 8
    ratio = dev[0.02] / dev[0.01]
    assert np.all((ratio > 7.0) & (ratio < 9.0)), ratio


def test_load_a3_coefficient():
    """Next order as a -> 0: K(t, s) = (2/pi)[kappa0 - kappa2 (t^2 + s^2)/2 + ...] with
    kappa2 = Int (F0 - 1) k^2 dk changes the t^2 coefficient of g, so that at fixed a
    P/P_Hertz - 1 = -(2 kappa2/(3 pi)) a^3 + O(a^5) (kappa2 by scipy's quad: 0.81298 a^3)."""
    kappa2 = quad(lambda k: float(F0_minus_1(np.array([k]))[0]) * k * k, 0.0, np.inf,
                  epsabs=1e-14, epsrel=1e-13)[0]
    coef = -2.0 * kappa2 / (3.0 * math.pi)
    for a in (0.01, 0.02):
        c = sphere_with_radius(a)
        assert (c.load / hertz_load(a) - 1.0) / a**3 == pytest.approx(coef, rel=2e-3)


def test_base_stress_point_load_limit():
    """a -> 0: sigma_zz(0, 0) = -(P/2pi) [Int A k dk - (a^2/10) Int A k^3 dk] + O(a^4)
    (second moment of the Hertz pressure <r^2> = 2a^2/5), the moments by scipy's quad."""
    def A(k):
        return float(transfer_functions(np.array([k]))[2][0])

    m1 = quad(lambda k: A(k) * k, 0.0, np.inf, epsabs=1e-14, epsrel=1e-13)[0]
    m3 = quad(lambda k: A(k) * k**3, 0.0, np.inf, epsabs=1e-14, epsrel=1e-13)[0]
    dev = {}
    for a in (0.02, 0.05):
        c = sphere_with_radius(a)
        pred = -(c.load / (2.0 * math.pi)) * (m1 - a * a / 10.0 * m3)
        dev[a] = float(c.base_sigma_zz(np.array([0.0]))[0]) / pred - 1.0
    assert abs(dev[0.05]) < 1.5e-5
    assert 30.0 < dev[0.05] / dev[0.02] < 50.0   # O(a^4): 2.5^4 = 39


def test_hertz_constants_in_si():
    """The dimensionless Hertz formulas are the SI ones (E* = 4E/3) in the package's units."""
    E, R, h, F = 2.4e6, 0.01, 1e-4, 1e-3
    u = unit_scales(E, R, h)
    P = F / u["force"]
    H = hertz_sphere(P)
    Es = 4.0 * E / 3.0
    a_si = (3.0 * F * R / (4.0 * Es)) ** (1.0 / 3.0)
    assert H["a"] * u["length"] == pytest.approx(a_si, rel=1e-13)
    assert H["indentation"] * u["displacement"] == pytest.approx(a_si**2 / R, rel=1e-13)
    assert H["max_pressure"] * u["stress"] == pytest.approx(3 * F / (2 * math.pi * a_si**2),
                                                            rel=1e-13)
    # a tiny contact (a = 0.01 h) reported in SI is Hertz's: F = 4 E* a^3/(3R), p0 = 2 E* a/(pi R)
    c = sphere_on_layer(hertz_load(0.01))
    si = c.to_si(E, R, h)
    a_si = 0.01 * h
    assert si["contact_radius_m"] == pytest.approx(a_si, rel=2e-6)
    assert si["force_N"] == pytest.approx(4 * (4 * E / 3) * a_si**3 / (3 * R), rel=1e-12)
    assert si["max_pressure_Pa"] == pytest.approx(2 * (4 * E / 3) * a_si / (math.pi * R), rel=2e-6)


# --- equilibrium ---------------------------------------------------------------------------
@pytest.mark.parametrize("a", [0.3, 1.0, 3.0, 5.0])
def test_equilibrium(contacts, a):
    c = contacts[a]
    assert c.pressure_integral() == pytest.approx(c.load, rel=1e-12)
    # adaptive quadrature of the pressure callable (independent of the internal rule)
    val, _ = quad(lambda r: 2.0 * math.pi * r * float(c.pressure(np.array([r]))[0]), 0.0, c.a,
                  epsabs=0.0, epsrel=1e-12, limit=200)
    assert val == pytest.approx(c.load, rel=1e-10)
    p = c.pressure(np.linspace(0.0, 1.2 * a, 301))
    assert p.min() >= 0.0 and p.max() == pytest.approx(c.max_pressure, rel=1e-10)
    assert np.all(p[251:] == 0.0)


@pytest.mark.parametrize("a", [0.3, 1.0, 3.0])
def test_base_stress_integral(contacts, a):
    """Int sigma_zz(r, 0) 2 pi r dr = -P (the kernels decay like exp(-0.739 r): R = a + 50)."""
    c = contacts[a]
    edges = np.arange(0.0, a + 50.0 + 1e-9, 1.0)
    r = np.concatenate([gauss_legendre(20, lo, hi)[0] for lo, hi in zip(edges[:-1], edges[1:])])
    w = np.concatenate([gauss_legendre(20, lo, hi)[1] for lo, hi in zip(edges[:-1], edges[1:])])
    s = c.base_sigma_zz(r)
    assert 2.0 * math.pi * float(w @ (s * r)) == pytest.approx(-c.load, rel=1e-9)
    assert s[0] < 0.0


# --- convergence ---------------------------------------------------------------------------
@pytest.mark.parametrize("a", [0.05, 1.0, 3.0, 5.0])
def test_converged_to_1e8(a):
    P = ax._Level(a, 120).P
    c = sphere_on_layer(P, tol=1e-10)
    ref = ax._Level(c.a, 2 * c.nodes)
    true = max(abs(c.indentation / ref.d - 1.0), abs(c.max_pressure / ref.max_pressure() - 1.0),
               abs(c.load / ref.P - 1.0))
    assert abs(c.a / a - 1.0) < 1e-10
    assert true < 1e-10 and c.error_estimate < 1e-10
    assert true < max(10.0 * c.error_estimate, 1e-12)
    # a coarse level is measurably worse: the node-count control is not idle
    coarse = ax._Level(a, 8)
    if a >= 3.0:
        assert abs(coarse.d / ref.d - 1.0) > 1e-8


def test_tolerance_loose_is_cheaper():
    P = ax._Level(5.0, 120).P
    tight, loose = sphere_on_layer(P, tol=1e-12), sphere_on_layer(P, tol=1e-4)
    assert loose.nodes <= tight.nodes
    assert loose.a == pytest.approx(tight.a, rel=1e-4)


# --- independent check on a 2D periodic grid -----------------------------------------------
def _grid_pressure(c, n, margin=10.0):
    """The reference pressure sampled on an n x n periodic grid centred on the apex."""
    L = 2.0 * c.a + 2.0 * margin
    grid = Grid.centered((n, n), (L, L))
    X, Y = grid.coordinates()
    R = np.sqrt(X**2 + Y**2)
    return grid, R, c.pressure(R)


def _grid_sinking(c, n, margin=10.0):
    """w = H p on an n x n periodic grid (Film's 2D compliance) at the nodes with r < a + 2.

    w_plain: the sampled p on the grid as it is (brute force; the sqrt edge limits it).
    w_split: the sqrt edge handled in closed form, p = c_e sqrt(a^2 - r^2) + (p - that): the
    first part's sinking is the Hertz half-space one (closed form, E* = 4 in these units) plus
    (1/2) Int (F0 - 1) P~_e(k) J0(kr) dk with its closed-form Hankel transform P~_e; the remainder
    (~ (a^2 - r^2)^1.5) goes through the grid.  Returns (r, w_plain, w_split)."""
    a = c.a
    grid, R, p = _grid_pressure(c, n, margin)
    ce = float(c._q(np.array(a * a), exact=True))  # Q(a^2) = lim p / sqrt(a^2 - r^2) at r = a
    pe = ce * np.sqrt(np.maximum(a * a - R**2, 0.0))
    fft = get_rfft(grid.shape)
    H = Film().surface_compliance(grid.direction, grid.kmag, 0.0)
    near = (R < a + 2.0).ravel()
    w_plain = fft.backward(H * fft.forward(p)).ravel()[near]
    w_rest = fft.backward(H * fft.forward(p - pe)).ravel()[near]
    r = R.ravel()[near]
    rout = np.maximum(r, a)
    w_hs = np.where(r < a, math.pi * ce * (2 * a * a - r**2) / 16.0,
                    ce / 8.0 * ((2 * a * a - rout**2) * np.arcsin(a / rout)
                                + a * np.sqrt(rout**2 - a * a)))
    k, wk = k_rule(26.0, 2.0 * a + 2.0)
    Pe = ce * (np.sin(k * a) - k * a * np.cos(k * a)) / k**3
    w_corr = 0.5 * (j0(np.multiply.outer(r, k)) @ (wk * F0_minus_1(k) * Pe))
    return r, w_plain, w_rest + w_hs + w_corr


def test_grid_sinking_matches_contact_condition():
    c = sphere_with_radius(1.0)
    res = {}
    for n in (256, 512):
        r, w_plain, w_split = _grid_sinking(c, n)
        gap_split = w_split - (c.indentation - r**2)   # gap = w - d + r^2: 0 in, >= 0 out
        gap_plain = w_plain - (c.indentation - r**2)
        inside = r < c.a
        res[n] = np.max(np.abs(gap_split[inside])) / c.indentation
        if n == 512:
            # brute force (sampled p, no closed form): the sqrt edge limits it to ~dx^0.6
            assert np.max(np.abs(gap_plain[inside])) < 4e-3 * c.indentation
            assert abs(gap_plain[np.argmin(r)]) < 1e-4 * c.indentation
            ring = r > c.a
            assert gap_split[ring].min() > -1e-5 * c.indentation
            order = np.argsort(r[ring])
            assert np.all(np.diff(gap_split[ring][order]) > -1e-5)   # opens outward
            assert gap_split[ring][order][-1] > 0.5                  # and is not zero
            # the reference's own sinking outside the contact agrees with the grid's
            sel = np.flatnonzero(ring)[::7]
            assert np.max(np.abs(c.surface_sinking(r[sel]) - w_split[sel])) < 2e-5 * c.indentation
    assert res[512] < 1.5e-5, res
    assert res[256] / res[512] > 2.5, res   # converges with the grid (~dx^2.5)


def test_grid_base_stress_matches():
    """Film.base_stresses on the grid: brute force (sampled p) to the sqrt edge's aliasing, and,
    with the edge part c_e sqrt(a^2 - r^2) carried by its closed-form Hankel transform, to ~1e-7."""
    c = sphere_with_radius(1.0)
    a, n = c.a, 512
    grid, R, p = _grid_pressure(c, n)
    fft = get_rfft(grid.shape)
    film = Film()
    szz, _ = film.base_stresses(fft, grid, -p, (0.0 * p, 0.0 * p))
    x = grid.axes[0]
    assert abs(grid.axes[1][n // 2]) < 1e-12
    ref = c.base_sigma_zz(np.abs(x))
    scale = np.max(np.abs(ref))
    assert np.max(np.abs(szz[:, n // 2] - ref)) < 1.5e-4 * scale
    ce = float(c._q(np.array(a * a), exact=True))
    pe = ce * np.sqrt(np.maximum(a * a - R**2, 0.0))
    rest, _ = film.base_stresses(fft, grid, -(p - pe), (0.0 * p, 0.0 * p))
    k, wk = k_rule(46.0, 2.0 * a + float(np.max(np.abs(x))))
    A = transfer_functions(k)[2]
    Pe = ce * (np.sin(k * a) - k * a * np.cos(k * a)) / k**3
    s_e = -(j0(np.multiply.outer(np.abs(x), k)) @ (wk * A * k * Pe))
    err = np.max(np.abs(rest[:, n // 2] + s_e - ref))
    assert err < 1e-6 * scale, err / scale


# --- physics of the solution -----------------------------------------------------------------
def test_monotonic_in_load():
    loads = np.geomspace(1e-3, 3e4, 9)
    cs = [sphere_on_layer(P, tol=1e-8) for P in loads]
    for key in ("a", "indentation", "max_pressure"):
        v = np.array([getattr(c, key) for c in cs])
        assert np.all(np.diff(v) > 0.0), key
    for P, c in zip(loads, cs):   # a below both limits: the film is stiffer than either
        assert c.a < min(hertz_sphere(P)["a"], thin_film_sphere(P)["a"])
        assert c.load == pytest.approx(P, rel=1e-13)


def test_thin_film_limit_approached(contacts):
    """a >> h: lubrication (w = -(1/3) lap p) gives p = (3/16)(a^2 - r^2)^2, d = a^2/2,
    P = pi a^6/16.  Deviations shrink with a; the contact radius trails the thin-film one by a
    nearly constant edge layer (~1.3-1.4 h)."""
    devs = []
    for a in (1.0, 3.0, 5.0):
        c = contacts[a]
        T = thin_film_sphere(c.load)
        devs.append([T["a"] / c.a - 1.0, c.indentation / (0.5 * c.a**2) - 1.0,
                     c.max_pressure / (3.0 * c.a**4 / 16.0) - 1.0])
        if a >= 3.0:
            assert 1.2 < T["a"] - c.a < 1.5
    devs = np.array(devs)
    assert np.all(devs > 0.0)
    assert np.all(np.diff(devs, axis=0) < 0.0)
    # and at a = 5 the base stress follows the gradient expansion of A(k) = 1 - k^2/2 + 7k^4/8:
    # sigma_zz(r, 0) ~ -(p + lap p / 2 + 7 lap^2 p / 8), lap^2 p ~ 12 (thin-film shape)
    c = contacts[5.0]
    r, h = np.array([0.0, 1.0, 2.0, 3.0]), 1e-3
    pp = (c.pressure(r + h) - 2.0 * c.pressure(r) + c.pressure(np.abs(r - h))) / h**2
    p1 = (c.pressure(r + h) - c.pressure(np.abs(r - h))) / (2.0 * h)
    lap = np.where(r > 0, pp + p1 / np.maximum(r, 1e-300), 2.0 * pp)
    s = c.base_sigma_zz(r)
    assert np.all(np.abs(s / -c.pressure(r) - 1.0) > 0.05)     # not local yet ...
    assert np.allclose(s, -(c.pressure(r) + 0.5 * lap + 0.875 * 12.0), rtol=5e-3)


@pytest.mark.parametrize("a", [0.05, 1.0, 3.0, 5.0])
def test_forward_sinking_undoes_the_abel_inversion(contacts, a):
    """w(r) from the forward (half-space Abel + layer Hankel) formula is d - r^2 in the contact
    to round-off, and the gap opens monotonically outside."""
    c = contacts[a] if a in contacts else sphere_with_radius(a)
    r = np.linspace(0.0, a, 13)
    assert np.max(np.abs(c.surface_sinking(r) - (c.indentation - r**2))) < 1e-11 * c.indentation
    ro = c.a + np.linspace(0.0, 3.0, 13)
    gap = c.surface_sinking(ro) - c.indentation + ro**2
    assert abs(gap[0]) < 1e-11 * c.indentation and np.all(np.diff(gap) > 0.0)


def test_pressure_interpolant_is_exact(contacts):
    c = contacts[3.0]
    # base stress on many points (a 2D grid): the piecewise interpolant is the direct sum
    r = np.random.default_rng(2).uniform(0.0, 9.0, 600)
    s_fast, s_direct = c.base_sigma_zz(r), c._base_sigma_zz_direct(r)
    assert np.max(np.abs(s_fast - s_direct)) < 1e-12 * np.max(np.abs(s_direct))
    r = np.random.default_rng(1).uniform(0.0, c.a, 25)
    assert np.max(np.abs(c.pressure(r) - c.pressure_exact(r))) < 1e-11 * c.max_pressure
    assert c.pressure_hankel(np.array([0.0]))[0] == pytest.approx(c.load / (2 * math.pi),
                                                                  rel=1e-12)


@pytest.mark.parametrize("P,tol", [(0.0, 1e-8), (-1.0, 1e-8), (float("nan"), 1e-8),
                                   (1.0, 0.0), (1.0, 0.5), ("x", 1e-8), (1e-20, 1e-8),
                                   (1e12, 1e-8)])
def test_bad_input(P, tol):
    with pytest.raises(InputError):
        sphere_on_layer(P, tol)


def test_bad_radius():
    for a in (0.0, -1.0, 100.0, float("inf")):
        with pytest.raises(InputError):
            sphere_with_radius(a)
