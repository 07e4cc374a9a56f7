import mpmath as mp
import numpy as np
import pytest

from spectral_contact.physics.film import DECAY_RATE, surface_compliance
from spectral_contact.physics.transfer import F0_minus_1, transfer_functions

mp.mp.dps = 50


def exact(k):
    k = mp.mpf(k)
    D = mp.cosh(2 * k) + 1 + 2 * k**2
    return [(mp.sinh(2 * k) - 2 * k) / D, 2 * k**2 / D, 2 * (mp.cosh(k) + k * mp.sinh(k)) / D,
            2 * k * mp.cosh(k) / D, 2 * (mp.cosh(k) - k * mp.sinh(k)) / D]


@pytest.mark.parametrize("k", np.concatenate([np.logspace(-9, 2.5, 90), [1.1997, 1.19967864]]))
def test_transfer_functions_match_high_precision(k):
    got = transfer_functions(np.array([k]))
    ref = exact(k)
    scale = abs(ref[2])  # C vanishes near k = 1.2: judge it against A's magnitude there
    for name, g, r in zip("F0 F1 A B C".split(), got, ref):
        denom = max(abs(r), scale) if name == "C" else abs(r)
        assert abs(g[0] - float(r)) <= 1e-13 * float(denom), (name, k)


def test_no_overflow_and_limits():
    k = np.array([0.0, 1e-300, 400.0, 1e4, 1e6, np.inf])
    F0, F1, A, B, C = transfer_functions(k)
    for f in (F0, F1, A, B, C):
        assert np.all(np.isfinite(f))
    assert F0[-1] == 1.0 and F1[-1] == 0.0 and A[-1] == 0.0
    assert A[0] == 1.0 and C[0] == 1.0 and B[0] == 0.0 and F0[0] == 0.0
    small = np.array([1e-4])
    assert transfer_functions(small)[0][0] == pytest.approx(2 * 1e-12 / 3, rel=1e-6)
    assert transfer_functions(small)[1][0] == pytest.approx(1e-8, rel=1e-6)


def test_F0_minus_1_without_cancellation():
    for k in (3.0, 30.0, 300.0):
        ref = exact(k)[0] - 1
        assert F0_minus_1(np.array([k]))[0] == pytest.approx(float(ref), rel=1e-13)


def test_compliance_halfspace_limit_and_zero_mode():
    k = np.array([0.0, 40.0])
    H = surface_compliance(k, mu=3.0)
    assert H[0] == 0  # uniform pressure does not move an incompressible film on a rigid base
    assert H[1].real == pytest.approx(1 / 80, rel=1e-12)  # half-space 1/(2k)
    assert abs(H[1].imag) < 1e-30


def test_decay_rate_is_the_pole_of_1_over_D():
    y = DECAY_RATE  # D(iy) = cos 2y + 1 - 2y^2 = 2(cos^2 y - y^2)
    assert abs(np.cos(2 * y) + 1 - 2 * y * y) < 1e-14
