"""The beyond_amontons study, --quick, into tmp_path."""
import math

from studies import beyond_amontons

from .conftest import read_rows


def test_beyond_amontons_quick(tmp_path, capsys):
    assert beyond_amontons.main(["--quick", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "beyond_amontons.png").stat().st_size > 20_000
    rows = read_rows(tmp_path / "beyond_amontons.csv")
    assert len(rows) == 4 * 4
    for r in rows:
        for k in ("chi_zz", "chi_xz", "chi_zz_fit", "chi_xz_fit"):
            assert math.isfinite(float(r[k])) and 0 <= float(r[k]) < 1
        # the refit can only lower the misfit of the paper's model
        assert float(r["chi_zz_fit"]) <= float(r["chi_zz"]) + 1e-3
        if r["refinement"].startswith("power"):  # n = 0.047: Q/P within 1 % of mu_d
            assert abs(float(r["Q_over_P"]) / float(r["mu_d"]) - 1) < 0.01
        else:
            assert float(r["Q_over_P"]) == float(r["mu_d"])
    # the compliant interface widens the contact at every operating point
    for r in rows:
        if r["refinement"].startswith(("C =", "exponential")):
            assert float(r["a_mm"]) > float(r["a_ref_mm"])
    goodman = read_rows(tmp_path / "beyond_amontons_goodman.csv")
    assert len(goodman) == 12
    # Goodman's error grows with mu_d in every slice (the introduction's third claim)
    out = capsys.readouterr().out
    assert "lower mu_d: holds monotonically in 6 of 6 slices" in out
