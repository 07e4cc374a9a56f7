import csv

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
    printed = capsys.readouterr().out
    assert "GMRES iterations" in printed
    # issue 13's targets: each printed and written against its limit, met or not
    # (commas inside text cells are written as ";": plain CSV readers split on commas)
    targets = {r["target"].replace(";", ","): r
               for r in csv.DictReader((tmp_path / "benchmark_targets.csv").open())}
    peer = {k: targets.pop(k) for k in list(targets) if k.startswith("vs ")}
    assert len(targets) >= 6 and "wall / CPU time" in printed
    # the peers' targets (studies.peers): film and half-space, each peer, N = 2^12 with --quick
    assert len(peer) == 4 and all("N=2^12" in k for k in peer)
    for r in peer.values():
        assert float(r["limit"]) == 10
        if r["status"] in ("met", "not met"):  # a speed-up: met when the ratio reaches the limit
            assert (r["status"] == "met") == (float(r["measured"]) >= 10)
        else:
            assert r["status"].startswith("not measured")
    for r in targets.values():
        assert r["status"] in ("met", "not met", "not measured (quick)")
        if r["status"] != "not measured (quick)":
            assert (r["status"] == "met") == (float(r["measured"]) <= float(r["limit"]))
    err = targets["paper scene, fft, tol 1e-4: true error vs abel tol 1e-10"]
    assert 0 < float(err["measured"]) < 1e-4  # the solver's accuracy, not a speed
    assert float(targets["abel, tol 1e-8: solve time"]["measured"]) > 0
    assert targets["fixed grids >= 2^16, cold start: solve time"]["status"].startswith("not measured")
    # the error estimate on the verification sweep (its 6-run version with --quick)
    below = [r for name, r in targets.items() if name.startswith("error estimate below")]
    assert len(below) == 1 and below[0]["measured"] == "0" and below[0]["status"] == "met"
    assert any(name.startswith("error estimate / true error, median") for name in targets)
    for e in (20, 22):  # the absolute targets of the full run
        assert targets[f"fixed grid 2^{e}, cold start: solve time"]["status"].startswith("not measured")


def test_unknown_study_exits_2(capsys):
    assert main(["study", "nosuch"]) == 2
    assert "unknown study" in capsys.readouterr().err
