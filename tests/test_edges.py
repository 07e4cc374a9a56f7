"""Sub-grid edge location (numerics/edges.py): the closed-form fit against numpy's polyfit."""
import numpy as np
import pytest

from spectral_contact.numerics.edges import _quadratic_fit_root

S = np.arange(2, 6, dtype=float)


def _polyfit_root(y):
    """The former implementation: np.polyfit + np.roots, the real root in range nearest 0.5."""
    roots = np.roots(np.polyfit(S, y, 2))
    roots = roots[np.isreal(roots)].real
    roots = roots[(roots > -0.25) & (roots < 1.5)]
    return float(roots[np.argmin(np.abs(roots - 0.5))]) if roots.size else None


def test_exact_on_a_parabola_and_a_line():
    for e in (-0.2, 0.0, 0.37, 1.0, 1.45):
        assert _quadratic_fit_root(*(2.0 * (S - e))) == pytest.approx(e, abs=1e-14)
        y = 0.8 * (S - e) - 0.03 * (S - e) ** 2
        assert _quadratic_fit_root(*y) == pytest.approx(e, abs=1e-13)
    assert _quadratic_fit_root(1.0, 2.0, 3.0, 4.0) == pytest.approx(1.0, abs=1e-14)
    assert _quadratic_fit_root(5.0, 5.0, 5.0, 5.0) is None       # constant: no root
    assert _quadratic_fit_root(1.0, 0.5, 0.5, 1.0) is None       # parabola above 0
    assert _quadratic_fit_root(*(S - 3.0)) is None               # root outside (-0.25, 1.5)


def test_same_roots_as_polyfit_on_edge_like_and_random_data():
    rng = np.random.default_rng(1)
    n_root = 0
    for i in range(4000):
        if i % 2:  # gap^(2/3) near an edge: nearly linear, curvature and noise small
            e = rng.uniform(-0.5, 1.8)
            y = rng.uniform(0.1, 3) * (S - e) + rng.normal(0, 0.05) * (S - e) ** 2
            y = np.maximum(y + rng.normal(0, 1e-3, 4), 0.0)
        else:
            y = rng.normal(0, 1, 4)
        ref, got = _polyfit_root(y), _quadratic_fit_root(*y)
        if ref is None:
            assert got is None, (y, got)
        else:
            n_root += 1
            assert got == pytest.approx(ref, abs=1e-11), y
    assert n_root > 1000


def _runs_by_rolling(active):
    """The former contact_runs: roll to the first inactive node, then diff."""
    n = active.size
    start = int(np.argmin(active))
    a = np.roll(active, -start)
    d = np.diff(np.concatenate([[0], a.astype(np.int8), [0]]))
    firsts = np.flatnonzero(d == 1)
    lasts = np.flatnonzero(d == -1) - 1
    return [((f + start) % n, (e + start) % n) for f, e in zip(firsts, lasts)]


def test_contact_runs_same_runs_in_the_same_order_as_rolling():
    from spectral_contact.numerics.edges import contact_runs
    rng = np.random.default_rng(5)
    cases = [np.array([1, 1, 0, 0, 1, 0, 1, 1], bool), np.array([0, 1, 1, 0], bool),
             np.array([1, 0, 0, 0], bool), np.array([0, 0, 0, 1], bool),
             np.array([1, 0, 0, 1], bool), np.array([0, 1, 0, 1, 0], bool)]
    cases += [rng.random(n) < q for n in (5, 16, 64) for q in (0.2, 0.5, 0.8) for _ in range(30)]
    cases += [rng.random((12, 7))[:, 3] < 0.5 for _ in range(20)]  # strided columns (2D)
    n_checked = 0
    for a in cases:
        if a.all() or not a.any():
            continue
        assert contact_runs(a) == [(int(f), int(e)) for f, e in _runs_by_rolling(a)], a
        n_checked += 1
    assert n_checked > 200
    assert contact_runs(np.zeros(8, bool)) == []
