from studies import paper_figures

from .conftest import assert_opens_plainly, read_rows


def test_paper_figures_quick(tmp_path, capsys):
    assert paper_figures.main(["--quick", "--out", str(tmp_path)]) == 0
    for name in ("surface_mu", "surface_load", "base_mu", "base_load"):
        assert (tmp_path / f"{name}.png").stat().st_size > 10_000
        assert_opens_plainly(tmp_path / f"profiles_{name}.csv")
    rows = read_rows(tmp_path / "widths.csv")
    assert len(rows) == 6
    for r in rows:
        w, hertz = float(r["width_exact_mm"]), float(r["hertz_width_mm"])
        assert 0 < w  # a film on a rigid base is stiffer than the half-space ...
        if float(r["mu"]) == 0.3 or float(r["load_N_per_m"]) == 20:
            assert float(r["width_goodman_mm"]) < hertz  # ... so its frictionless contact is narrower
    assert "caption" in capsys.readouterr().out
