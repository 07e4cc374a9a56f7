"""The model-map and peers studies, --quick, into tmp_path."""
import math
import sys

import pytest

from studies import model_map, peers

from .conftest import read_rows


def test_model_map_quick(tmp_path, capsys):
    assert model_map.main(["--quick", "--out", str(tmp_path)]) == 0
    for name in ("model_map.csv", "model_map_fit.csv", "model_map_auto.csv", "model_map.png"):
        assert (tmp_path / name).stat().st_size > 0, name
    assert (tmp_path / "model_map.png").stat().st_size > 20_000
    rows = read_rows(tmp_path / "model_map.csv")
    assert len(rows) == 36
    for r in rows:
        for tag in ("H", "G"):
            e = float(r[f"{tag}_max"])
            assert math.isfinite(e) and 0 <= e < 10
        if float(r["mu"]) == 0:
            assert float(r["G_max"]) < 1e-12  # Goodman is the exact model without friction
    # Hertz's error grows with the contact (film stiffening), Goodman's with the friction
    h0 = sorted((float(r["s"]), float(r["H_a"])) for r in rows if float(r["mu"]) == 0)
    assert all(b[1] > a[1] for a, b in zip(h0, h0[1:]))
    assert h0[0][1] == pytest.approx(0.5 * h0[0][0] ** 2, rel=0.1)  # a shrinks by ~0.5 (a/h)^2
    # the stored bound is never below a measured error where auto could use it
    fit = read_rows(tmp_path / "model_map_fit.csv")
    stored_all = [r for r in fit if r["bound"].startswith("stored") and r["rows"] == "all"][0]
    assert int(stored_all["hertz_violations"]) == 0 and int(stored_all["goodman_violations"]) == 0
    for r in read_rows(tmp_path / "model_map_auto.csv"):
        assert int(r["picks_over_tol"]) == 0
    out = capsys.readouterr().out
    assert "Model errors against the exact model" in out and "fit" in out


def test_peers_quick_whatever_is_installed(tmp_path, capsys):
    assert peers.main(["--quick", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "peers.png").stat().st_size > 0
    rows = read_rows(tmp_path / "peers.csv")
    ours = [r for r in rows if r["version"] == "this"]
    assert len(ours) == 3 and all(float(r["residual"]) < 1e-8 for r in ours)  # A, B, C nu=0.3
    versions = peers.peers_available()
    for r in rows:
        if r["solver"].startswith("ContactMechanics") or r["solver"].startswith("tamaas"):
            pkg = "ContactMechanics" if r["solver"].startswith("Contact") else "tamaas"
            if not peers.present(versions, pkg):
                assert r["version"] == "absent"
                continue
            assert not r["note"].startswith("failed"), r["note"]
            if "film" in r["solver"]:  # the same problem: pressures agree closely
                assert float(r["dp_rel"]) < 1e-4
            else:  # the half-space: near Hertz, off the film by the film's effect
                assert float(r["dp_hertz"]) < 0.05
            mine = next(o for o in ours if o["case"] == r["case"])  # ours on the same case
            assert abs(float(r["a_nodes"]) - float(mine["a_nodes"])) < 1e-9 + 2 * float(r["L_h"]) / int(r["N"])
    assert "ContactMechanics:" in capsys.readouterr().out


def test_peers_absent_still_exits_0(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "ContactMechanics", None)  # import raises ImportError
    monkeypatch.setitem(sys.modules, "tamaas", None)
    assert peers.main(["--quick", "--out", str(tmp_path)]) == 0
    rows = read_rows(tmp_path / "peers.csv")
    assert {r["version"] for r in rows if r["version"] not in ("this", "-")} == {"absent"}
    out = capsys.readouterr().out
    assert "peers absent: ContactMechanics, tamaas" in out
