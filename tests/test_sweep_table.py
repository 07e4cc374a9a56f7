"""The sweep's table (issue 24, sweeps): one name per quantity, with its unit; the grid's
request and what was used, the same form on line and surface rows; write errors that name the
user's path (never a temporary) and come before the progress header."""
from __future__ import annotations

import os

import pytest

pd = pytest.importorskip("pandas", reason="the sweep extra is not installed")

from spectral_contact import solve  # noqa: E402
from spectral_contact.cli.main import main  # noqa: E402
from spectral_contact.physics.options import option  # noqa: E402
from spectral_contact.sweep import OPTIONS, column, option_of, sweep, table_columns  # noqa: E402


def test_one_column_per_quantity_named_with_its_unit():
    cols = table_columns()
    assert len(cols) == len(set(cols))
    for name in OPTIONS:  # each option once, under the JSON key of solve (its unit in its name)
        assert column(name) == (option(name).json or name) and column(name) in cols
        assert option_of(column(name)) == option_of(name.replace("_", "-")) == name
        if option(name).unit:
            assert column(name) != name and name not in cols
    for old in ("load", "force", "young", "radius", "thickness", "solved_mu", "solved_indenter",
                "solved_load_N_per_m"):
        assert old not in cols
    for k in ("load_N_per_m", "force_N", "young_Pa", "radius_m", "domain_length_m"):
        assert k in cols and f"solved_{k}" not in cols or k == "domain_length_m"


def test_grid_points_the_request_and_what_was_used_alike_on_lines_and_surfaces():
    df = sweep(indenter="line,sphere", mu=1.0, tol=1e-2, engine="serial", progress=False)
    line, sph = df.iloc[0], df.iloc[1]
    assert line["indenter"] == "line" and sph["indenter"] == "sphere"
    for row in (line, sph):  # the request: empty (chosen from tol)
        assert pd.isna(row["grid_points"]) and pd.isna(row["domain_length_m"])
        assert float(row["solved_grid_points"]).is_integer() and row["solved_grid_points"] >= 64
        assert row["solved_domain_length_m"] > 0
    r2 = solve(load=200.0, mu=1.0, tol=1e-2).summary()
    assert line["solved_grid_points"] == r2["grid_points"]
    assert pd.isna(line["solved_grid_points_y"]) and pd.isna(line["solved_domain_length_y_m"])
    r3 = solve(indenter="sphere", force=1.0, mu=1.0, tol=1e-2).summary()
    assert [sph["solved_grid_points"], sph["solved_grid_points_y"]] == r3["grid_points"]
    assert [sph["solved_domain_length_m"], sph["solved_domain_length_y_m"]] == r3["domain_length_m"]
    fixed = sweep(indenter="line,sphere", mu=1.0, tol=1e-2, grid_points=64, engine="serial",
                  progress=False)
    assert fixed["grid_points"].tolist() == [64, 64] and fixed["solved_grid_points"].tolist() == [64, 64]
    assert fixed["solved_grid_points_y"].iloc[1] == 64


def test_an_option_left_empty_holds_the_value_the_solve_used():
    df = sweep(indenter="paraboloid", radius=0.05, force=0.2, mu=0.0, tol=1e-2,
               engine="serial", progress=False)
    assert df["status"].iloc[0] == "ok", df["message"].iloc[0]
    assert df["radius_x_m"].iloc[0] == df["radius_y_m"].iloc[0] == 0.05
    assert pd.isna(df["load_N_per_m"].iloc[0])


def _run(argv, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    capsys.readouterr()
    code = main(argv)
    return code, capsys.readouterr().err.strip().splitlines()


@pytest.mark.parametrize("blocker", ["summary.csv", "scenes", "summary.parquet"])
def test_an_output_that_cannot_be_written_is_refused_before_the_header(blocker, tmp_path,
                                                                      capsys, monkeypatch):
    out = tmp_path / "o"
    out.mkdir()
    if blocker == "scenes":
        (out / blocker).write_text("a file where the sweep keeps its scenes\n")
    else:
        (out / blocker).mkdir()
    code, err = _run(["sweep", "--load", "100", "--tol", "1e-2", "--serial", "--out", "o"],
                     tmp_path, capsys, monkeypatch)
    assert code == 2 and len(err) == 1, err  # no progress header, no bar
    assert f"o/{blocker}" in err[0] and ".tmp" not in err[0] and "--out" in err[0], err
    assert sorted(os.listdir(out)) == [blocker]


def test_a_failed_write_names_the_users_file_not_the_temporary(tmp_path, capsys, monkeypatch):
    import spectral_contact.sweep.store as store

    real = store.os.replace

    def full(src, dst):  # the disk fills up as summary.csv is put in place
        if str(dst).endswith("summary.csv"):
            raise OSError(28, "No space left on device", str(src))
        return real(src, dst)

    monkeypatch.setattr(store.os, "replace", full)
    code, err = _run(["sweep", "--load", "100", "--tol", "1e-2", "--serial", "--out", "o"],
                     tmp_path, capsys, monkeypatch)
    assert code == 2 and err[-1].startswith("error: "), err
    assert str(tmp_path / "o" / "summary.csv") in err[-1] or "o/summary.csv" in err[-1], err
    assert ".tmp" not in err[-1] and "No space left on device" in err[-1]
    assert not [f for f in os.listdir(tmp_path / "o") if f.endswith(".tmp")]
