"""The peers on fixed grids (studies.peers, issue 13): the same discrete problem for every solver,
so their pressures agree.  The peer tests skip when tamaas / ContactMechanics are absent (.ci/run
does not install them: `pip install -e '.[peers]'`)."""
import math

import numpy as np
import pytest

from spectral_contact import Scene
from spectral_contact.numerics.contact import solve_contact
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.film import Film
from spectral_contact.physics.indenters import Cylinder
from studies import peers

L_PAPER = 21.380848268299545  # the period of the paper's scene at mu_d = 0, tol 1e-4 (as D uses)


def _problem(n, film):
    grid = Grid.centered(n, L_PAPER, 0.0)
    P = Scene(mu=0.0).P
    sym = film.surface_compliance((np.ones_like(grid.k),), grid.k, 0.0).real
    ref = solve_contact(grid, 0.0, [Cylinder(0.0, P)], rtol=1e-13, film=film)
    return grid, P, sym, ref


def test_half_space_limit_is_westergaards_symbol_bit_for_bit():
    grid = Grid.centered(2**12, L_PAPER, 0.0)
    sym = peers.HALF_SPACE.surface_compliance((np.ones_like(grid.k),), grid.k, 0.0).real
    assert np.array_equal(sym, peers.halfspace_symbol(grid))


def test_tamaas_with_the_film_registered_from_python_solves_our_problem():
    pytest.importorskip("tamaas")
    grid, P, sym, ref = _problem(1024, Film())
    p_film = peers.tamaas_runner(grid, P, sym, tol=1e-12, count=False)()["p"]
    p_hs = peers.tamaas_runner(grid, P, None, tol=1e-12, count=False)()["p"]
    pmax = ref.pressure.max()
    assert np.max(np.abs(p_film - ref.pressure)) < 1e-7 * pmax  # the same discrete problem
    assert np.max(np.abs(p_hs - ref.pressure)) > 1e-2 * pmax    # its Westergaard: not the film


def test_contactmechanics_layer_near_incompressible_is_our_film():
    pytest.importorskip("ContactMechanics")
    grid, P, sym, ref = _problem(1024, Film())
    pmax = ref.pressure.max()
    p = peers.contactmechanics_runner(grid, P, True, float(ref.indentations[0]), pmax, tol=1e-12)()["p"]
    assert np.max(np.abs(p - ref.pressure)) < 1e-6 * pmax


def test_fixed_grid_comparison_equal_accuracy_and_targets():
    pytest.importorskip("tamaas")
    pytest.importorskip("ContactMechanics")
    rows = peers.fixed_grid_comparison((10,), repeats=1, log=None)
    # film: ours, ContactMechanics, tamaas; half-space: ours, ContactMechanics, tamaas x 2
    assert [(r["operator"], r["N"]) for r in rows] == [("film", 1024)] * 3 + [("half-space", 1024)] * 4
    for r in rows:  # each within LEVEL of the reference: any two solvers within 2 LEVEL
        assert r["status"] == "timed", r
        assert r["dp_ref"] <= peers.LEVEL and r["tol"] in peers.TOLERANCES
        assert r["residual"] < 1e-6 and r["time_ms"] > 0 and r["time_in_fft_pairs"] > 0
        assert (r["solver"] == peers.OURS_FIXED) == (r["time_ratio"] == 1.0)
    targets = peers.peer_targets(rows)  # one per operator and peer: its fastest configuration
    assert len(targets) == 4 and all("N=2^10" in t["target"] for t in targets)
    for t in targets:
        assert t["limit"] == peers.SPEEDUP and math.isfinite(t["measured"])
        assert t["status"] == ("met" if t["measured"] >= peers.SPEEDUP else "not met")
    hs_tamaas = [r["time_ratio"] for r in rows if r["operator"] == "half-space" and "tamaas" in r["solver"]]
    assert next(t for t in targets if t["target"].startswith("vs tamaas half-space"))["measured"] == min(hs_tamaas)


def test_fixed_grid_comparison_without_the_peers(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "ContactMechanics", None)
    monkeypatch.setitem(sys.modules, "tamaas", None)
    rows = peers.fixed_grid_comparison((10,), repeats=1, operators=("film",), log=None)
    assert [r["status"] for r in rows] == ["timed"] + ["not measured (peer not installed)"] * 2
    assert {t["status"] for t in peers.peer_targets(rows)} == {"not measured (peer not installed)"}
