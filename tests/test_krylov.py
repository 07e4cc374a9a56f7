"""GMRES (numerics/krylov.py): the minimal-residual iterates, restarts, reused buffers."""
import numpy as np
import pytest

from spectral_contact.numerics.krylov import gmres


def _system(n, seed=0):
    rng = np.random.default_rng(seed)
    A = np.eye(n) * 3 + rng.standard_normal((n, n)) / np.sqrt(n)  # nonsymmetric
    M = np.diag(1.0 / np.diag(A)) + 0.01 * rng.standard_normal((n, n)) / np.sqrt(n)
    return A, M, rng.standard_normal(n), rng.standard_normal(n)


def test_solves_to_rtol_and_reports_true_residual():
    A, M, b, x0 = _system(80)
    x, its, rel = gmres(lambda v: A @ v, lambda v: M @ v, b, x0, rtol=1e-12)
    true = np.linalg.norm(b - A @ x) / np.linalg.norm(b)
    assert rel <= 1e-12 and true == pytest.approx(rel, rel=1e-6)
    assert np.allclose(x, np.linalg.solve(A, b), rtol=0, atol=1e-10)
    assert 0 < its < 80


@pytest.mark.parametrize("k", [1, 2, 3, 5, 8])
def test_iterates_minimise_the_residual_over_the_krylov_space(k):
    """x_k = x0 + M y, y in K_k(A M, r0) minimising ||b - A x_k||: computed independently by
    least squares on an orthonormalised Krylov basis."""
    A, M, b, x0 = _system(40, seed=k)
    x, its, _ = gmres(lambda v: A @ v, lambda v: M @ v, b, x0, rtol=1e-300, maxiter=k)
    assert its == k
    r0 = b - A @ x0
    K = [r0 / np.linalg.norm(r0)]
    for _ in range(k - 1):
        K.append(A @ (M @ K[-1]))
        K[-1] /= np.linalg.norm(K[-1])
    Q, _ = np.linalg.qr(np.array(K).T)
    Zk = M @ Q
    y = np.linalg.lstsq(A @ Zk, r0, rcond=None)[0]
    assert np.allclose(x, x0 + Zk @ y, rtol=0, atol=1e-11 * np.linalg.norm(x))


def test_restarts_and_buffer_reuse_across_sizes_give_the_same_answers():
    A, M, b, x0 = _system(60, seed=3)
    A2, M2, b2, x02 = _system(25, seed=4)
    ref = gmres(lambda v: A @ v, lambda v: M @ v, b, x0, rtol=1e-11, restart=5)
    small = gmres(lambda v: A2 @ v, lambda v: M2 @ v, b2, x02, rtol=1e-11, restart=7)
    again = gmres(lambda v: A @ v, lambda v: M @ v, b, x0, rtol=1e-11, restart=5)
    assert ref[1] > 5  # it did restart
    assert np.array_equal(ref[0], again[0]) and ref[1] == again[1]
    assert np.allclose(small[0], np.linalg.solve(A2, b2), atol=1e-9)


def test_a_nested_solve_does_not_overwrite_the_outer_bases():
    """A preconditioner that itself runs GMRES (re-entrant call, same thread)."""
    A, M, b, x0 = _system(30, seed=5)

    def inner_solve(v):
        # inexact (two iterations): the outer solve needs several, with several bases rows
        return gmres(lambda u: A @ u, lambda u: M @ u, v, np.zeros_like(v), maxiter=2)[0]

    x, its, rel = gmres(lambda v: A @ v, inner_solve, b, x0, rtol=1e-11)
    assert rel <= 1e-11 and 3 <= its < 30
    assert np.allclose(x, np.linalg.solve(A, b), atol=1e-9)

