"""Where a viscoelastic line solve's FFT pairs go (issue 23's cost): the solves beside the
levels start where they can (studies/README, viscoelastic, cost)."""
import numpy as np

from spectral_contact.numerics.contact import solve_contact
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.scene import Scene
from spectral_contact.solvers import fft as fft_solver
from spectral_contact.solvers.fft import solve_fft

E_INF = 2.2e6
SLS = ((E_INF, 0.01),)
FILM = {"young": E_INF, "thickness": 0.002, "radius": 0.130}


def test_contact_solve_from_its_solution_and_indentation_takes_no_gmres_iteration():
    """``d_init``: started from a converged pressure and its indentation, a contact solve
    checks the state (one transform) instead of re-solving from d = 0 (the whole gap as the
    first residual)."""
    scene = Scene(load=200.0, mu=2.0, speed=0.1, prony=SLS, **FILM)  # the paper's, sliding
    film = scene.core_film()
    ind = [scene.indenter_object()]
    g = Grid.centered(1024, 24.0, 0.5)
    ref = solve_contact(g, 2.0, ind, film=film, rtol=1e-9, accept=1e-6)
    cold = solve_contact(g, 2.0, ind, film=film, p_init=ref.pressure, rtol=1e-9, accept=1e-6)
    warm = solve_contact(g, 2.0, ind, film=film, p_init=ref.pressure, rtol=1e-9, accept=1e-6,
                         d_init=ref.indentations)
    assert cold.krylov_iterations >= 4
    assert warm.krylov_iterations == 0 and warm.fft_pairs == 1 and warm.iterations == 1
    assert np.array_equal(warm.active, ref.active)
    assert abs(warm.indentations[0] - ref.indentations[0]) <= 1e-9 * abs(ref.indentations[0])


def test_measured_images_start_from_the_final_level(monkeypatch):
    """A viscoelastic line whose images are measured (a_H/h 1 at 0.1 m/s: kappa l_r = 0.74,
    no bound) solves the final level's nodes on twice the period from that level's pressure
    and indentation: fewer FFT pairs than from d = 0 (1 against 18 on the period before the
    far-field margin; 12 against 16 on the shorter one, whose images are larger)."""
    seen = []
    real = fft_solver._LineSolve.contact

    def spy(self, grid, *args, **kwargs):
        sol = real(self, grid, *args, **kwargs)
        cold = None
        if kwargs.get("d_init") is not None:  # the same solve from d = 0, for comparison
            cold = real(self, grid, *args, **{**kwargs, "d_init": None}).fft_pairs
        seen.append((grid.n, sol.fft_pairs, cold))
        return sol

    monkeypatch.setattr(fft_solver._LineSolve, "contact", spy)
    load = 2.0 * np.pi * Scene(**FILM).stress_unit * Scene(**FILM).length_unit  # a_H = h
    r = solve_fft(Scene(load=load, mu=0.0, speed=0.1, prony=SLS, **FILM), tol=1e-4)
    n_final, pairs_far, pairs_cold = seen[-1]
    assert n_final == 2 * r.grid_points  # the images' solve: the final nodes over 2L
    assert r.info["domain_difference"] < 0.25e-4  # (within the tol/4 the images may take)
    assert pairs_far < pairs_cold


def test_friction_images_relaxed_solve_extrapolates_its_shrinking_ends(monkeypatch):
    """The friction images' d_el (the relaxed film's contact on an eighth of the final level's
    points, started from the solve's narrower pressure): a band is added at once, then the
    end nodes are shed with their ends extrapolated (``extrapolate``), not halved per step:
    the paper's scene at 0.32 m/s, 80 -> 50 FFT pairs, d_el the same."""
    from spectral_contact.solvers import fft_driver

    seen = []
    real = fft_driver.Problem.solve_contact

    def spy(self, grid, indenters, film, *args, **kwargs):
        sol = real(self, grid, indenters, film, *args, **kwargs)
        if self.visco and not film.moving:  # the relaxed film's solve
            seen.append((sol.fft_pairs, float(sol.indentations[0])))
        return sol

    monkeypatch.setattr(fft_driver.Problem, "solve_contact", spy)
    r = solve_fft(Scene(load=200.0, mu=2.0, speed=0.32, prony=SLS, **FILM), tol=1e-4)
    assert "friction_images_bound" in r.info and len(seen) == 1
    pairs, d_el = seen[0]
    assert pairs <= 56
    # the relaxed film's converged indentation: d_el within the 2.2e-4 the bound allows for
    d_conv = solve_fft(Scene(load=200.0, mu=2.0, **FILM), tol=1e-6).indentation
    assert abs(d_el - d_conv) < 2.2e-4 * d_conv


def test_slow_path_counts_both_elastic_solves():
    """The slow-sliding path that runs the relaxed elastic solve twice (a_H/h 1 at 3.16e-4
    m/s, tol 1e-4: the first's estimate plus the remainder 1.01e-4 > tol) reports the work of
    both (126 + 127 FFT pairs; it reported the second's alone)."""
    load = 2.0 * np.pi * Scene(**FILM).stress_unit * Scene(**FILM).length_unit  # a_H = h
    scene = Scene(load=load, mu=0.0, speed=3.16e-4, prony=SLS, **FILM)
    r = solve_fft(scene, tol=1e-4)
    el = solve_fft(Scene(load=load, mu=0.0, **FILM), tol=1e-4)
    assert "slow_sliding" in r.info
    assert r.counters["transforms"] > 1.8 * el.counters["transforms"]
    assert r.info["fft_pairs"] == r.counters["transforms"]
