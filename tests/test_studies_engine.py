"""The studies that sweep run their points through spectral_contact.sweep.map_tasks
(studies/_common.run_points): the engine chosen from --quick / --workers / --serial, bad --workers
refused, and the tables the same bit for bit on a LocalCluster as in this process."""
import pytest

from studies import _common, paper_figures


def _engine_for(argv, monkeypatch):
    import spectral_contact.sweep as sw

    seen = {}

    def fake(fn, items, *, engine, workers, unit):
        seen.update(engine=engine, workers=workers, fn=fn.__name__)
        return [fn.__name__ for _ in items]

    monkeypatch.setattr(sw, "map_tasks", fake)
    args, _ = _common.parse(argv, "t", "unused", engine=True)
    assert _common.run_points(args, "studies.sphere_sliding", "sphere_point", [1, 2], "x") == \
        ["sphere_point"] * 2
    return seen["engine"], seen["workers"]


@pytest.mark.parametrize("argv, engine, workers", [
    (["--quick"], "serial", None),             # a LocalCluster's start-up would dominate
    (["--quick", "--workers", "2"], "auto", 2),
    (["--serial"], "serial", None),
    ([], "auto", None),                        # full runs: a LocalCluster of the cores
    (["--workers", "3"], "auto", 3),
])
def test_engine_choice(argv, engine, workers, monkeypatch, tmp_path):
    assert _engine_for(argv + ["--out", str(tmp_path)], monkeypatch) == (engine, workers)


def test_bad_workers_exit_2_with_one_line(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        paper_figures.main(["--quick", "--workers", "0", "--out", str(tmp_path / "o")])
    assert e.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--workers" in err[0] and ">= 1" in err[0]
    assert not (tmp_path / "o").exists()


def test_paper_figures_local_cluster_tables_are_bit_identical(tmp_path):
    pytest.importorskip("distributed")
    a, b = tmp_path / "serial", tmp_path / "cluster"
    assert paper_figures.main(["--quick", "--out", str(a)]) == 0
    assert paper_figures.main(["--quick", "--workers", "2", "--out", str(b)]) == 0
    names = sorted(p.name for p in a.glob("*.csv"))
    assert len(names) == 5
    for name in names:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name


def test_cli_study_passes_the_engine_options(tmp_path, monkeypatch):
    from spectral_contact.cli.main import main

    seen = []
    monkeypatch.setattr(paper_figures, "main", lambda argv: seen.append(argv) or 0)
    assert main(["study", "paper_figures", "--quick", "--serial", "--out", str(tmp_path)]) == 0
    assert main(["study", "paper_figures", "--workers", "2", "--out", str(tmp_path)]) == 0
    assert seen == [["--quick", "--out", str(tmp_path), "--serial"],
                    ["--out", str(tmp_path), "--workers", "2"]]


@pytest.mark.parametrize("argv, words", [
    (["study", "benchmark", "--quick", "--workers", "2"], "takes no --workers"),
    (["study", "paper_figures", "--quick", "--workers", "0"], "--workers must be >= 1"),
])
def test_cli_study_bad_engine_options_exit_2(argv, words, tmp_path, capsys):
    from spectral_contact.cli.main import main

    assert main(argv + ["--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0]
    assert not (tmp_path / "o").exists()
