"""The tenth session's audit of the viscoelastic estimates (studies/README, "viscoelastic: an
audit of the estimates (tenth session)"; ``studies.viscoelastic_audit``)."""
import csv

import pytest

from spectral_contact import solve

E_INF = 2.2e6
TAU = 0.01


def test_a_split_prony_term_is_the_same_film():
    """((30 E_inf, tau),) and ((10 E_inf, tau),) * 3 are one material (G* is the sum over the
    terms): a_H/h 0.3 (mu 0) at 0.17 mm/s (|V| tau = 2.8e-3 a), tol 1e-2.  The single term is
    heavier than the fitted range and has its edge structure resolved (p_max 1.6399 under
    1.5e-3 on 2^18 points); the split one was left to the fits term by term and stopped on
    2048 points at p_max 1.2538 under 8.8e-3 (main at 0e3d80d: the audit's finding, xfail
    then).  Since ``physics.viscoelastic.merged_weights`` (terms within a factor 4 in tau are
    one heavy term for the fitted range) it is resolved as the single term.  Their p_max must
    agree within the two estimates."""
    from studies.viscoelastic import FILM, load_for

    kw = dict(load=load_for(0.3), mu=0.0, speed=1.7e-4, tol=1e-2, **FILM)
    one = solve(prony=((30 * E_INF, TAU),), **kw)
    split = solve(prony=((10 * E_INF, TAU),) * 3, **kw)
    assert abs(split.max_pressure - one.max_pressure) / one.max_pressure <= \
        split.error_estimate + one.error_estimate


def test_audit_quick(tmp_path):
    """``studies.viscoelastic_audit --quick`` (two lines, one sphere at tol 1e-2, each against
    two references): every row bounded, Q/P = mu + mu_def, the mirrored scene mirrors."""
    from studies.viscoelastic_audit import main

    assert main(["--quick", "--out", str(tmp_path)]) == 0
    rows = list(csv.DictReader(open(tmp_path / "viscoelastic_audit.csv")))
    assert len(rows) == 3 and {r["kind"] for r in rows} == {"line", "sphere"}
    for r in rows:
        assert r["status"] == "bounded", r
        assert float(r["true_error"]) <= float(r["error_estimate"])
        assert float(r["QP_identity"]) < 1e-12
        assert float(r["mirror_change"]) < 1e-9


@pytest.mark.xfail(strict=True, reason=(
    "a surface's estimate is the last two levels' difference; the line load at y = 0 (a node "
    "sum over a row with square-root edges) errs by where the edges fall in their cells, not "
    "monotonically in the cell, so two levels can agree closer than the finer one's error: "
    "3.8-4.1e-4 off under 1.79e-4 (2.2x); studies/README, audit (tenth session)"))
def test_elastic_sphere_line_load_within_its_estimate():
    """The elastic sphere, F = 0.3 N, mu 0, tol 1e-3: the solve stops on 512^2 (levels 256^2,
    512^2) with line load at y = 0 118.6787 N/m under an estimate of 1.79e-4; fixed grids on
    the solve's period give 118.7234 (1024^2), 118.7275 (1536^2), 118.7257 (2048^2): 3.8-4.1e-4
    off (radius, centroid, d, p_max within 4.4e-5)."""
    r = solve(indenter="sphere", force=0.3, mu=0.0, tol=1e-3)
    assert r.grid_points == (512, 512)
    ref = 118.7257  # 2048^2 on the solve's period (1024^2 .. 2048^2 within 3.5e-5 of it)
    assert abs(r.summary()["line_load_y0_N_per_m"] - ref) / ref <= r.error_estimate


@pytest.mark.xfail(strict=True, reason=(
    "as the elastic sphere's: the line load at y = 0 is 1.6-2.2e-4 off under an estimate of "
    "1.17e-4 (the audit's scene 44); studies/README, audit (tenth session)"))
def test_viscoelastic_sphere_line_load_within_its_estimate():
    """The audit's scene 44 (a light long term, E_1 = 0.177 E_inf at 4.37 s, V = -2.78 mm/s,
    F = 0.68 N, mu 0, tol 1e-3): 512^2, line load 225.9399 N/m under 1.17e-4 (0e3d80d; since
    505bf2a 225.9012 under 1.43e-4, 3.3-3.9e-4 off); fixed grids on
    the solve's period 225.9899 (1024^2), 225.9754 (1536^2), 225.9803 (2048^2)."""
    r = solve(speed=-0.0027761347213070943, prony=((388624.33503537375, 4.374888680084054),),
              mu=0.0, tol=1e-3, indenter="sphere", force=0.6815129850282954)
    assert r.grid_points == (512, 512)
    ref = 225.9754  # the closest of the three fine grids
    assert abs(r.summary()["line_load_y0_N_per_m"] - ref) / ref <= r.error_estimate
