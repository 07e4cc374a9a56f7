"""The 3D studies run (quick modes) and write what they say."""
import csv

import pytest


@pytest.mark.parametrize("name, csvname, columns", [
    ("finite_cylinder", "finite_cylinder.csv",
     {"P_N", "line_load_y0_N_per_m", "sensor_Szz_integral_N_per_m", "sensor_ratio_y0",
      "static_width_y0_mm", "max_diff_2D_at_line_load"}),
    ("sphere_sliding", "sphere_sliding.csv",
     {"aH_over_h", "mu", "radius_exact_h", "radius_goodman_h", "centroid_exact_h"}),
    ("three_d_cost", "three_d_cost.csv",
     {"nx", "solve_s", "fft_pair_ms", "gmres_its", "active_set_its"}),
])
def test_three_d_study_quick(tmp_path, name, csvname, columns):
    mod = __import__(f"studies.{name}", fromlist=["main"])
    assert mod.main(["--quick", "--out", str(tmp_path)]) == 0
    with (tmp_path / csvname).open() as fh:
        rows = list(csv.DictReader(fh))
    assert rows and columns <= set(rows[0])
    assert all((tmp_path / f).stat().st_size > 1000 for f in tmp_path.iterdir() if f.suffix == ".png")
    if name == "finite_cylinder":
        # the y = 0 line carries about P/L (within 10 %) in the model: a finding, see README
        for r in rows:
            assert 0.5 < float(r["line_load_y0_N_per_m"]) / float(r["P_over_L_N_per_m"]) < 1.1
    if name == "sphere_sliding":
        fr = [r for r in rows if float(r["mu"]) == 0.0]
        assert all(abs(float(r["centroid_exact_h"])) < 1e-9 for r in fr)
