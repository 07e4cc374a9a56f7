"""The inverse (issue 21): from base stresses (or the MEMS view) to the interface tractions."""
import json
import math

import numpy as np
import pytest

from spectral_contact import solve
from spectral_contact.cli.main import main
from spectral_contact.instruments.inverse import (
    LineForward,
    base_from_tractions,
    invert,
    invert_line,
)
from spectral_contact.instruments.sensor import sensor_profiles, sensor_view
from spectral_contact.physics.film import Film

H = 0.002
X = np.arange(-10e-3, 10e-3 + 1e-9, 0.1e-3)  # a +-10 mm record, 201 samples


def _record(result, noise, seed, view="base", x=X):
    if view == "base":
        zz = np.interp(x, result.x_m, -result.base_sigma_zz_Pa)
        xz = np.interp(x, result.x_m, result.base_sigma_xz_Pa)
    else:
        v = sensor_view(result)
        zz = np.interp(x, result.x_m, v["S_zz_Pa"])
        xz = np.interp(x, result.x_m, v["S_xz_Pa"])
    rng = np.random.default_rng(seed)
    return (zz + noise * np.abs(zz).max() * rng.standard_normal(x.size),
            xz + noise * np.abs(xz).max() * rng.standard_normal(x.size))


@pytest.fixture(scope="module")
def amontons():
    return solve(load=200.0, mu=1.0)


@pytest.fixture(scope="module")
def strength():
    return solve(load=200.0, mu=1.0, friction_law="linear", shear_strength=15e3, shear_slope=0.3)


def test_totals_identities():
    """Int base sigma_zz dx = -P and Int base sigma_xz dx = Q (A(0) = C(0) = 1, B(0) = 0), for
    the synthetic route and for the inverse's forward matrix."""
    x = np.linspace(-40 * H, 40 * H, 4096, endpoint=False)
    p = np.where(np.abs(x) < 2e-3, 5e4 * np.sqrt(np.clip(1 - (x / 2e-3) ** 2, 0, None)), 0.0)
    q = 0.4 * p + np.where(np.abs(x) < 2e-3, 3e3, 0.0)
    szz, sxz = base_from_tractions(x, p, q, H)
    dx = x[1] - x[0]
    assert np.sum(-szz) * dx == pytest.approx(np.sum(p) * dx, rel=1e-9)
    assert np.sum(sxz) * dx == pytest.approx(np.sum(q) * dx, rel=1e-9)
    # forward matrix: a node in the middle of a long record; its columns integrate to the
    # node's weight (p -> zz, q -> xz) and to 0 across (the B coupling is odd)
    xs = np.linspace(-30.0, 30.0, 6001)
    fwd = LineForward.build(xs, Film(1.0))
    j = int(np.argmin(np.abs(fwd.nodes)))
    d = xs[1] - xs[0]
    assert np.sum(fwd.Mzp[:, j]) * d == pytest.approx(fwd.weights[j], rel=1e-5)
    assert np.sum(fwd.Mxq[:, j]) * d == pytest.approx(fwd.weights[j], rel=1e-5)
    assert abs(np.sum(fwd.Mzq[:, j]) * d) < 1e-5 * fwd.weights[j]
    # and it reproduces the periodic transfer at the samples
    pt = np.interp(xs * H, x, p)
    t = fwd.nodes * H
    pn, qn = np.interp(t, x, p), np.interp(t, x, q)
    dz, dxz = fwd.apply(pn, qn)
    ok = np.abs(xs) < 10
    assert np.max(np.abs(dz[ok] - np.interp(xs[ok] * H, x, -szz))) < 0.02 * np.max(pt)
    assert np.max(np.abs(dxz[ok] - np.interp(xs[ok] * H, x, sxz))) < 0.02 * np.max(pt)


@pytest.mark.parametrize("prior", ["auto", "contact"])
def test_noise_free_recovery(amontons, prior):
    """The solver's own base stresses (exact model, noise-free, its 8192 samples over the whole
    period, averaged in groups of 6): P, Q to 0.1 % and within 2 sigma, the tractions to what
    the forward map's discretisation allows (L2 < 3 %; measured 1.2 %), the contact's edges
    within 0.1 mm and within 2 of their sd (measured +4 um at sd 17, -12 um at sd 11; right
    edge -23 um, 2.1 sd, before the window's rounding offset was added back,
    ``inverse_prior.rounding_offset``), with the default prior too: both priors' likelihoods
    share the model-error floor (``inverse_prior.model_error_floor``).  Without it the envelope
    prior fitted the record to 4e-6 of its peak, won the evidence by ~7600 nats on that alone
    and gave Q = 200.32 +- 0.08 and a right edge 0.26 mm (16 sd) out."""
    inv = invert(amontons) if prior == "auto" else invert(amontons, prior=prior)
    s = inv.summary()
    assert s["binned_by"] > 1 and s["points"] == amontons.x_m.size
    for key in ("load_N_per_m", "tangential_load_N_per_m"):
        err = abs(s[key] - 200.0)
        assert err < 2e-4 * 200.0 or err < 2 * s[key.replace("_N_per_m", "_sigma_N_per_m")]
        assert err < 1e-3 * 200.0
    for f, true in ((inv.pressure_Pa, amontons.pressure_Pa), (inv.shear_Pa, amontons.surface_shear_Pa)):
        t = np.interp(inv.x_m, amontons.x_m, true)
        assert np.linalg.norm(f - t) / np.linalg.norm(t) < 0.03
    (a, b), = amontons.contact_intervals_m
    lo, hi = s["contact_interval_m"]
    assert abs(lo - a) < 1e-4 and abs(hi - b) < 1e-4
    for edge, true, sd in zip((lo, hi), (a, b), s["contact_interval_sigma_m"]):
        assert abs(edge - true) <= 2 * sd
    assert inv.laws["best"] == "amontons"


def test_noise_free_windowed_record_default_prior():
    """A noise-free base record of a thicker film (h = 3 mm, P_L = 150 N/m, mu = 1.2) on a
    window [-8, 14] mm, step 0.1 mm, default prior: L2 of p and q < 3 % (measured 1.6 %), the
    2-sd band covers the truth at >= 80 % of the contact's nodes (measured 0.92 / 0.96; was
    L2 3.9 / 5.3 % and coverage 0.77 / 0.69 when the envelope prior won by its noise floor)."""
    r = solve(load=150.0, mu=1.2, thickness=0.003)
    x = np.arange(-8e-3, 14e-3 + 1e-9, 0.1e-3)
    zz = np.interp(x, r.x_m, -r.base_sigma_zz_Pa)
    xz = np.interp(x, r.x_m, r.base_sigma_xz_Pa)
    inv = invert_line(x, zz, xz, thickness=0.003)
    (a, b), = r.contact_intervals_m
    inside = (inv.x_m > a) & (inv.x_m < b)
    for f, sd, true in ((inv.pressure_Pa, inv.pressure_sd_Pa, r.pressure_Pa),
                        (inv.shear_Pa, inv.shear_sd_Pa, r.surface_shear_Pa)):
        t = np.interp(inv.x_m, r.x_m, true)
        assert np.linalg.norm(f - t) / np.linalg.norm(t) < 0.03
        assert np.mean(np.abs(f - t)[inside] <= 2 * sd[inside]) >= 0.8
    s = inv.summary()
    assert abs(s["load_N_per_m"] - 150.0) < 1e-3 * 150.0
    assert abs(s["tangential_load_N_per_m"] - 180.0) < 1e-3 * 180.0


def test_hyperparameter_propagation_and_binning(amontons):
    """Integrating over the hyperparameters widens the posterior (S + J Sigma J^T >= S: every
    node's sd and P's sigma at least the fixed-hyperparameter ones), and a record sampled 10x
    finer (averaged in groups before the inversion) reports the per-sample noise sd it was made
    with (within 10 %) and the same P within the two sigmas."""
    zz, xz = _record(amontons, 0.01, 11)
    fixed = invert_line(X, zz, xz, hyper=False)
    full = invert_line(X, zz, xz)
    assert np.all(full.pressure_sd_Pa >= fixed.pressure_sd_Pa * (1 - 1e-9) - 1e-9)
    assert full.load_sigma_N_per_m >= fixed.load_sigma_N_per_m
    assert np.isfinite(full.contact_interval_sigma_m).all()
    x = np.arange(-10e-3, 10e-3 + 1e-9, 0.01e-3)
    zz2, xz2 = _record(amontons, 0.01, 12, x=x)
    fine = invert_line(x, zz2, xz2)
    assert fine.binned_by >= 5
    sd_true = 0.01 * np.abs(np.interp(x, amontons.x_m, -amontons.base_sigma_zz_Pa)).max()
    assert fine.noise_sd_zz_Pa == pytest.approx(sd_true, rel=0.1)
    gap = abs(fine.load_N_per_m - full.load_N_per_m)
    assert gap < 2 * math.hypot(fine.load_sigma_N_per_m, full.load_sigma_N_per_m)


@pytest.mark.parametrize("view", ["base", "sensor"])
def test_round_trip_within_bands(amontons, view):
    """1 % noise: P and Q within 2 sigma and 1 %, the 2-sd bands cover the truth at >= 80 % of
    the contact's nodes; an Amontons record is not rejected (chi^2 p-value > 0.01)."""
    zz, xz = _record(amontons, 0.01, 3, view)
    inv = invert_line(X, zz, xz, view=view)
    s = inv.summary()
    for key, true in (("load_N_per_m", 200.0), ("tangential_load_N_per_m", 200.0)):
        sig = s[key.replace("_N_per_m", "_sigma_N_per_m")]
        assert abs(s[key] - true) < 2 * sig + 1e-3 * true
        assert abs(s[key] - true) < 0.01 * true
    (a, b), = amontons.contact_intervals_m
    inside = (inv.x_m > a) & (inv.x_m < b)
    for f, sd, true in ((inv.pressure_Pa, inv.pressure_sd_Pa, amontons.pressure_Pa),
                        (inv.shear_Pa, inv.shear_sd_Pa, amontons.surface_shear_Pa)):
        t = np.interp(inv.x_m, amontons.x_m, true)
        assert np.mean(np.abs(f - t)[inside] <= 2 * sd[inside]) >= 0.8
    am = s["laws"]["amontons"]
    assert am["p_value"] > 0.01
    assert abs(am["mu"] - 1.0) < 2 * am["mu_sigma"] + 0.02
    ok = np.isfinite(inv.mu_local)
    assert ok.sum() >= 5
    assert np.all(np.isnan(inv.mu_local[inv.pressure_Pa <= 3 * inv.pressure_sd_Pa]))


def test_shear_strength_law(strength):
    """q = tau0 + alpha p (tau0 = 15 kPa, alpha = 0.3), 401 samples at 0.1 % noise: the fit
    recovers tau0 and alpha within 2 sigma, and Amontons loses by AIC (by more than 2).  (At
    0.3 % noise and 201 samples the laws are not told apart: studies/inverse.py.)"""
    x = np.arange(-10e-3, 10e-3 + 1e-9, 0.05e-3)
    zz, xz = _record(strength, 0.001, 0, x=x)
    laws = invert_line(x, zz, xz).laws
    lin, am = laws["linear"], laws["amontons"]
    assert abs(lin["tau0_Pa"] - 15e3) < 2 * lin["tau0_Pa_sigma"]
    assert abs(lin["alpha"] - 0.3) < 2 * lin["alpha_sigma"]
    assert am["aic"] > lin["aic"] + 2


def test_varying_mu_sensor_bands_cover():
    """A local mu varying across the contact (0.2 ... 0.8: the mu = 0.5 solve's pressure with
    q = mu(x) p, through the film's base transfer) seen through the paper's apparatus, 1 %
    noise, 401 samples, noise seeds 0-5: the 2-sd band of p covers the truth at >= 90 % of the
    central 70 % of the contact and >= 80 % of the whole contact on average over the seeds, and
    at >= 70 % of the contact on each (issue 21's coverage).  Before l_p's cap
    (``inverse_prior.LP_MAX_WIDTH``) the same six records gave 0.82 central, 0.81 contact, two
    records below 0.5."""
    r = solve(load=200.0, mu=0.5)
    x, p = r.x_m, r.pressure_Pa
    (a, b), = r.contact_intervals_m
    q = np.where(p > 0, (0.5 + 0.3 * (x - 0.5 * (a + b)) / (0.5 * (b - a))) * p, 0.0)
    szz, sxz = base_from_tractions(x, p, q, H)
    v = sensor_profiles(x, szz, sxz, periodic=True)
    xs = np.arange(-10e-3, 10e-3 + 1e-9, 0.05e-3)
    c, hw = 0.5 * (a + b), 0.5 * (b - a)
    central, contact = [], []
    for seed in range(6):
        rng = np.random.default_rng(seed)
        zz, xz = (np.interp(xs, x, f) + 0.01 * np.abs(f).max() * rng.standard_normal(xs.size)
                  for f in (v["S_zz_Pa"], v["S_xz_Pa"]))
        inv = invert_line(xs, zz, xz, view="sensor")
        t = inv.x_m
        ok = np.abs(inv.pressure_Pa - np.interp(t, x, p)) <= 2 * inv.pressure_sd_Pa
        central.append(ok[np.abs(t - c) < 0.7 * hw].mean())
        contact.append(ok[(t > a) & (t < b)].mean())
    assert np.mean(central) >= 0.9 and np.mean(contact) >= 0.8
    assert min(contact) >= 0.7


def _write(path, header, rows):
    path.write_text(header + "\n" + "\n".join(",".join(f"{v:.9g}" for v in r) for r in rows) + "\n")


@pytest.fixture(scope="module")
def good_file(tmp_path_factory, amontons):
    zz, xz = _record(amontons, 0.01, 5)
    p = tmp_path_factory.mktemp("inv") / "rec.csv"
    _write(p, "x_m,base_sigma_zz_Pa,base_sigma_xz_Pa", zip(X, -zz, xz))
    return p


def test_cli_outputs(good_file, tmp_path, capsys):
    out, png = tmp_path / "t.csv", tmp_path / "t.png"
    assert main(["invert", str(good_file), "--json", "--out", str(out), "--plot", str(png)]) == 0
    rec = json.loads(capsys.readouterr().out)
    for key in ("load_N_per_m", "load_sigma_N_per_m", "tangential_load_N_per_m",
                "tangential_load_sigma_N_per_m", "Q_over_P", "Q_over_P_sigma",
                "contact_interval_m", "resolution_length_m", "regularisation", "log_evidence",
                "laws"):
        assert key in rec
    assert rec["load_N_per_m"] == pytest.approx(200.0, rel=0.01)
    import pandas as pd

    df = pd.read_csv(out)
    assert list(df.columns) == ["x_m", "pressure_Pa", "pressure_sd_Pa", "shear_Pa", "shear_sd_Pa",
                                "mu_local", "mu_local_sd"]
    assert png.stat().st_size > 1000
    # never over the input
    before = good_file.read_bytes()
    assert main(["invert", str(good_file), "--out", str(good_file)]) == 2
    assert good_file.read_bytes() == before


@pytest.mark.parametrize("header, rows, words", [
    ("x_m,base_sigma_zz_Pa", [(i * 1e-4, 1.0) for i in range(20)], "missing"),
    ("x_m,base_sigma_zz_Pa,base_sigma_xz_Pa", [(i * 1e-4, float("nan") if i == 3 else 1.0, 0.0)
                                               for i in range(20)], "not finite"),
    ("x_m,base_sigma_zz_Pa,base_sigma_xz_Pa", [(0.0, -1.0, 0.0)], "only 1 data rows"),
    ("x_m,base_sigma_zz_Pa,base_sigma_xz_Pa", [((i * 7) % 20 * 1e-4, -1.0, 0.0) for i in range(20)],
     "not strictly increasing"),
    ("x_m,S_zz_Pa,base_sigma_xz_Pa,S_xz_Pa", [(i * 1e-4, 1.0, 0.0, 0.0) for i in range(20)],
     "mixes views"),
])
def test_cli_bad_files(tmp_path, capsys, header, rows, words):
    f = tmp_path / "bad.csv"
    _write(f, header, rows)
    out = tmp_path / "o.csv"
    assert main(["invert", str(f), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0]
    assert not out.exists()


def test_cli_apparatus_with_base_file(good_file, tmp_path, capsys):
    g = tmp_path / "g.csv"
    _write(g, "r_m,G", [(i * 1e-4, np.exp(-i / 5)) for i in range(30)])
    assert main(["invert", str(good_file), "--apparatus-zz", str(g)]) == 2
    assert "--apparatus-zz" in capsys.readouterr().err


def test_positive_and_support(amontons):
    """p >= 0 at every node with positive=True (the nodes at the bound have sd 0); with a known
    support the nodes lie on it and the totals still hold."""
    zz, xz = _record(amontons, 0.01, 7)
    inv = invert_line(X, zz, xz, positive=True)
    assert np.all(inv.pressure_Pa >= 0)
    assert np.all(inv.pressure_sd_Pa[inv.pressure_Pa == 0] == 0)
    assert inv.summary()["load_N_per_m"] == pytest.approx(200.0, rel=0.01)
    (a, b), = amontons.contact_intervals_m
    inv = invert_line(X, zz, xz, support=(a, b))
    assert inv.x_m.min() == pytest.approx(a) and inv.x_m.max() == pytest.approx(b)
    s = inv.summary()
    assert abs(s["load_N_per_m"] - 200.0) < 0.01 * 200.0
    assert abs(s["tangential_load_N_per_m"] - 200.0) < 0.01 * 200.0


def test_auto_prior_keeps_the_higher_evidence():
    """``prior="auto"`` (the default) fits both priors to the same data and keeps the one of
    higher log-evidence; a contact prior whose window search fails is reported (it did on the
    example U profile, mu = 2, before the first pass scanned windows: every start went to a
    window beyond the record's edge); on the example the contact prior now wins (by ~100
    nats) and recovers P_L = 200 N/m and Q/P = 2."""
    from pathlib import Path

    example = Path(__file__).resolve().parents[1] / "examples" / "synthetic_sliding_profile.csv"
    inv = invert(str(example))
    c = inv.record["regularisation"]["prior_choice"]
    les = {k: c[f"log_evidence_{k}"] for k in ("contact", "envelope")}
    finite = {k: v for k, v in les.items() if v is not None}
    assert c["chosen"] == max(finite, key=finite.get)
    assert (c["contact_failed"] is None) == (les["contact"] is not None)
    assert abs(inv.load_N_per_m - 200.0) < 3 * inv.load_sigma_N_per_m
    assert abs(inv.Q_over_P - 2.0) < 3 * inv.Q_over_P_sigma + 0.01
    assert c["contact_failed"] is None and c["chosen"] == "contact"


def test_text_summary_gives_the_laws_reason(tmp_path, capsys):
    """When no law is fitted the text summary says why (the JSON's laws.note), not 'None'."""
    rng = np.random.default_rng(1)
    x = np.arange(-10e-3, 10e-3 + 1e-9, 0.2e-3)
    f = tmp_path / "flat.csv"
    _write(f, "x_m,base_sigma_zz_Pa,base_sigma_xz_Pa",
           zip(x, -100 * rng.standard_normal(x.size), 100 * rng.standard_normal(x.size)))
    assert main(["invert", str(f)]) == 0
    out = capsys.readouterr().out
    line = [ln for ln in out.splitlines() if "best law" in ln][0]
    assert "None" not in line and "resolved" in line


def test_auto_screen_does_not_skip_a_winning_envelope(amontons):
    """``auto`` fits the envelope prior on its own nodes unless its cheap screen (nodes every
    h/2) is more than SCREEN_NATS below the contact prior's evidence.  On tractions that are no
    contact's (a Gaussian bump, no square-root edges, 1 % noise) the envelope wins (by ~7
    nats): the screen must pass it on, and the full envelope fit is the one kept; on a noisy
    contact record the contact prior wins and the screen's evidence is reported below the
    contact's."""
    from spectral_contact.instruments.inverse import SCREEN_NATS

    xp = np.linspace(-40 * H, 40 * H, 4096, endpoint=False)
    p = 5e4 * np.exp(-0.5 * (xp / 1.5e-3) ** 2)
    szz, sxz = base_from_tractions(xp, p, 0.3 * p, H)
    rng = np.random.default_rng(0)
    zz, xz = np.interp(X, xp, -szz), np.interp(X, xp, sxz)
    zz = zz + 0.01 * np.abs(zz).max() * rng.standard_normal(X.size)
    xz = xz + 0.01 * np.abs(xz).max() * rng.standard_normal(X.size)
    c = invert_line(X, zz, xz).record["regularisation"]["prior_choice"]
    assert c["chosen"] == "envelope" and c["envelope_screened"] is None
    assert c["log_evidence_envelope"] > c["log_evidence_contact"]
    zz, xz = _record(amontons, 0.01, 3)
    c = invert_line(X, zz, xz).record["regularisation"]["prior_choice"]
    assert c["chosen"] == "contact"
    if c["envelope_screened"] is not None:
        assert c["log_evidence_envelope"] < c["log_evidence_contact"] - SCREEN_NATS
