"""3D solves at the FFT floor (issue 25): counts, not times (timings are in studies/benchmark
and studies/three_d_cost).  The fixed-grid sliding sphere of the speed target (mu 1, 1 N,
30 mm period) through the public solve: the finest grid's active-set steps and GMRES
iterations do not grow with the grid, and the whole solve's FFT pairs stay bounded."""
import numpy as np
import pytest

from spectral_contact import solve
from spectral_contact.numerics.contact import nested_guess, solve_contact
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.indenters import Sphere
from spectral_contact.physics.scene import Scene3D

SCENE = dict(indenter="sphere", force=1.0, mu=1.0, domain_length=0.03)


@pytest.fixture(scope="module")
def by_n():
    return {n: solve(grid_points=n, **SCENE) for n in (128, 512, 1024)}


def test_finest_grid_iterations_flat_in_n(by_n):
    small, big = by_n[128], by_n[512]
    assert big.info["final_level_active_set_iterations"] <= \
        small.info["final_level_active_set_iterations"] + 1
    assert big.info["final_level_krylov_iterations"] <= \
        small.info["final_level_krylov_iterations"] + 4
    # one or two active-set steps on the finest grid from the nested start (4 before)
    assert big.info["final_level_active_set_iterations"] <= 2
    # the finest grid's own FFT pairs (GMRES, preconditioner, residual checks) under 50
    assert big.info["final_level_fft_pairs"] <= 50
    # and at 1024^2 by count (2048^2 took 3 steps before the release look-ahead; measured 2,
    # 19 GMRES there: studies.three_d_cost)
    larger = by_n[1024]
    assert larger.info["final_level_active_set_iterations"] <= 2
    assert larger.info["final_level_krylov_iterations"] <= \
        small.info["final_level_krylov_iterations"] + 4


def test_release_lookahead_saves_the_cascade_step_not_the_answer(monkeypatch):
    """A step that sheds tensile nodes also sheds those the release turns tensile
    (contact._released_tensile): at 512^2, 3 N, mu 1 the plain path's finest grid takes a third
    step for 2 such nodes; with the look-ahead two steps, and the same contact set and
    pressures to the solver's tolerance."""
    import spectral_contact.numerics.contact as contact

    kw = dict(SCENE, force=3.0, grid_points=512)
    ahead = solve(**kw)
    monkeypatch.setattr(contact, "_RELEASE_STEPS", 0)
    plain = solve(**kw)
    assert ahead.info["final_level_active_set_iterations"] == 2
    assert plain.info["final_level_active_set_iterations"] >= \
        ahead.info["final_level_active_set_iterations"]
    assert ((ahead.pressure > 0) == (plain.pressure > 0)).all()
    np.testing.assert_allclose(ahead.pressure, plain.pressure, rtol=0,
                               atol=1e-5 * plain.pressure.max())  # (accept, tol 1e-3)
    for k in ("area", "indentation", "pmax", "x_min", "x_max"):
        assert ahead.measures[k] == pytest.approx(plain.measures[k], rel=1e-6)  # tol 1e-3


def test_release_prediction_sheds_only_nodes_the_next_solve_finds_tensile():
    """_released_tensile's local prediction (the grid's compliance on 5 x 5 patches, the
    indentation held) against dense solves of the bordered system on the same sets: the
    sliding sphere's cold 64^2 start (the half-space guess, too wide on the film).  Every node
    it sheds ahead is tensile on the plain path's next solve, and it finds some (the rest of
    that cascade is the global shrinking of a far guess, not its business)."""
    from spectral_contact.numerics import contact
    from spectral_contact.numerics.fft import get_rfft

    sc = Scene3D(force=1.0, mu=1.0)
    L = 0.03 / sc.length_unit
    g = Grid.centered((64, 64), (L, L))
    n = g.shape[0]
    ind = Sphere(0.0, sc.P)
    op = contact.compliance_operator(g.shape, g.lengths, 1.0, contact._FILM)
    kern = get_rfft(g.shape).backward(op.symbol)  # nodal compliance (periodic)
    f = np.broadcast_to(ind.height(g), g.shape).ravel()

    def dense(active):  # K p - d = -f on the set, cell sum p = P
        idx = np.flatnonzero(active)
        ix, iy = np.divmod(idx, n)
        m = idx.size
        A = np.zeros((m + 1, m + 1))
        A[:m, :m] = kern[(ix[:, None] - ix[None, :]) % n, (iy[:, None] - iy[None, :]) % n]
        A[:m, m], A[m, :m] = -1.0, g.cell
        x = np.linalg.solve(A, np.concatenate([-f[idx], [ind.load]]))
        p = np.zeros(n * n)
        p[idx] = x[:m]
        return p

    first = np.broadcast_to(ind.initial_pressure(g), g.shape).ravel() > 0
    p0 = dense(first)
    shed = first & (p0 < 0)
    keep = first & ~shed
    more = contact._released_tensile(shed, keep, p0, g.shape, contact._release_kernel(op, [0]))
    assert more is not None and more.sum() >= 2
    plain = dense(keep)
    assert (plain[more] < 0).all()  # no false release
    assert (dense(keep & ~more)[keep & ~more] < 0).sum() < (plain[keep] < 0).sum()


def test_nested_first_set_is_the_fine_contact_up_to_a_boundary_layer():
    """The first active set from the coarse solution's fitted chords (nested_guess) differs
    from the fine solution's contact by fewer nodes than one per boundary cell: the
    frictionless sphere then needs a single active-set step."""
    sc = Scene3D(force=1.0, mu=0.0)
    L = 0.03 / sc.length_unit
    coarse = solve_contact(Grid.centered((128, 128), (L, L)), 0.0, [Sphere(0.0, sc.P)])
    fine_grid = Grid.centered((256, 256), (L, L))
    p0 = nested_guess(coarse, fine_grid)
    fine = solve_contact(fine_grid, 0.0, [Sphere(0.0, sc.P)], p_init=p0)
    first, final = p0 > 0, fine.active
    boundary = 2 * np.pi * np.sqrt(final.sum() / np.pi)  # perimeter in cells
    assert (first ^ final).sum() < 0.1 * boundary
    assert fine.iterations == 1


def test_output_fields_are_the_films(by_n):
    """The output fields (one forward transform, multipliers cached per grid) are
    Film.base_stresses and Film.surface_displacements to round-off."""
    from spectral_contact.numerics.fft import get_rfft
    from spectral_contact.physics.film import Film

    r = by_n[128]
    g = Grid(r.pressure.shape, r.domain_length, (r.x[0], r.y[0]))
    film = Film()
    shear = (r.scene.mu * r.pressure, np.zeros_like(r.pressure))
    fft = get_rfft(g.shape)
    szz, (sxz, syz) = film.base_stresses(fft, g, -r.pressure, shear)
    (ux, uy), delta = film.surface_displacements(fft, g, r.pressure, shear)
    for a, b in ((szz, r.base_sigma_zz), (sxz, r.base_sigma_xz), (syz, r.base_sigma_yz),
                 (ux, r.surface_ux), (uy, r.surface_uy), (-delta, r.surface_uz)):
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-13 * np.abs(a).max())
