"""The tenth session's audit of the viscoelastic estimates (studies/README, "viscoelastic: an
audit of the estimates (tenth session)"; ``studies.viscoelastic_audit``)."""
import csv

import pytest

from spectral_contact import solve

E_INF = 2.2e6
TAU = 0.01


@pytest.mark.xfail(strict=True, reason=(
    "lines fit the edge structure of every Prony term up to E_i/E_inf = 10 one term at a time "
    "(_LineSolve.LAYER_FITTED_WEIGHT): three terms of 10 E_inf at one tau are the film of one "
    "term of 30 E_inf, whose leading-edge glassy spike the fitted grid does not see (p_max "
    "23 % off under an estimate of 8.8e-3); studies/README, audit (tenth session)"))
def test_a_split_prony_term_is_the_same_film():
    """((30 E_inf, tau),) and ((10 E_inf, tau),) * 3 are one material (G* is the sum over the
    terms): a_H/h 0.3 (mu 0) at 0.17 mm/s (|V| tau = 2.8e-3 a), tol 1e-2.  The single term is
    heavier than the fitted range and has its edge structure resolved (p_max 1.6399 under
    1.5e-3 on 2^18 points); the split one is left to the fits term by term and stops on 2048
    points at p_max 1.2538 under 8.8e-3.  Their p_max must agree within the two estimates."""
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
