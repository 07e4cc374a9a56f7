"""MEMS sensor: apparatus functions, sensor view, axisymmetric base stresses, calibration round
trips, comparison with the models, measured-file validation and the CLI subcommands."""
import json
import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import expm

from spectral_contact.errors import InputError
from spectral_contact.instruments.apparatus import G_XZ, G_ZZ, GaussianFoot, TabulatedApparatus, load_apparatus_csv
from spectral_contact.instruments.axisym import (
    base_stresses_3d,
    flat_punch_base_stresses,
    flat_punch_transform,
    plane_grid,
    punch_sensitivity,
)
from spectral_contact.instruments.calibration import calibrate
from spectral_contact.instruments.measured_io import read_measured_profile, read_radial_profile
from spectral_contact.instruments.sensor import convolve_line, sensor_profiles, sensor_view
from spectral_contact.numerics.fft import get_rfft
from spectral_contact.physics.transfer import transfer_functions


def _write(path, text):
    path.write_text(text)
    return path


def _csv(path, columns: dict, comment="synthetic"):
    names = list(columns)
    data = np.column_stack([columns[n] for n in names])
    with open(path, "w") as fh:
        fh.write(f"# {comment}\n" + ",".join(names) + "\n")
        np.savetxt(fh, data, delimiter=",", fmt="%.17g")
    return path


# --- apparatus functions ----------------------------------------------------------------------

def test_line_form_of_2d_gaussian_is_1d_gaussian_of_same_sd():
    s = 561e-6
    G = GaussianFoot(s)
    x = np.linspace(-4e-3, 4e-3, 41)
    expected = np.exp(-0.5 * (x / s) ** 2) / (math.sqrt(2 * math.pi) * s)
    assert np.allclose(G.line(x), expected, rtol=1e-12)
    # and it is the y-integral of the plane function
    for xi in (0.0, 0.4e-3, 1.3e-3):
        yint = 2 * quad(lambda y: G.radial(math.hypot(xi, y)), 0, 10e-3)[0]
        assert G.line(xi) == pytest.approx(yint, rel=1e-9)


@pytest.mark.parametrize("G", [G_ZZ, G_XZ], ids=["G_zz", "G_xz"])
def test_unit_integrals_plane_line_and_transform(G):
    pts = [G.foot_radius] if G.f else None
    plane = quad(lambda r: 2 * math.pi * r * G.radial(r), 0, 12e-3, points=pts, limit=200)[0]
    line = quad(lambda x: G.line(x), -12e-3, 12e-3,
                points=[-G.foot_radius, G.foot_radius] if G.f else None, limit=200)[0]
    assert plane == pytest.approx(1.0, abs=1e-9)
    assert line == pytest.approx(1.0, abs=1e-9)
    assert G.transform(0.0) == pytest.approx(1.0, abs=1e-15)
    # the transform is the cosine transform of the line form
    for k in (700.0, 3000.0):
        num = quad(lambda x: G.line(x) * math.cos(k * x), -12e-3, 12e-3,
                   points=[-G.foot_radius, G.foot_radius] if G.f else None, limit=400)[0]
        assert G.transform(k) == pytest.approx(num, abs=1e-9)


def test_xz_foot_is_a_disc_of_diameter_2p7mm_at_4p1_percent_of_the_peak():
    gauss = lambda r: G_XZ.g0 * np.exp(-0.5 * (r / 688e-6) ** 2)  # noqa: E731
    for r in (0.2e-3, 1.0e-3, 1.34e-3):
        assert G_XZ.radial(r) - gauss(r) == pytest.approx(0.041 * G_XZ.radial(0.0), rel=1e-12)
    assert G_XZ.radial(1.36e-3) - gauss(1.36e-3) == pytest.approx(0.0, abs=1e-9)
    assert 0.07 < G_XZ.foot_weight < 0.08


def test_tabulated_apparatus_normalised_and_consistent(tmp_path):
    r = np.linspace(0, 4e-3, 161)
    T = TabulatedApparatus(r, 7.0 * G_XZ.radial(r))  # arbitrary scale: normalised here
    x = np.array([0.0, 0.5e-3, 1.0e-3, 2.0e-3])
    assert np.allclose(T.line(x), G_XZ.line(x), rtol=3e-3, atol=1.0)
    assert T.transform(np.array([0.0]))[0] == pytest.approx(1.0, rel=1e-6)
    f = _csv(tmp_path / "g.csv", {"r_m": r, "G": 3.0 * G_ZZ.radial(r)})
    L = load_apparatus_csv(f)
    assert L.radial(0.0) == pytest.approx(G_ZZ.radial(0.0), rel=1e-3)


# --- sensor view ------------------------------------------------------------------------------

def _hertz_like_base_stresses(P_L=100.0, mu=2.0, a=2e-3, h=2e-3, n=4096, L=0.08):
    """Base stresses of a Hertz-like pressure with Amontons shear (physics.md formulas)."""
    x = (np.arange(n) - n // 2) * (L / n)
    p = np.where(np.abs(x) < a, 2 * P_L / (math.pi * a * a) * np.sqrt(np.clip(a * a - x * x, 0,
                                                                          None)), 0.0)
    k = 2 * np.pi * np.fft.fftfreq(n, L / n)
    _, _, A, B, C = transfer_functions(np.abs(k) * h)
    szz1, sxz1 = np.fft.fft(-p), np.fft.fft(mu * p)
    s = np.sign(k)
    szz0 = np.fft.ifft(A * szz1 + 1j * s * B * sxz1).real
    sxz0 = np.fft.ifft(C * sxz1 + 1j * s * B * szz1).real
    return x, szz0, sxz0, p


def test_sensor_integrals_and_signs_on_synthetic_profile():
    x, szz, sxz, p = _hertz_like_base_stresses()
    dx = x[1] - x[0]
    P_L = np.sum(p) * dx
    v = sensor_profiles(x, szz, sxz, periodic=True)
    assert np.sum(v["S_zz_Pa"]) * dx == pytest.approx(P_L, rel=1e-10)
    assert np.sum(v["S_xz_Pa"]) * dx == pytest.approx(2.0 * P_L, rel=1e-10)
    assert v["S_zz_Pa"].max() > 0 and v["S_zz_Pa"].max() > -v["S_zz_Pa"].min()  # compression > 0
    assert np.allclose(v["U_zz_mV"], v["S_zz_Pa"] * 19.00e-5)
    assert np.allclose(v["U_xz_mV"], v["S_xz_Pa"] * 7.95e-5)


def test_sensor_convolution_matches_direct_quadrature():
    x, szz, _, _ = _hertz_like_base_stresses()
    dx = x[1] - x[0]
    out = convolve_line(x, szz, G_XZ, periodic=False)
    for i in (1800, 2048, 2300):
        direct = np.sum(G_XZ.line(x[i] - x) * szz) * dx
        assert out[i] == pytest.approx(direct, rel=2e-3, abs=1e-6 * np.abs(szz).max())


def test_sensor_view_of_solved_profile_integrates_to_load_and_friction():
    from spectral_contact import Scene, solve

    r = solve(Scene(load=200.0, mu=2.0), tol=1e-3)
    v = sensor_view(r)
    dx = r.x_m[1] - r.x_m[0]
    assert np.sum(v["S_zz_Pa"]) * dx == pytest.approx(200.0, rel=1e-8)
    assert np.sum(v["S_xz_Pa"]) * dx == pytest.approx(400.0, rel=1e-8)
    assert set(v) == {"S_zz_Pa", "S_xz_Pa", "U_zz_mV", "U_xz_mV"}


@pytest.mark.parametrize("gain", [0.0, -1.0, float("nan")])
def test_sensor_rejects_bad_gain(gain):
    x, szz, sxz, _ = _hertz_like_base_stresses(n=256)
    with pytest.raises(InputError, match="A_zz"):
        sensor_profiles(x, szz, sxz, A_zz_mV_per_bar=gain)


# --- axisymmetric base stresses ---------------------------------------------------------------

def _propagator_base_traction(kx, ky, h=1.0):
    """Independent check: (sxz, syz, szz)(z=0) = M (sxz, syz, szz)(z=h) for one Fourier mode of
    the incompressible layer bonded at z = 0, by the propagator matrix of the 3D equations."""
    i = 1j
    M = np.zeros((6, 6), complex)  # state (ux, uy, uz, sxz, syz, szz), G = 1
    M[0, 3], M[0, 2] = 1.0, -i * kx
    M[1, 4], M[1, 2] = 1.0, -i * ky
    M[2, 0], M[2, 1] = -i * kx, -i * ky
    sxx = np.array([4 * i * kx, 2 * i * ky, 0, 0, 0, 1])
    syy = np.array([2 * i * kx, 4 * i * ky, 0, 0, 0, 1])
    sxy = np.array([i * ky, i * kx, 0, 0, 0, 0])
    M[3] = -i * kx * sxx - i * ky * sxy
    M[4] = -i * kx * sxy - i * ky * syy
    M[5, 3], M[5, 4] = -i * kx, -i * ky
    return np.linalg.inv(expm(M * h)[3:, 3:])


@pytest.mark.parametrize("kx,ky", [(0.7, 0.0), (-1.3, 0.0), (0.6, 0.8), (-2.0, 1.5), (3.0, -4.0)])
def test_3d_transfer_relations_match_propagator_solution(kx, ky):
    t = np.array([0.3 - 0.2j, -0.5 + 0.1j, 1.0 + 0.4j])  # (sxz, syz, szz) at the surface
    ref = _propagator_base_traction(kx, ky) @ t
    zz, x, y = base_stresses_3d(t[2], t[0], t[1], kx, ky, 1.0)
    assert np.allclose([x, y, zz], ref, rtol=1e-10, atol=1e-12)


def test_flat_punch_base_stresses():
    b = flat_punch_base_stresses(1.0, dx_m=125e-6, r_max_m=24e-3)
    r = b["r_m"]
    assert np.trapezoid(2 * np.pi * r * b["sigma_zz_Pa"], r) == pytest.approx(-1.0, abs=2e-3)
    assert b["sigma_zz_Pa"][0] < 0 and b["sigma_xz_Pa"][0] == pytest.approx(0.0, abs=1e-6)
    assert b["sigma_xz_Pa"][1:40].min() > 0  # the base is dragged outward
    sens = punch_sensitivity()
    assert sens["zz"] < 0.02 and sens["xz"] < 0.02


# --- calibration round trip -------------------------------------------------------------------

DR, RMAX, H, A_TRUE = 100e-6, 12e-3, 2e-3, {"zz": 19.00, "xz": 7.95}


@pytest.fixture(scope="module")
def rod_scan():
    """Computed sigma on the calibration radii, and U = A G (*) sigma computed independently
    (twice finer 2D grid, analytic punch and apparatus transforms)."""
    from spectral_contact.instruments.axisym import _grid_size

    b = flat_punch_base_stresses(1.0, dx_m=DR, r_max_m=RMAX)
    r = b["r_m"]
    dxf = DR / 2
    n = _grid_size(RMAX, H, dxf, 16.0)
    ky, kx, k = plane_grid(n, dxf)
    zz, xz, _ = base_stresses_3d(-flat_punch_transform(k, 1.0, 250e-6), None, None, kx, ky, H)
    fft = get_rfft((n, n))
    prof = lambda spec: fft.backward(spec)[0, ::2][:r.size] / dxf**2  # noqa: E731
    U = {"zz": prof(-zz * G_ZZ.transform(k)) * A_TRUE["zz"] * 1e-5,
         "xz": prof(xz * G_XZ.transform(k)) * A_TRUE["xz"] * 1e-5}
    S = {"zz": -b["sigma_zz_Pa"], "xz": b["sigma_xz_Pa"]}
    return r, U, S


def _roundtrip(rod_scan, comp, method, eta, seed=0):
    r, U, S = rod_scan
    Un = U[comp] + eta * np.abs(U[comp]).max() * np.random.default_rng(seed).standard_normal(r.size)
    cal = calibrate(r, Un, S[comp], comp, method, n_boot=4, seed=seed)
    G = (G_ZZ if comp == "zz" else G_XZ).radial(r)
    w = r * (r <= 4e-3)  # plane L2 norm over the sensor's extent
    err_G = math.sqrt(np.sum(w * (cal.G - G) ** 2) / np.sum(w * G**2))
    err_A = cal.A_mV_per_bar / A_TRUE[comp] - 1.0
    return err_G, err_A, cal


# stated accuracy (relative L2 error of G over r <= 4 mm; relative error of A); noise = sd of
# white noise on U as a fraction of max |U|.  Worst of 6 noise seeds, G / A:
#   wiener zz 1.7 % / 0.05 %, 8.6 % / 0.4 %, 21.5 % / 2.9 %;  xz 2.4 / 0.06, 2.9 / 0.3, 7.7 / 2.7
#   ratio  zz 1.8 % / 0.07 %, 24 % / 0.8 %,  71 % / 6.8 %;    xz 2.5 / 1.7, 8.5 / 3.7, 52 / 21
# (noise 0, 0.1 %, 1 %); the paper's ratio is erratic at 1 % noise.  Bounds keep a margin.
BOUNDS = {
    ("wiener", 0.0): (0.03, 0.003), ("wiener", 1e-3): (0.12, 0.01), ("wiener", 1e-2): (0.30, 0.05),
    ("ratio", 0.0): (0.03, 0.03), ("ratio", 1e-3): (0.30, 0.06), ("ratio", 1e-2): (0.80, 0.25),
}


@pytest.mark.parametrize("comp", ["zz", "xz"])
@pytest.mark.parametrize("method", ["wiener", "ratio"])
def test_calibration_round_trip(rod_scan, comp, method):
    errs = []
    for eta in (0.0, 1e-3, 1e-2):
        err_G, err_A, cal = _roundtrip(rod_scan, comp, method, eta)
        bG, bA = BOUNDS[(method, eta)]
        assert err_G < bG, (comp, method, eta, err_G)
        assert abs(err_A) < bA, (comp, method, eta, err_A)
        assert cal.A_lo <= cal.A_mV_per_bar <= cal.A_hi
        errs.append(err_G)
    # grows gracefully: monotone within a small slack (and bounded, above)
    assert errs[0] <= errs[1] + 0.01 and errs[1] <= errs[2] + 0.01


def test_calibration_catches_sign_and_normalisation(rod_scan):
    r, U, S = rod_scan
    flipped = calibrate(r, U["zz"], -S["zz"], "zz", "wiener", n_boot=0)  # model sign by mistake
    assert flipped.A_mV_per_bar == pytest.approx(-19.0, rel=1e-2)
    doubled = calibrate(r, U["xz"], 2 * S["xz"], "xz", "wiener", n_boot=0)
    assert doubled.A_mV_per_bar == pytest.approx(7.95 / 2, rel=1e-2)
    # unit plane integral of the piecewise-linear G (exact quadrature)
    assert TabulatedApparatus._plane_integral(doubled.r_m, doubled.G) == pytest.approx(1.0,
                                                                                      rel=1e-9)


def test_calibrated_apparatus_feeds_the_sensor_view(rod_scan):
    _, _, cal = _roundtrip(rod_scan, "zz", "wiener", 1e-3)
    x, szz, sxz, _ = _hertz_like_base_stresses()
    ref = sensor_profiles(x, szz, sxz, periodic=True)
    got = sensor_profiles(x, szz, sxz, apparatus=(cal.apparatus(), None), periodic=True)
    assert np.abs(got["S_zz_Pa"] - ref["S_zz_Pa"]).max() < 0.02 * ref["S_zz_Pa"].max()
    assert np.allclose(got["S_xz_Pa"], ref["S_xz_Pa"])


# --- comparison with the models (through the CLI) ---------------------------------------------

def _synthetic_measurement(tmp_path, model, P=200.0, mu=2.0, offset=1.234e-3, eta=0.005,
                           half_window=16e-3, kind="S", seed=3, **scene_options):
    """The sensor view of ``model`` on Scene(load=P, mu=mu, **scene_options), shifted by
    ``offset``, with noise of ``eta`` times each component's peak, written as a measured CSV."""
    from spectral_contact import Scene, solve

    r = solve(Scene(load=P, mu=mu, **scene_options), model=model, tol=1e-4)
    v = sensor_view(r)
    x = np.arange(-half_window, half_window + 1e-9, 0.1e-3)
    rng = np.random.default_rng(seed)
    E = {}
    for c in ("zz", "xz"):
        e = np.interp(x - offset, r.x_m, v[f"S_{c}_Pa"])
        E[c] = e + eta * np.abs(e).max() * rng.standard_normal(x.size)
    noise_chi = {c: eta * np.abs(E[c]).max() * math.sqrt(x.size) / math.sqrt(np.sum(E[c] ** 2))
                 for c in E}
    if kind == "S":
        cols = {"x_m": x, "S_zz_Pa": E["zz"], "S_xz_Pa": E["xz"]}
    else:
        cols = {"x_m": x, "U_zz_mV": E["zz"] * 19.00e-5, "U_xz_mV": E["xz"] * 7.95e-5}
    return _csv(tmp_path / f"meas_{model}_{kind}.csv", cols), noise_chi


def test_compare_recovers_load_friction_offset(tmp_path, capsys):
    from spectral_contact.cli.main import main

    f, noise_chi = _synthetic_measurement(tmp_path, "exact")
    png = tmp_path / "cmp.png"
    assert main(["compare", str(f), "--json", "--plot", str(png)]) == 0
    rec = json.loads(capsys.readouterr().out)
    # integral estimates: the +-16 mm window truncates the tails by ~0.3 %
    assert rec["load_N_per_m"] == pytest.approx(200.0, rel=0.015)
    assert rec["mu"] == pytest.approx(2.0, rel=0.015)
    assert rec["offset_m"] == pytest.approx(1.234e-3, abs=30e-6)
    assert rec["fit_load_N_per_m"] == pytest.approx(200.0, rel=0.01)
    assert rec["fit_mu"] == pytest.approx(2.0, rel=0.01)
    assert rec["fit_offset_m"] == pytest.approx(1.234e-3, abs=20e-6)
    for c in ("zz", "xz"):
        assert rec[f"chi_{c}_exact"] < 1.3 * noise_chi[c]
        assert rec[f"fit_chi_{c}"] < 1.15 * noise_chi[c]
    assert rec["chi_zz_goodman"] > 2.0 * rec["chi_zz_exact"]
    assert rec["chi_xz_goodman"] > 1.5 * rec["chi_xz_exact"]
    assert png.stat().st_size > 10_000


def test_compare_prefers_the_model_that_made_the_data(tmp_path, capsys):
    from spectral_contact.cli.main import main

    f, noise_chi = _synthetic_measurement(tmp_path, "goodman", kind="U")
    assert main(["compare", str(f), "--json", "--no-fit"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["chi_zz_goodman"] < 1.3 * noise_chi["zz"]
    assert rec["chi_zz_exact"] > 1.5 * rec["chi_zz_goodman"]
    assert rec["fit_mu"] is None


# --- calibrate subcommand ---------------------------------------------------------------------

def test_calibrate_cli_writes_apparatus_csv_and_plot(tmp_path, capsys, rod_scan):
    from spectral_contact.cli.main import main

    r, U, S = rod_scan
    meas = _csv(tmp_path / "U.csv", {"r_m": r, "U_zz_mV": U["zz"], "U_xz_mV": U["xz"]})
    comp = _csv(tmp_path / "s.csv", {"r_m": r, "sigma_zz_Pa": -S["zz"], "sigma_xz_Pa": S["xz"]})
    out, png = tmp_path / "G.csv", tmp_path / "G.png"
    assert main(["calibrate", "--measured", str(meas), "--computed", str(comp), "--component",
                 "zz", "--out", str(out), "--plot", str(png), "--json", "--n-boot", "4"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["A_mV_per_bar"] == pytest.approx(19.0, rel=3e-3)
    G = load_apparatus_csv(out)
    assert G.radial(0.0) == pytest.approx(G_ZZ.radial(0.0), rel=0.05)
    assert png.stat().st_size > 10_000
    # a plain CSV (metadata beside it), and solve --sensor takes it as compare does
    from .conftest import assert_opens_plainly

    assert_opens_plainly(out)
    meta = json.loads((tmp_path / "G.meta.json").read_text())
    assert meta["A_mV_per_bar"] == rec["A_mV_per_bar"] and meta["component"] == "zz"
    assert main(["solve", "--tol", "1e-3", "--sensor", "--apparatus-zz", str(out), "--json"]) == 0
    own = json.loads(capsys.readouterr().out)
    assert main(["solve", "--tol", "1e-3", "--sensor", "--json"]) == 0
    paper = json.loads(capsys.readouterr().out)
    assert own["apparatus_zz"].startswith("TabulatedApparatus") and own["apparatus_xz"] == paper["apparatus_xz"]
    # the calibrated G_zz is the paper's within the calibration's accuracy: peaks within 1 %
    assert own["S_zz_peak_Pa"] == pytest.approx(paper["S_zz_peak_Pa"], rel=0.01)
    assert own["S_zz_peak_Pa"] != paper["S_zz_peak_Pa"]
    # the punch computed internally gives the same A
    assert main(["calibrate", "--measured", str(meas), "--punch-load", "1.0", "--component",
                 "xz", "--method", "ratio", "--n-boot", "0", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["A_mV_per_bar"] == pytest.approx(7.95, rel=0.03)


# --- bad files --------------------------------------------------------------------------------

GOOD_ROWS = "\n".join(f"{i * 1e-4:.6g},{math.exp(-i * i / 50):.6g},{0.1 * i:.6g}"
                      for i in range(-20, 21))
BAD_FILES = {
    "missing_column": ("x_m,S_zz_Pa\n" + "\n".join(f"{i},{i}" for i in range(20)), "S_xz_Pa"),
    "non_numeric": ("x_m,S_zz_Pa,S_xz_Pa\n" + GOOD_ROWS + "\n0.0021,abc,1", "S_zz_Pa"),
    "nan": ("x_m,S_zz_Pa,S_xz_Pa\n" + GOOD_ROWS + "\n0.0021,nan,1", "not finite"),
    "empty": ("", "empty"),
    "comments_only": ("# nothing here\n\n", "empty"),
    "header_only": ("x_m,S_zz_Pa,S_xz_Pa\n", "no data"),
    "no_header": (GOOD_ROWS, "header"),
    "unsorted": ("x_m,S_zz_Pa,S_xz_Pa\n" + "\n".join(
        f"{x:.6g},1,1" for x in [0, 1e-4, 3e-4, 2e-4] + [k * 1e-4 for k in range(4, 20)]),
        "increasing"),
    "non_uniform": ("x_m,S_zz_Pa,S_xz_Pa\n" + "\n".join(
        f"{(k * 1e-4) * (1 + 0.01 * (k % 2)):.8g},1,1" for k in range(20)), "uniform"),
    "too_few": ("x_m,S_zz_Pa,S_xz_Pa\n0,1,1\n1e-4,2,1\n2e-4,1,1", "at least"),
    "ragged": ("x_m,S_zz_Pa,S_xz_Pa\n" + GOOD_ROWS + "\n0.0021,1", "cells"),
}


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_measured_file_raises_one_line_input_error(tmp_path, case):
    text, needle = BAD_FILES[case]
    f = _write(tmp_path / f"{case}.csv", text)
    with pytest.raises(InputError) as exc:
        read_measured_profile(f)
    msg = str(exc.value)
    assert "\n" not in msg and str(f) in msg and needle in msg


@pytest.mark.parametrize("case", ["missing_column", "nan", "empty", "non_uniform", "too_few"])
def test_bad_measured_file_via_cli_exits_2_and_writes_nothing(tmp_path, capsys, case):
    from spectral_contact.cli.main import main

    f = _write(tmp_path / f"{case}.csv", BAD_FILES[case][0])
    png = tmp_path / "out.png"
    assert main(["compare", str(f), "--plot", str(png), "--json"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(f) in err and "Traceback" not in err
    assert not png.exists()


def test_bad_inputs_to_calibrate_exit_2_and_write_nothing(tmp_path, capsys):
    from spectral_contact.cli.main import main

    r = np.arange(40) * 1e-4
    good = _csv(tmp_path / "U.csv", {"r_m": r, "U_zz_mV": np.exp(-r / 1e-3)})
    shifted = _csv(tmp_path / "Ushift.csv", {"r_m": r + 5e-4, "U_zz_mV": np.exp(-r / 1e-3)})
    wrongcol = _csv(tmp_path / "s.csv", {"r_m": r, "pressure": np.exp(-r / 1e-3)})
    out = tmp_path / "G.csv"
    cases = [
        ["--measured", str(good), "--computed", str(wrongcol)],  # no sigma column
        ["--measured", str(good)],  # neither --computed nor --punch-load
        ["--measured", str(shifted), "--punch-load", "1"],  # does not start at r = 0
        ["--measured", str(good), "--component", "xz", "--punch-load", "1"],  # no U_xz_mV
        ["--measured", str(tmp_path / "missing.csv"), "--punch-load", "1"],
        ["--measured", str(good), "--punch-load", "-1"],
    ]
    for argv in cases:
        assert main(["calibrate", *argv, "--out", str(out)]) == 2, argv
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and "Traceback" not in err, argv
        assert not out.exists()


def test_radial_profile_reader_rejects_negative_radii(tmp_path):
    f = _csv(tmp_path / "neg.csv", {"r_m": np.arange(-2, 10) * 1e-4, "G": np.ones(12)})
    with pytest.raises(InputError, match="negative"):
        read_radial_profile(f, ("G",))


@pytest.mark.parametrize("mu, P_bias, mu_bias", [
    (0.3, -0.00737, -0.03153), (1.0, -0.00821, -0.03079), (2.0, -0.01149, -0.02826),
    (3.0, -0.01867, -0.02278)])
def test_integral_estimates_biased_low_in_a_10mm_window(mu, P_bias, mu_bias):
    """README: the paper's integral estimates of P_L and mu_d from a +-10 mm window centred on
    the contact, 200 N/m: P_L -0.7 to -1.9 %, mu_d -2.3 to -3.2 % (the window cuts the tails)."""
    from spectral_contact import sensor, solve
    from spectral_contact.instruments.compare import integral_estimates

    r = solve(load=200.0, mu=mu)
    v = sensor(r)
    sel = np.abs(v.x_m - r.contact_center_m) <= 0.010
    P, m = integral_estimates(v.x_m[sel], v.S_zz_Pa[sel], v.S_xz_Pa[sel])
    assert P / 200.0 - 1 == pytest.approx(P_bias, abs=3e-4)
    assert m / mu - 1 == pytest.approx(mu_bias, abs=3e-4)
