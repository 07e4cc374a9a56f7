"""Smoke tests of studies/stability.py and studies/large_domain.py (their --quick versions)."""
import math

import pytest

from studies import large_domain, stability

from .conftest import read_rows


def _f(row, key):
    return float(row[key])


@pytest.fixture(scope="module")
def stability_out(tmp_path_factory):
    out = tmp_path_factory.mktemp("stability")
    assert stability.main(["--quick", "--out", str(out)]) == 0
    return out


@pytest.fixture(scope="module")
def large_out(tmp_path_factory):
    out = tmp_path_factory.mktemp("large_domain")
    assert large_domain.main(["--quick", "--out", str(out)]) == 0
    return out


def test_stability_files(stability_out):
    for name in ("stability_domain.csv", "stability_grid.csv", "stability_phase.csv",
                 "stability_phase_summary.csv", "stability_mu.csv", "stability_thin.csv"):
        assert (stability_out / name).stat().st_size > 100, name
    assert (stability_out / "stability.png").stat().st_size > 20_000


def test_stability_images_follow_the_decay(stability_out):
    rows = [r for r in read_rows(stability_out / "stability_domain.csv") if r["status"] == "ok"]
    assert {"L_minus_2a", "err_a", "err_c", "err_d", "predicted"} <= set(rows[0])
    rows.sort(key=lambda r: _f(r, "L_minus_2a"))
    err = [max(_f(r, "err_a"), _f(r, "err_c"), _f(r, "err_d")) for r in rows]
    assert all(math.isfinite(e) for e in err)
    assert err[-1] < 1e-5 < err[0]  # images fall with L ...
    far = [(e, _f(r, "predicted")) for e, r in zip(err, rows) if 4 < _f(r, "L_minus_2a") < 20]
    assert far and all(0.05 < e / p < 5 for e, p in far)  # ... like exp(-0.739 (L - 2a))


def test_stability_grid_and_phase(stability_out):
    rows = [r for r in read_rows(stability_out / "stability_grid.csv") if r["status"] == "ok"]
    coarse, fine = rows[0], rows[-1]
    assert _f(fine, "across") > 100 > _f(coarse, "across")
    for tag in ("raw", "avg"):
        assert _f(fine, f"{tag}_err_a") < 1e-3 < _f(coarse, f"{tag}_err_a")
    summ = read_rows(stability_out / "stability_phase_summary.csv")[0]
    # averaging over a half-cell shift shrinks the phase-dependent part of the edge error
    assert 0 < _f(summ, "avg_rms_dx") < 0.7 * _f(summ, "raw_rms_dx") < 0.1


def test_stability_mu_and_thin(stability_out):
    mus = read_rows(stability_out / "stability_mu.csv")
    for r in mus:
        if r["status"] == "ok":
            assert 0 < int(r["gmres_total"]) < 10_000 and math.isfinite(_f(r, "a"))
            assert int(r["runs"]) >= 1
    ok = [r for r in mus if r["status"] == "ok"]
    assert [_f(r, "mu") for r in ok][:3] == [0.0, 2.0, 10.0]
    a = [_f(r, "a") for r in ok]
    assert a == sorted(a)  # friction widens the contact
    thin = [r for r in read_rows(stability_out / "stability_thin.csv") if r["status"] == "ok"]
    big = max(thin, key=lambda r: _f(r, "a_thin"))
    assert _f(big, "a_thin") >= 20
    assert 0.85 < _f(big, "a_over_thin") < 1 and abs(_f(big, "pmax_over_thin") - 1) < 0.05


def test_large_domain_files(large_out):
    for name in ("large_domain_cost.csv", "large_domain_planning.csv", "large_domain_train.csv",
                 "large_domain_train_size.csv", "large_domain_unequal.csv"):
        assert (large_out / name).stat().st_size > 100, name
    assert (large_out / "large_domain.png").stat().st_size > 20_000


def test_large_domain_cost(large_out):
    rows = read_rows(large_out / "large_domain_cost.csv")
    assert int(rows[-1]["N"]) >= 2**14
    for r in rows:
        assert _f(r, "solve_s") > 0 and _f(r, "peak_MiB") > 0
        assert 0 < int(r["gmres_its"]) < 500 and 0 < int(r["active_set_its"]) < 50
    # fixed dx: the same contact at every N once the images are gone
    assert all(_f(r, "a_minus_a_last") < 1e-8 for r in rows[1:])
    # memory grows with N
    assert _f(rows[-1], "peak_MiB") > 2 * _f(rows[0], "peak_MiB")
    plan = read_rows(large_out / "large_domain_planning.csv")
    assert all(_f(r, "measure_plan_s") > 0 and _f(r, "wisdom_replan_ms") > 0 for r in plan)


def test_large_domain_trains(large_out):
    rows = [r for r in read_rows(large_out / "large_domain_train.csv") if r["status"] == "ok"]
    assert len(rows) >= 3 and int(rows[0]["M"]) == 4
    rows.sort(key=lambda r: _f(r, "spacing"))
    inter = [abs(_f(r, "d_mid_rel")) for r in rows]
    assert inter == sorted(inter, reverse=True)  # neighbours matter less when further apart
    assert inter[-1] < 1e-2 < inter[0]
    uneq = read_rows(large_out / "large_domain_unequal.csv")
    for r in uneq:  # the widely spaced train reproduces each isolated cylinder
        assert abs(_f(r, "a_rel_s25")) < 1e-5
        assert abs(_f(r, "iso_vs_front_door")) < 2e-3
