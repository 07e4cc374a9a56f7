import pytest

pytest.importorskip("pandas", reason="the sweep extra is not installed")
pytest.importorskip("distributed", reason="the sweep extra is not installed")

from spectral_contact.cli.main import main  # noqa: E402

from .conftest import read_rows  # noqa: E402


def test_benchmark_sweep_quick_through_the_cli(tmp_path, capsys):
    assert main(["study", "benchmark_sweep", "--quick", "--out", str(tmp_path)]) == 0
    rows = read_rows(tmp_path / "benchmark_sweep.csv")
    assert [r["engine"] for r in rows] == ["serial", "dask-1", "dask-2"]
    for r in rows:
        assert int(r["scenes"]) == int(r["ok"]) == 40 and r["identical"] == "True"
        assert float(r["wall_s"]) > 0 and float(r["solve_sum_s"]) > 0
    assert 1 <= int(rows[1]["tasks"]) <= 40 and 1 <= int(rows[2]["tasks"]) <= 40
    assert float(rows[2]["noop_task_ms"]) > 0
    assert "target <= 0.6" in capsys.readouterr().out
