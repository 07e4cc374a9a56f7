import json

import numpy as np
import pytest

from spectral_contact.cli.main import main
from spectral_contact.result import JSON_KEYS, PROFILE_COLUMNS


def test_default_scene_summary(capsys):
    assert main(["solve", "--tol", "1e-3"]) == 0
    out = capsys.readouterr().out
    assert "half-width" in out and "mm" in out and "P_L = 200 N/m" in out


def test_json_has_every_key(capsys):
    assert main(["solve", "--json", "--tol", "1e-3", "--mu", "-1"]) == 0
    rec = json.loads(capsys.readouterr().out)
    for key in JSON_KEYS:
        assert key in rec
    assert rec["mu"] == -1 and rec["x0_m"] == -rec["contact_center_m"]
    assert rec["contact_center_m"] < 0  # sliding toward -x


def test_profiles_and_plot(tmp_path, capsys):
    csv, png = tmp_path / "p.csv", tmp_path / "p.png"
    assert main(["solve", "--tol", "1e-3", "--profiles", str(csv), "--plot", str(png),
                 "--model", "goodman"]) == 0
    header = csv.read_text().splitlines()[0]  # no comment lines: metadata in p.meta.json
    assert header.split(",") == list(PROFILE_COLUMNS)
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    dx = data[1, 0] - data[0, 0]
    assert np.sum(data[:, 3]) * dx == pytest.approx(-200.0, rel=1e-8)
    assert png.stat().st_size > 10_000


@pytest.mark.parametrize("argv", [
    ["solve", "--young", "-1"], ["solve", "--load", "nan"], ["solve", "--tol", "0.2"],
    ["solve", "--radius", "abc"], ["solve", "--model", "foo"], ["nosuch"], ["solve", "--bogus"],
    # found by review: these used to end in tracebacks
    ["solve", "--grid-points", "65"], ["solve", "--domain-length", "0.004"],
    ["solve", "--tol", "1e-15"], ["solve", "--load", "1e-12"], ["solve", "--plot", "x.txt"],
    ["solve", "--method", "abel", "--domain-length", "0.01"],
])
def test_bad_input_exits_2_with_one_line(argv, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv + (["--profiles", "p.csv"] if argv[0] == "solve" else [])) == 2
    assert not any(tmp_path.iterdir())  # nothing written
    err = capsys.readouterr().err.strip()
    assert err and len(err.splitlines()) == 1 and "Traceback" not in err
