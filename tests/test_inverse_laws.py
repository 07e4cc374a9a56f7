"""The law fits' verdict (issue 21): AIC ranks the laws, chi^2 says whether any fits."""
import numpy as np

from spectral_contact.instruments.inverse_laws import REJECT_P, best_line, fit_laws


def _pairs(q_of_p, sd, seed=0):
    rng = np.random.default_rng(seed)
    p = np.linspace(1e4, 5e4, 30)
    q = q_of_p(p) + sd * rng.standard_normal(p.size)
    C = np.eye(p.size) * sd ** 2
    return p, q, np.eye(p.size) * 1e-6, C, np.zeros((p.size, p.size))


def test_a_law_that_fits_is_not_flagged():
    p, q, Cpp, Cqq, Cpq = _pairs(lambda p: 0.8 * p, 50.0)
    laws = fit_laws(p, q, Cpp, Cqq, Cpq)
    assert laws["amontons"]["p_value"] > REJECT_P and "note" not in laws
    assert best_line(laws) == f"  best law (AIC): {laws['best']}"


def test_every_law_rejected_is_said():
    """Pairs on a curve none of the three laws follows, with tiny errors (a noise-free
    record's floor): the best by AIC is still named, with the note that all are rejected."""
    p, q, Cpp, Cqq, Cpq = _pairs(lambda p: 1e4 * np.sin(p / 5e3), 1.0)
    laws = fit_laws(p, q, Cpp, Cqq, Cpq)
    assert all(laws[k]["p_value"] < REJECT_P for k in ("amontons", "linear", "power"))
    assert "rejected" in laws["note"] and "rejected" in best_line(laws)
    assert laws["best"] in ("amontons", "linear", "power")
