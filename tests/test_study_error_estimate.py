from studies import error_estimate

from .conftest import read_rows


def test_error_estimate_quick(tmp_path, capsys):
    assert error_estimate.main(["--quick", "--out", str(tmp_path)]) == 0
    rows = read_rows(tmp_path / "error_estimate.csv")
    assert len(rows) == 6 and all(r["status"] == "ok" for r in rows)
    for r in rows:
        assert float(r["ref_check"]) < 1e-10  # the reference is converged far below tol
        assert float(r["true_error"]) <= float(r["tol"])  # the solver meets its tolerance here
        assert float(r["error_estimate"]) > 0
    assert (tmp_path / "error_estimate.png").stat().st_size > 10_000
    assert "ratio estimate / true error" in capsys.readouterr().out
