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
    return {n: solve(grid_points=n, **SCENE) for n in (128, 512)}


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
