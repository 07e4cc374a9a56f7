"""The surface inverse's contact prior (issue 21, maps): bands over the contact and the local
friction law from maps, on the small records of test_inverse_maps (48 x 48 cells of h/4, a
disc of radius 1.2 h with a square-root edge)."""
import numpy as np
import pytest

from spectral_contact.instruments import inverse_maps as im

from .test_inverse_maps import MU, STEP, H, X, Y, _maps, _tractions

TAU0, ALPHA = 8e3, 0.4


def _cover(inv, truth, centre=(0.3 * H, -0.2 * H), a=1.2 * H):
    XX, YY = np.meshgrid(X, Y, indexing="ij")
    r = np.hypot(XX - centre[0], YY - centre[1]) / a
    c = truth[0] > 0
    out = []
    for f, t, s in zip((inv.pressure_Pa, inv.shear_x_Pa, inv.shear_y_Pa), truth,
                       (inv.pressure_sd_Pa, inv.shear_x_sd_Pa, inv.shear_y_sd_Pa)):
        ok = np.abs(f - t) <= 2 * s
        out.append((ok[r < 0.7].mean(), ok[c].mean()))
    return out


@pytest.fixture(scope="module")
def disc():
    truth, d = _maps(0.01, 5)
    return truth, im.invert_maps(X, Y, *d, thickness=H)


def test_contact_prior_bands(disc):
    """1 % noise: the evidence keeps the contact prior (by hundreds of log units here), whose
    2-sd band holds the truth at >= 90 % of the central 70 % of the contact for p, q_x and q_y
    and at >= 85 % of the whole contact for q (the smooth prior: ~0.2-0.4, studies/README).
    Over the whole contact p's band holds 70-80 % on this coarse grid: the edge falls inside
    cells of h/4 (a tenth of the radius) and the cells cut by it are the misses; the sphere's
    finer maps reach 0.8 (the study)."""
    truth, inv = disc
    reg = inv.summary()["regularisation"]
    ch = reg["prior_choice"]
    assert ch["chosen"] == "contact"
    assert ch["log_evidence"]["contact"] > ch["log_evidence"]["smooth"] + 100
    (pc, pa), (qc, qa), (yc, ya) = _cover(inv, truth)
    assert min(pc, qc, yc) >= 0.9
    assert qa >= 0.85 and ya >= 0.85
    assert pa >= 0.7
    # the ellipse found by evidence is the disc
    assert reg["centre_h"][0] * H + X[0] == pytest.approx(0.3 * H, abs=0.25 * STEP)
    assert np.mean(reg["semi_axes_h"]) * H == pytest.approx(1.2 * H, rel=0.1)
    # the L2 error of p over the contact: a few per cent (the smooth prior: ~9 %)
    p = truth[0]
    c = p > 0
    assert np.linalg.norm((inv.pressure_Pa - p)[c]) < 0.05 * np.linalg.norm(p[c])


def test_smooth_prior_forced(disc):
    """prior='smooth' keeps the stationary prior (uniform sd) and records both evidences only
    when both were fitted."""
    truth, d = _maps(0.01, 5)
    inv = im.invert_maps(X, Y, *d, thickness=H, prior="smooth")
    reg = inv.summary()["regularisation"]
    assert reg["prior_choice"]["chosen"] == "smooth"
    assert "contact" not in reg["prior_choice"]["log_evidence"]
    assert np.ptp(inv.pressure_sd_Pa) == 0.0
    assert np.ptp(disc[1].pressure_sd_Pa) > 0.0  # the contact prior's sd varies
    with pytest.raises(im.InputError):
        im.invert_maps(X, Y, *d, thickness=H, prior="other")


def test_laws_amontons_not_rejected(disc):
    """q = mu p on the disc: the Amontons fit from the map's local pairs gives mu within 2
    sigma and is not rejected (chi^2 p-value > 0.01)."""
    laws = disc[1].laws
    a = laws["amontons"]
    assert abs(a["mu"] - MU) < 2 * a["mu_sigma"]
    assert a["p_value"] > 0.01
    assert laws["pairs"] >= 5


def test_laws_shear_strength():
    """q = tau0 + alpha p inside the disc (a step at the edge), 1 % noise, on a finer record
    (80 x 80 cells of 0.15 h: 8 cells across the radius): the linear law recovers tau0 and
    alpha within 2 sigma and Amontons loses by AIC.  (On the 48 x 48 record, cells of h/4, the
    estimate of q is smoothed across the step and alpha comes out low by 5-7 sigma: the laws
    need the step resolved by the grid; here the bias is 0.5-1.7 sigma over seeds 2-4.)
    Amontons loses by at least 2 AIC units (the usual threshold): with q's length l_r capped at
    the contact's width (``inverse_maps_contact.LR_MAX_WIDTH``) its margin over seeds 2-6 is
    2.1-14.8 (7.5 on seed 2; the converged fit with l_r free had 22-42, with z of tau0 and alpha
    too large on the sphere's records, studies/README, inverse_maps): this small disc's ~8
    cells across the radius leave the test of a shear strength weak."""
    x = (np.arange(80) - 40) * 0.15 * H
    p, _, _ = _tractions(x, x)
    q = np.where(p > 0, TAU0 + ALPHA * p, 0.0)
    szz, sxz, syz = im.base_maps_from_tractions(x, x, p, q, 0 * p, H)
    rng = np.random.default_rng(2)
    s = 0.01 * np.abs(szz).max()
    d = [f + s * rng.standard_normal(f.shape) for f in (-szz, sxz, syz)]
    inv = im.invert_maps(x, x, *d, thickness=H)
    laws = inv.laws
    lin = laws["linear"]
    assert abs(lin["tau0_Pa"] - TAU0) < 2 * lin["tau0_Pa_sigma"]
    assert abs(lin["alpha"] - ALPHA) < 2 * lin["alpha_sigma"]
    assert lin["tau0_Pa_sigma"] < 0.5 * TAU0
    assert laws["amontons"]["aic"] > lin["aic"] + 2
    assert laws["best"] in ("linear", "power")


def _disc_prior(seed=5):
    """fit_contact's arguments on the disc record, as invert_maps makes them (scaled data,
    lengths in h; the truth's pressure for the starting ellipse)."""
    from spectral_contact.numerics.grid import Grid
    from spectral_contact.physics.film import Film

    truth, d = _maps(0.01, seed)
    scale = max(float(np.abs(f).max()) for f in d)
    ds = np.stack(d) / scale
    n, step = X.size, STEP / H
    M = im._symbol(Grid((n, n), (n * step, n * step)), Film(1.0))
    Yk = np.moveaxis(np.fft.rfft2(ds, axes=(1, 2)), 0, -1)
    noise = np.full(3, 0.01 * float(np.abs(d[0]).max()) / scale)
    return (M, Yk, (n, n), (step, step), noise, (1.0, 0.0), truth[0] / scale, 0.05, MU)


def test_contact_evidence_gradient():
    """The contact prior's analytic gradient of the log-evidence (Woodbury form: the ellipse and
    mu0 through U, s_p and the lengths through K) equals central differences at a point off the
    maximum, in all eight hyperparameters."""
    from spectral_contact.instruments import inverse_maps_contact as ic

    M, Yk, shape, steps, noise, e, p0, _, mu = _disc_prior()
    geom = ic.start_geometry(p0, steps)
    prior = ic.ContactMapPrior(M, Yk, shape, steps, noise, e, geom)
    cx, cy, ax, ay = geom
    th = np.array([cx + 0.05, cy - 0.03, np.log(ax) + 0.02, np.log(ay) - 0.03, 0.0,
                   np.log(0.7 * ax), mu + 0.1, np.log(0.6 * ax)])
    v, g = prior.evidence(th, 0.005, grad=True)
    assert v == prior.evidence(th, 0.005)
    for i in range(8):
        step = np.zeros(8)
        step[i] = 1e-5
        fd = (prior.evidence(th + step, 0.005) - prior.evidence(th - step, 0.005)) / 2e-5
        assert g[i] == pytest.approx(fd, rel=1e-4, abs=1e-3)


def test_contact_fit_converged_and_stable(disc):
    """The contact prior's fit converges (the Newton step left at its end under 2 % of each
    hyperparameter's sd) and its answer does not depend on where it starts or on the data's
    last digits: from a start moved by a tenth of the semi-axes and by 0.5 in the lengths'
    logs, and on the data perturbed by 1e-12 of themselves, the log-evidence agrees within
    1e-2 nats and the tractions within 1e-2 of their sd.  (The fit before, 15 + 8 L-BFGS-B
    iterations with differenced gradients, fails the start's part: in place of ``_maximise``
    it moved theta by 0.12 sd and the mean by up to 4 sd here; and on a study record 1e-12 of
    the data moved its answer by 1 sd and p's coverage 0.95 -> 0.85.)"""
    from spectral_contact.instruments import inverse_maps_contact as ic

    truth, d = _maps(0.01, 5)
    inv = disc[1]
    reg = inv.summary()["regularisation"]
    assert reg["optimizer_converged"] and reg["optimizer_step_sd"] <= ic.CONVERGED_STEP_SD
    assert reg["optimizer_iterations"] > 0 and np.isfinite(reg["optimizer_gradient_norm"])
    # the data's last digits
    rng = np.random.default_rng(1)
    d2 = [f * (1.0 + 1e-12 * rng.standard_normal(f.shape)) for f in d]
    inv2 = im.invert_maps(X, Y, *d2, thickness=H)
    assert inv2.summary()["log_evidence"] == pytest.approx(inv.summary()["log_evidence"],
                                                           abs=1e-2)
    for a, b, s in ((inv.pressure_Pa, inv2.pressure_Pa, inv.pressure_sd_Pa),
                    (inv.shear_x_Pa, inv2.shear_x_Pa, inv.shear_x_sd_Pa),
                    (inv.shear_y_Pa, inv2.shear_y_Pa, inv.shear_y_sd_Pa)):
        assert np.max(np.abs(a - b) / s) < 1e-2
    # the start
    args = _disc_prior()
    prior, th, s_out, v, fit = ic.fit_contact(*args)
    sd = np.sqrt(np.diag(ic.propagate(prior, th, s_out)[1]))
    moved = th + np.array([0.1 * np.exp(th[2]), -0.1 * np.exp(th[3]), 0.1, -0.1, 0.3, -0.5,
                           0.2, -0.5])
    prior2, th2, s2, v2, fit2 = ic.fit_contact(*args, start=moved)
    assert s2 == s_out and v2 == pytest.approx(v, abs=1e-2)
    assert np.max(np.abs(th2 - th) / sd) < 0.05
    m1, var1 = prior.posterior(th, s_out)[:2]
    m2 = prior2.posterior(th2, s2)[0]
    assert np.max(np.abs(m1 - m2) / np.sqrt(var1)) < 1e-2


def test_contact_fit_not_converged_is_flagged(monkeypatch):
    """A fit stopped early (two L-BFGS-B iterations a round) is reported as not converged, with
    the step it leaves (many sd), rather than passed off as the maximum."""
    from spectral_contact.instruments import inverse_maps_contact as ic

    monkeypatch.setattr(ic, "OPT_MAXITER", 2)
    _, d = _maps(0.01, 5)
    reg = im.invert_maps(X, Y, *d, thickness=H, prior="contact").summary()["regularisation"]
    assert reg["optimizer_converged"] is False
    assert reg["optimizer_step_sd"] > ic.CONVERGED_STEP_SD
