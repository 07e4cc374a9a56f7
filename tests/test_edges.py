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


def _line_solutions(sizes, period, film_kw, load, mu):
    """Fixed-grid collocation solves of a line (the solver's contact solve, no refinement)."""
    from spectral_contact.numerics.contact import solve_contact
    from spectral_contact.numerics.grid import Grid
    from spectral_contact.physics.scene import Scene

    scene = Scene(load=load, mu=mu, **film_kw)
    film = scene.core_film()
    ind = [scene.indenter_object()]
    out = []
    for n in sizes:
        g = Grid.centered(n, period, 0.0)
        out.append((g, solve_contact(g, mu, ind, film=film, rtol=1e-10, accept=1e-8),
                    film.trailing_edge_layer()))
    return out


@pytest.mark.parametrize("film_kw,load,mu", [
    # a_H/h 1 (the series' own scene: P = 2 pi (a_H/h)^2 E h/(6R) ... in N/m), relaxed film
    (dict(young=2.2e6, thickness=0.002, radius=0.130), 2 * np.pi * 2.2e6 * 0.002 ** 2 / (6 * 0.130)
     * 1.0, 0.0),
    # the paper's scene on the SLS film at 10 m/s (trailing layer fit, friction): not fitted on
    (dict(young=2.2e6, thickness=0.002, radius=0.130, speed=10.0, prony=((2.2e6, 0.01),)),
     200.0, 2.0),
])
def test_lattice_error_removes_the_collocation_edge_error(film_kw, load, mu):
    """The 4-node fit's error at a square-root edge is dx times a function of the fitted
    offset (``lattice_error``): over grids of 2048-3072 points on one period, both edges, the
    raw fits are up to 0.03-0.065 cells off a 2^16-point reference, the corrected ones within
    0.005 (studies.edge_noise: rms 1e-4 - 2e-4)."""
    from spectral_contact.numerics.edges import fit_edges

    period = 21.9
    (gr, ref, tr), = _line_solutions([65536], period, film_kw, load, mu)
    (l_ref, r_ref), = fit_edges(gr.x, gr.dx, ref.gap, ref.pressure, ref.active, tr, True)
    raw, corrected = [], []
    for g, sol, tr in _line_solutions([2048, 2304, 2560, 2816, 3072], period, film_kw, load, mu):
        for lattice, errs in ((False, raw), (True, corrected)):
            (left, right), = fit_edges(g.x, g.dx, sol.gap, sol.pressure, sol.active, tr, lattice)
            errs += [abs(left - l_ref) / g.dx, abs(right - r_ref) / g.dx]
    assert max(raw) > 0.02  # (the noise the correction removes)
    assert max(corrected) < 0.005


def test_lattice_error_is_smooth_in_the_fitted_offset():
    """Continuous across the offsets the fit gives (the jump in the edge's cell position,
    where the next node joins the contact, is at the two ends of that range), flat beyond."""
    from spectral_contact.numerics.edges import LATTICE_ERROR_RANGE, lattice_error

    lo, hi = LATTICE_ERROR_RANGE
    t = np.linspace(lo, hi, 1001)
    g = np.array([lattice_error(v) for v in t])
    assert np.max(np.abs(np.diff(g) / np.diff(t))) < 0.4  # (cells per cell of offset)
    assert lattice_error(lo - 0.05) == lattice_error(lo) and lattice_error(1.4) == lattice_error(hi)
    assert -0.025 < g.min() < -0.015 and 0.06 < g.max() < 0.075  # (the measured range)


def test_line_solver_with_the_lattice_correction_settles_x_c_from_grid_to_grid(monkeypatch):
    """The paper's scene on the SLS film at 10 m/s (nearly glassy; the lead's seventh-session
    case), fixed grids on one period: x_c/a wandered by ~1e-4 from N to N (the edges' noise,
    not monotone in N); with the correction (``solvers.fft.VISCO_LATTICE``, on for
    viscoelastic films) within 1e-5."""
    from spectral_contact import solve
    from spectral_contact.solvers import fft as fft_solver

    kw = dict(load=200.0, mu=2.0, tol=1e-4, young=2.2e6, thickness=0.002, radius=0.130,
              speed=10.0, prony=((2.2e6, 0.01),), domain_length=20.95 * 0.002)

    def spread():
        c = [solve(grid_points=n, **kw) for n in (2048, 2304, 2560, 2816)]
        return (max(r.center for r in c) - min(r.center for r in c)) / c[0].half_width

    after = spread()
    monkeypatch.setattr(fft_solver, "VISCO_LATTICE", False)
    before = spread()
    assert before > 3e-5 and after < 1e-5


def test_one_node_run_with_crossed_fits_is_not_moved_by_the_period():
    """A run of one contact node whose two edge fits both lie inside it (offsets -0.2 cells:
    right < left) is a run of width 0 at the node, not a run that wraps the period (which
    fit_edges used to make of it by adding the period: a sphere's locator column at its tip
    doubled the period along y).  A run that does wrap still gets the period added."""
    from spectral_contact.numerics.edges import fit_edges

    n, dx = 64, 0.1
    x = np.arange(n) * dx
    i0 = 30
    gap = ((np.abs(np.arange(n) - i0) + 0.2) * dx) ** 1.5
    active = np.zeros(n, bool)
    active[i0] = True
    gap[i0] = 0.0
    p = np.where(active, 1.0, 0.0)
    (left, right), = fit_edges(x, dx, gap, p, active)
    assert left == pytest.approx(x[i0]) and right == pytest.approx(x[i0])
    # a run through the period's end: the right edge beyond x[-1] + the period's start
    act = np.zeros(n, bool)
    act[[n - 2, n - 1, 0, 1]] = True
    d = np.minimum(np.abs(np.arange(n) - (n - 0.5)), np.abs(np.arange(n) + 0.5)) - 2.0
    g2 = np.where(act, 0.0, (np.maximum(d, 0.0) * dx) ** 1.5)
    (l2, r2), = fit_edges(x, dx, g2, np.where(act, 1.0, 0.0), act)
    assert l2 < x[n - 2] and r2 > n * dx + x[1]


def test_the_correction_is_on_for_viscoelastic_lines_only():
    """Issue 23's cost: viscoelastic lines correct their edges (``VISCO_LATTICE``); the elastic
    film keeps the uncorrected fits its issue-13 estimate was verified on (``--speed 0`` with
    the Prony terms is the elastic film)."""
    from spectral_contact.physics.scene import Scene
    from spectral_contact.solvers import fft as fft_solver
    from spectral_contact.solvers.fft_driver import Problem

    def lattice(**kw):
        scene = Scene(load=200.0, mu=2.0, young=2.2e6, thickness=0.002, radius=0.130, **kw)
        return fft_solver._lattice_edges(Problem(scene, "exact", 1e-4))

    sls = dict(speed=0.01, prony=((2.2e6, 0.01),))
    assert lattice(**sls) and not lattice() and not lattice(speed=0.0, prony=sls["prony"])


def test_corrected_edges_keep_half_the_shift_difference():
    """With the phase error corrected, the grid and the shifted grid differ by errors their
    average does not cancel: the estimate keeps half their difference (a quarter for the
    uncorrected fits, whose averaged phase error was measured at that)."""
    from spectral_contact.solvers.fft import _discretisation_error

    step, last = np.array([1e-6, 0.0, 0.0, 0.0]), np.array([2e-6, 0.0, 0.0, 0.0])
    assert _discretisation_error(step, last, 1e-4) == pytest.approx(0.25e-4)
    assert _discretisation_error(step, last, 1e-4, corrected=True) == pytest.approx(0.5e-4)
    assert _discretisation_error(step, None, 1e-4, corrected=True) == pytest.approx(0.5e-4)
