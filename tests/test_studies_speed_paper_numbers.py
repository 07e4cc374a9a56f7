"""The speed_vs_accuracy and paper_numbers studies (--quick) into a temporary folder."""

from studies import paper_numbers, speed_vs_accuracy

from .conftest import read_rows


def test_speed_vs_accuracy_quick(tmp_path, capsys):
    assert speed_vs_accuracy.main(["--quick", "--out", str(tmp_path)]) == 0
    for name in ("paper", "thin"):
        assert (tmp_path / f"speed_vs_accuracy_{name}.png").stat().st_size > 10_000
    rows = read_rows(tmp_path / "speed_vs_accuracy.csv")
    for scene in ("paper", "thin"):
        fft = [r for r in rows if r["scene"] == scene and r["sweep"] == "fft tol"]
        errs = [float(r["err_scalar"]) for r in fft]
        tols = [float(r["param"]) for r in fft]
        assert tols == sorted(tols, reverse=True) and len(fft) >= 3
        assert errs[-1] < errs[0] / 10  # smaller tol, smaller error
        for r, tol in zip(fft, tols):  # and the tolerance is met, with the estimate covering it
            assert float(r["err_scalar"]) <= tol
            assert float(r["err_base"]) <= 10 * tol
            assert float(r["error_estimate"]) >= float(r["err_scalar"])
        abel = [r for r in rows if r["scene"] == scene and r["sweep"] == "abel nodes"]
        n = [int(r["N_or_nodes"]) for r in abel]
        e = [float(r["err_scalar"]) for r in abel]
        assert n == sorted(n) and n[0] <= 8 and n[-1] >= 24
        assert e[-1] < 1e-12 and e[0] > 1e3 * e[-1]  # spectral in the node count
        for lo, hi in zip(e, e[1:]):
            assert hi < lo or hi < 1e-13  # falls until roundoff
        assert all(float(r["median_ms"]) > 0 for r in rows)
    ref = read_rows(tmp_path / "speed_vs_accuracy_reference.csv")
    for r in ref:  # the reference is converged and the FFT agrees with it
        assert float(r["abel64_scalar_diff"]) < 1e-12
        assert float(r["fft_scalar_diff"]) < 1e-4
    win = read_rows(tmp_path / "speed_vs_accuracy_winners.csv")
    assert {r["winner"] for r in win} <= {"fft", "abel", "none"}
    # only Abel reaches 1e-8 (the FFT's fixed period and edge error floor it near 1e-6)
    deep = [r for r in win if float(r["target"]) <= 1e-8]
    assert deep and all(r["winner"] != "fft" for r in deep)
    assert all(r["winner"] == "abel" for r in deep if r["runs"] == "any")
    out = capsys.readouterr().out
    assert "Summary" in out and "defaults (tol 1e-4)" in out


def test_paper_numbers_quick(tmp_path, capsys):
    assert paper_numbers.main(["--quick", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "paper_numbers.png").stat().st_size > 10_000
    rows = read_rows(tmp_path / "paper_numbers.csv")
    a = [r for r in rows if r["item"].startswith("a")]
    b = [r for r in rows if r["item"].startswith("b")]
    c = [r for r in rows if r["item"].startswith("c")]
    assert len(a) == 20 and len(b) == 10 and len(c) == 6
    for r in rows:
        # both methods agree; the tables carry the caption's numbers
        assert abs(float(r["fft_mm"]) / float(r["abel_mm"]) - 1) < 2e-4
        assert float(r["fft_abel_rel"]) < 2e-4
        assert abs(float(r["diff_mm"]) - (float(r["abel_mm"]) - float(r["caption_mm"]))) < 1e-9
    for r in a + c:
        if r["model"] in ("goodman", "frictionless"):  # frictionless film: narrower than Hertz
            assert float(r["abel_mm"]) < float(r["hertz_mm"])
            assert r["ours_le_hertz"] == "1"
    # the caption's 20 N/m widths exceed Hertz: the study must say so
    first = [r for r in a if float(r["load_N_per_m"]) == 20.0]
    assert all(r["caption_le_hertz"] == "0" for r in first)
    assert [float(r["caption_mm"]) for r in a if r["model"] == "exact"] == \
        paper_numbers.CAPTION_WIDTHS_EXACT
    # friction widens our contact: a grows with mu at 200 N/m
    ab = [float(r["abel_mm"]) for r in b]
    assert ab == sorted(ab) and ab[-1] - ab[0] > 0.1
    # frictionless widths grow with load
    aw = [float(r["abel_mm"]) for r in a if r["model"] == "goodman"]
    assert aw == sorted(aw)
    fits = read_rows(tmp_path / "paper_numbers_fits.csv")
    assert len(fits) == 8 and all(float(r["rms_mm"]) >= 0 for r in fits)
    assert (tmp_path / "paper_numbers_interpretations.csv").exists()
    assert (tmp_path / "paper_numbers_static.csv").exists()
    out = capsys.readouterr().out
    assert "Summary" in out and "Hertz" in out
