"""The n-dimensional core: grid, transforms, Fourier operators, film symbols, indenters, and the
dimension-free contact solver (issue 9)."""
import pickle
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from spectral_contact import solve
from spectral_contact.numerics import fft as fftmod
from spectral_contact.numerics.contact import solve_contact
from spectral_contact.numerics.grid import Grid, pow2_at_least
from spectral_contact.numerics.operators import FourierOperator
from spectral_contact.physics.film import Film, surface_compliance
from spectral_contact.physics.indenters import Cylinder


def test_grid_layout_matches_numpy_real_transforms():
    g = Grid((6, 8), (3.0, 2.0), (-1.0, 0.5))
    kx, ky = g.wavevector
    assert g.kshape == np.fft.rfftn(np.zeros(g.shape)).shape == (6, 5)
    np.testing.assert_array_equal(kx.ravel(), 2 * np.pi * np.fft.fftfreq(6, 0.5))
    np.testing.assert_array_equal(ky.ravel(), 2 * np.pi * np.fft.rfftfreq(8, 0.25))
    np.testing.assert_allclose(g.kmag, np.hypot(kx, ky), rtol=1e-15)
    assert g.cell == pytest.approx(0.5 * 0.25)
    x, y = g.coordinates()
    assert x.shape == (6, 1) and y.shape == (1, 8) and x[0, 0] == -1.0 and y[0, 1] == 0.75
    nx, ny = g.direction
    np.testing.assert_allclose(nx**2 + ny**2, 1.0)
    assert nx[0, 0] == 1.0 and ny[0, 0] == 0.0  # e_x at k = 0
    one = Grid(8, 4.0)  # 1D from scalars
    assert one.shape == (8,) and one.dx == 0.5 and np.all(one.k >= 0)
    assert pow2_at_least(65, 64) == 128 and pow2_at_least(3, 64) == 64


def test_operator_apply_preconditioner_and_constant():
    g = Grid((16, 12), (4.0, 3.0))
    film = Film()
    op = FourierOperator(g, film.compliance_symbol(0.7))
    rng = np.random.default_rng(1)
    f = rng.standard_normal(g.shape)
    ref = np.fft.irfftn(op.symbol * np.fft.rfftn(f), g.shape, axes=(0, 1))
    np.testing.assert_allclose(op.apply(f), ref, atol=1e-13)
    kc = 2.0
    P = op.preconditioner(kc)
    hi = g.kmag >= kc
    np.testing.assert_allclose(P[hi] * op.symbol[hi], 1.0, rtol=1e-13)
    lo = ~hi
    clipped = film.surface_compliance(g.direction, np.full(g.kshape, kc), 0.7)
    np.testing.assert_allclose(P[lo] * clipped[lo], 1.0, rtol=1e-13)
    shifted = op + 0.25
    np.testing.assert_allclose(shifted.symbol, op.symbol + 0.25)
    np.testing.assert_allclose(shifted.apply(f), op.apply(f) + 0.25 * f, atol=1e-12)


def test_film_symbols_reduce_to_plane_strain_on_a_y_independent_field():
    """A field independent of y only excites k_y = 0, where the 2D symbols are the 1D ones."""
    film = Film()
    g2 = Grid((32, 4), (8.0, 2.0))
    g1 = Grid(32, 8.0)
    # (the Nyquist mode, index 16, is k_x = -16 on the full axis: its odd part is discarded
    # by either inverse transform, so only 0..15 are compared)
    np.testing.assert_allclose(film.surface_compliance(g2.direction, g2.kmag, 1.3)[:16, 0],
                               surface_compliance(g1.k, 1.3)[:16], rtol=1e-14, atol=1e-300)
    rng = np.random.default_rng(2)
    p1 = rng.random(32)
    p2 = np.repeat(p1[:, None], 4, axis=1)
    z1, (x1,) = film.base_stresses(fftmod.get_rfft(g1.shape), g1, -p1, (0.4 * p1,))
    z2, (x2, y2) = film.base_stresses(fftmod.get_rfft(g2.shape), g2, -p2, (0.4 * p2, 0 * p2))
    np.testing.assert_allclose(z2, z1[:, None] + 0 * z2, atol=1e-13)
    np.testing.assert_allclose(x2, x1[:, None] + 0 * x2, atol=1e-13)
    np.testing.assert_allclose(y2, 0.0, atol=1e-13)


def test_film_base_transfer_equilibrium_and_thickness_scaling():
    """k = 0 passes the loads to the base; a film of thickness 2 at k is the unit film at 2k."""
    film = Film(2.0)
    d = (np.array([0.6, 1.0]), np.array([0.8, 0.0]))
    k = np.array([0.5, 0.0])
    zz, (tx, ty) = film.base_transfer(d, k, np.array([1.0, 1.0]), (np.array([0.3, 0.3]),
                                                                   np.array([0.1, 0.1])))
    assert zz[1] == 1.0 and tx[1] == 0.3 and ty[1] == 0.1
    zz1, (tx1, ty1) = Film(1.0).base_transfer(d, 2 * k, np.array([1.0, 1.0]),
                                              (np.array([0.3, 0.3]), np.array([0.1, 0.1])))
    np.testing.assert_allclose([zz[0], tx[0], ty[0]], [zz1[0], tx1[0], ty1[0]], rtol=1e-14)
    assert Film(2.0).decay_rate == pytest.approx(Film().decay_rate / 2)


def test_contact_solver_is_dimension_free():
    """A cylinder on a 2D grid (height independent of y, load P per unit length times L_y)
    gives the plane-strain solution on every row."""
    P, mu = 17.7, 2.0
    g1 = Grid.centered(256, 16.0, 0.6)
    s1 = solve_contact(g1, mu, [Cylinder(0.0, P)])
    g2 = Grid.centered((256, 4), (16.0, 1.0), (0.6, 0.0))
    s2 = solve_contact(g2, mu, [Cylinder(0.0, P * 1.0)])
    assert s2.pressure.shape == (256, 4)
    np.testing.assert_array_equal(s2.active, np.repeat(s1.active[:, None], 4, axis=1))
    np.testing.assert_allclose(s2.pressure, s1.pressure[:, None] + 0 * s2.pressure,
                               atol=1e-8 * s1.pressure.max())
    assert s2.indentations[0] == pytest.approx(s1.indentations[0], rel=1e-8)


def test_threads_give_serial_results_bit_for_bit():
    """Plans are per thread: concurrent solves neither corrupt nor differ from serial ones."""
    scenes = [dict(load=float(L), mu=float(m)) for L in (60, 120, 200) for m in (0.0, 1.0, -2.0)]
    serial = [solve(tol=1e-3, **s).pressure for s in scenes]
    with ThreadPoolExecutor(4) as pool:
        threaded = list(pool.map(lambda s: solve(tol=1e-3, **s).pressure, scenes * 3))
    for i, p in enumerate(threaded):
        np.testing.assert_array_equal(p, serial[i % len(scenes)])


@pytest.mark.parametrize("content", [b"not wisdom at all", pickle.dumps("a pickled string"),
                                     b"(fftw-3.3 garbage"])
def test_bad_wisdom_file_is_ignored_with_one_warning(tmp_path, content):
    path = tmp_path / "wisdom.txt"
    path.write_bytes(content)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert fftmod.load_wisdom(path) is False
    assert len(caught) == 1 and "not FFTW wisdom" in str(caught[0].message)


def test_wisdom_round_trip_is_fftw_text(tmp_path):
    path = tmp_path / "wisdom.txt"
    fftmod.RealFFT((64,), "FFTW_MEASURE")
    fftmod.save_wisdom(path)
    assert path.read_bytes().startswith(b"(fftw-")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert fftmod.load_wisdom(path) is True


def test_two_dimensional_mirror_symmetry_is_exact():
    """mu -> -mu is x -> -x on a 2D grid (the Nyquist plane averaged over its aliases)."""
    g = Grid.centered((64, 16), (12.0, 6.0))
    film = Film()
    x, y = g.coordinates()
    p = np.exp(-((x - 0.7) ** 2) - 2 * y**2) + 0 * y
    pm = p[(-np.arange(64)) % 64, :]  # p(-x): node j <-> node -j (centred grid)
    op_p = FourierOperator(g, film.compliance_symbol(2.0))
    op_m = FourierOperator(g, film.compliance_symbol(-2.0))
    w_p = op_p.apply(p)
    w_m = op_m.apply(pm)
    np.testing.assert_allclose(w_m, w_p[(-np.arange(64)) % 64, :], atol=1e-14)
    assert np.all(np.isreal(op_p.symbol[g.nyquist_mask]))


@pytest.mark.parametrize("thickness", [1.0, 1e12])
def test_cold_start_extrapolated_edges_same_solution_fewer_steps(thickness):
    """The cold start's extrapolated shrinking steps change the path only: the same active set
    and the pressure to the solver's tolerance, in no more active-set steps (the film at the
    paper scene's period and load, 2^12 points: 8 plain steps, 4 extrapolated)."""
    g = Grid.centered(2**12, 21.380848262211956, 0.0)
    film = Film(thickness=thickness)
    ind = [Cylinder(0.0, 17.72727272727273)]
    ref = solve_contact(g, 0.0, ind, rtol=1e-13, film=film, extrapolate=False)
    plain = solve_contact(g, 0.0, ind, film=film, extrapolate=False)
    fast = solve_contact(g, 0.0, ind, film=film)
    assert np.array_equal(fast.active, ref.active)
    assert np.max(np.abs(fast.pressure - ref.pressure)) <= 1e-6 * ref.pressure.max()
    assert fast.iterations <= plain.iterations
    if thickness == 1.0:
        assert plain.iterations >= 7 and fast.iterations <= 5
