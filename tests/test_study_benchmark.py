from spectral_contact.cli.main import main

from .conftest import read_rows


def test_benchmark_quick_through_the_cli(tmp_path, capsys):
    assert main(["study", "benchmark", "--quick", "--out", str(tmp_path)]) == 0
    rows = read_rows(tmp_path / "benchmark.csv")
    assert rows[0]["case"].startswith("auto") and len(rows) == 4
    fixed = rows[1:]
    for r in fixed:
        assert float(r["solve_ms"]) > 0 and float(r["fft_pair_us"]) > 0
        assert int(r["gmres_its"]) >= int(r["active_set_its"]) > 0
    # the preconditioned iteration count does not grow materially with N
    assert int(fixed[-1]["gmres_its"]) <= 2 * int(fixed[0]["gmres_its"])
    assert (tmp_path / "benchmark.png").stat().st_size > 10_000
    start = {r["case"].split(" (")[0]: float(r["median_ms"]) for r in read_rows(tmp_path / "benchmark_startup.csv")}
    assert set(start) == {"interpreter alone", "import spectral_contact", "spectral-contact solve"}
    assert start["spectral-contact solve"] > start["interpreter alone"] > 0
    assert "GMRES iterations" in capsys.readouterr().out


def test_unknown_study_exits_2(capsys):
    assert main(["study", "nosuch"]) == 2
    assert "unknown study" in capsys.readouterr().err
