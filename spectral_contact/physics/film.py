"""Fourier symbols of the bonded incompressible film (physics.md; the paper's Eqs. bc3-bc4, Z1-Z6).

Fourier convention (numpy's): f^(k) = Int f(x) exp(-ikx) dx.  All symbols are returned on k >= 0
(real FFT half spectrum); the negative-k half follows from Hermitian symmetry.

Surface compliance, surface normal displacement u_z(x, 1) under sigma_zz(x, 1) with Amontons
friction sigma_xz(x, 1) = -mu sigma_zz(x, 1):

    u_z^ = H(k) sigma_zz^,   H(k) = (F0(|k|) + i mu sgn(k) F1(|k|)) / (2|k|),   H(0) = 0.

With sigma_zz = -p the surface sinks by w = -u_z = H p.  The i mu F1 term is real-odd in x: the
operator is not symmetric.  H(0) = 0: a uniform pressure does not move an incompressible film on a
rigid base.

Base stresses (z = 0) from surface tractions:

    sigma_zz^(k,0) = A sigma_zz^(k,1) + i sgn(k) B sigma_xz^(k,1)
    sigma_xz^(k,0) = C sigma_xz^(k,1) + i sgn(k) B sigma_zz^(k,1)
"""
from __future__ import annotations

import numpy as np

from .transfer import transfer_functions

__all__ = ["surface_compliance", "base_stress_symbols", "DECAY_RATE"]

DECAY_RATE = 0.7390851332151607
"""Slowest exponential decay rate (in 1/h) of the film's kernels in x: the pole of 1/D(k) at
k = i*0.739... (D = cosh 2k + 1 + 2k^2 vanishes where cos y = y).  Periodic images at distance s
perturb the solution by ~exp(-DECAY_RATE * s)."""


def surface_compliance(k: np.ndarray, mu: float) -> np.ndarray:
    """H(k) on k >= 0 (dimensionless: displacement h^2/2R per stress E h/6R per 1/h)."""
    k = np.asarray(k, dtype=float)
    F0, F1, *_ = transfer_functions(k)
    H = np.zeros(k.shape, dtype=complex)
    nz = k > 0
    H[nz] = (F0[nz] + 1j * mu * F1[nz]) / (2.0 * k[nz])
    return H


def base_stress_symbols(k: np.ndarray):
    """(A, iB, C) on k >= 0, so that, with s = sgn(k) = +1 there,
    sigma_zz^(0) = A szz^(1) + iB sxz^(1) and sigma_xz^(0) = C sxz^(1) + iB szz^(1)."""
    _, _, A, B, C = transfer_functions(np.asarray(k, dtype=float))
    return A, 1j * B, C


def base_stresses(fft, k, sigma_zz_surface, sigma_xz_surface):
    """Base stresses sigma_zz(x, 0), sigma_xz(x, 0) on the grid from surface tractions (both real
    arrays on the same periodic grid), through the planned transform ``fft``."""
    A, iB, C = base_stress_symbols(k)
    szz = fft.forward(sigma_zz_surface)
    sxz = fft.forward(sigma_xz_surface)
    return fft.backward(A * szz + iB * sxz), fft.backward(C * sxz + iB * szz)
