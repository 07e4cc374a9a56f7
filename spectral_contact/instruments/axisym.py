"""Base stresses of the film under an axisymmetric surface load (the calibration's flat punch).

The film is the same incompressible layer bonded to a rigid base, now loaded by a 3D (x, y)
surface traction.  Fields are 2D periodic grids handled by 2D FFTs (``numerics.fft``).

Transfer functions in 3D: exact, not an approximation
------------------------------------------------------
For one Fourier mode exp(i k.x) of wavevector k = |k| e_k, the layer's equations split into a
sagittal problem in the plane (e_k, z) -- displacements along e_k and z only, nothing varying
along e_perp = e_z x e_k, so it is exactly a plane-strain problem of wavenumber |k| -- and an
anti-plane problem (displacement along e_perp).  Hence, with tau = (sigma_xz, sigma_yz) and
tau_k = e_k . tau, tau_perp = tau - e_k tau_k (all at wavevector k, stresses in the film):

    sigma_zz^(k, 0) = A(|k|h) sigma_zz^(k, h) + i B(|k|h) tau_k^(k, h)
    tau_k^(k, 0)    = C(|k|h) tau_k^(k, h)    + i B(|k|h) sigma_zz^(k, h)
    tau_perp^(k, 0) = tau_perp^(k, h) / cosh(|k| h)          (anti-plane shear of the layer)

with A, B, C the plane-strain functions of ``physics.transfer`` (their sgn(k) factors become
the projection on e_k).  An axisymmetric load -- a pressure p(r) and/or a radial shear tau_r(r),
both gradient fields -- has tau_perp^ = 0, so only the plane-strain functions enter and the
result is exact for the 3D layer.  (The anti-plane part is kept for general tractions.)  The
test suite checks these relations against an independent propagator-matrix solution of the 3D
incompressible layer for oblique wavevectors.

The flat punch (assumptions)
----------------------------
The calibration indents the film with a rigid, flat-ended cylindrical rod of diameter 500 um
(radius a = 250 um) at normal load P, frictionless.  We prescribe its classical half-space
(Boussinesq) pressure p(r) = P / (2 pi a sqrt(a^2 - r^2)) for r < a, whose 2D Fourier transform
is P sin(k a)/(k a) (used analytically, so the edge singularity is not sampled).  On the
layer (h = 2 mm = 8 a) the true punch pressure differs from it; since the base stresses are
the load smoothed over ~h, the difference is small: replacing the punch distribution by a
*uniform* pressure on the same disc -- a far larger change -- moves the base stresses by at
most 0.8 % (sigma_zz) and 0.3 % (sigma_xz) of the peak |sigma_zz| (see ``punch_sensitivity``).
The paper's FE found the base stresses
insensitive to the friction condition under the rod; we take it frictionless.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..numerics.fft import get_rfft
from ..numerics.grid import Grid
from ..physics.film import Film

__all__ = ["base_stresses_3d", "film_of_thickness", "base_stresses_axisym", "flat_punch_transform",
           "uniform_disc_transform", "flat_punch_base_stresses", "punch_sensitivity",
           "plane_grid"]


def plane_grid(n: int, dx: float):
    """(ky, kx, |k|) of the rfft2 half-spectrum of an n x n periodic grid of step dx [1/m]:
    arrays here are indexed [y, x] (the rfft axis is x), so the grid's axes are (y, x)."""
    g = Grid((n, n), (n * dx, n * dx))
    ky, kx = g.wavevector
    return ky, kx, g.kmag


def film_of_thickness(thickness_m) -> Film:
    """The film of ``thickness_m`` [m] (a number, validated here: the one check, where the value
    enters) or a ``Film`` already made (passed on as it is: issue 20, the thickness validated
    once on the way from ``calibrate`` to the base stresses)."""
    return thickness_m if isinstance(thickness_m, Film) else Film(thickness_m)


def base_stresses_3d(szz_hat, tx_hat, ty_hat, kx, ky, thickness_m):
    """Base-stress spectra (sigma_zz, sigma_xz, sigma_yz at z = 0) from the surface-traction
    spectra (sigma_zz, sigma_xz, sigma_yz at z = h) on wavevectors (kx, ky) [1/m].  Any
    broadcastable shapes; None tractions are zero.  ``thickness_m``: h [m] or a ``Film``."""
    kx = np.asarray(kx, dtype=float)
    ky = np.asarray(ky, dtype=float)
    k = np.hypot(kx, ky)
    safe = np.where(k > 0, k, 1.0)
    direction = (np.where(k > 0, kx / safe, 1.0), np.where(k > 0, ky / safe, 0.0))  # e_x at 0
    tau = (0.0 if tx_hat is None else tx_hat, 0.0 if ty_hat is None else ty_hat)
    film = film_of_thickness(thickness_m)
    out_zz, (out_x, out_y) = film.base_transfer(direction, k, szz_hat, tau)
    return out_zz, out_x, out_y


def flat_punch_transform(k, load_N: float, radius_m: float):
    """2D Fourier transform of P / (2 pi a sqrt(a^2 - r^2)) (r < a): P sin(ka)/(ka)."""
    ka = np.abs(np.asarray(k, dtype=float)) * radius_m
    return load_N * np.sinc(ka / np.pi)


def uniform_disc_transform(k, load_N: float, radius_m: float):
    """2D Fourier transform of a uniform pressure P/(pi a^2) on r < a: 2 P J1(ka)/(ka)."""
    from scipy.special import j1

    ka = np.abs(np.asarray(k, dtype=float)) * radius_m
    safe = np.where(ka > 1e-8, ka, 1.0)
    return load_N * np.where(ka > 1e-8, 2.0 * j1(safe) / safe, 1.0 - ka * ka / 8.0)


def _grid_size(r_max, thickness, dx, margin_h):
    L = 2.0 * (r_max + margin_h * thickness)
    n = int(math.ceil(L / dx))
    n += n % 2
    return n


def base_stresses_axisym(thickness_m: float, *, pressure_transform=None, r_m=None,
                         pressure_Pa=None, shear_r_Pa=None, dx_m: float | None = None,
                         r_max_m: float | None = None, margin_h: float = 16.0) -> dict:
    """Base stresses of the film under an axisymmetric surface load, as radial profiles.

    The load is either ``pressure_transform`` (callable k [1/m] -> 2D transform [N] of the
    pressure p(r) >= 0 in compression), or sampled radial profiles ``r_m``, ``pressure_Pa``
    and optionally ``shear_r_Pa`` (outward radial surface shear sigma_rz(r, h)).

    Returns {"r_m", "sigma_zz_Pa", "sigma_xz_Pa"}: sigma_zz(r, 0) (< 0 in compression) and
    sigma_xz(x = r, y = 0) = sigma_rz(r, 0) (the radial base shear; sigma_xz(x, y) =
    sigma_rz(r) x / r), r from 0 to ``r_max_m`` (default 8 h) in steps ``dx_m`` (default h/32);
    the periodic grid extends ``margin_h`` film thicknesses beyond r_max (images < 1e-5).
    """
    film = film_of_thickness(thickness_m)  # h [m] or a Film: checked once
    h = film.thickness
    if pressure_transform is None and (r_m is None or pressure_Pa is None):
        raise InputError("give pressure_transform, or r_m and pressure_Pa")
    if r_m is not None:
        r_in = np.asarray(r_m, dtype=float)
        if r_in.ndim != 1 or np.any(np.diff(r_in) <= 0) or r_in[0] < 0:
            raise InputError("r_m must be increasing radii >= 0")
    dx = float(dx_m) if dx_m else h / 32.0
    # the base stresses decay like exp(-0.74 r/h): 8 h keeps the plane integral within ~1e-3
    r_max = float(r_max_m) if r_max_m else (8.0 * h if r_m is None else max(r_in[-1], 8.0 * h))
    n = _grid_size(r_max, h, dx, margin_h)
    ky, kx, k = plane_grid(n, dx)
    fft = get_rfft((n, n))
    j = np.arange(n)
    c = np.where(j <= n // 2, j, j - n) * dx  # periodic coordinates, 0 at index 0
    if pressure_transform is not None:
        p_hat = np.asarray(pressure_transform(k), dtype=complex)
        tx_hat = ty_hat = None
        if shear_r_Pa is not None:
            raise InputError("shear_r_Pa needs sampled profiles (r_m, pressure_Pa)")
    else:
        rr = np.hypot(c[:, None], c[None, :])
        p = np.interp(rr, r_in, np.asarray(pressure_Pa, dtype=float), right=0.0)
        p_hat = fft.forward(p) * dx * dx
        tx_hat = ty_hat = None
        if shear_r_Pa is not None:
            tr = np.interp(rr, r_in, np.asarray(shear_r_Pa, dtype=float), right=0.0)
            with np.errstate(invalid="ignore", divide="ignore"):
                cx = np.where(rr > 0, c[None, :] / np.where(rr > 0, rr, 1.0), 0.0)
                cy = np.where(rr > 0, c[:, None] / np.where(rr > 0, rr, 1.0), 0.0)
            tx_hat = fft.forward(tr * cx) * dx * dx
            ty_hat = fft.forward(tr * cy) * dx * dx
    zz_hat, xz_hat, _ = base_stresses_3d(-p_hat, tx_hat, ty_hat, kx, ky, film)
    szz = fft.backward(zz_hat) / (dx * dx)
    sxz = fft.backward(xz_hat) / (dx * dx)
    m = int(round(r_max / dx)) + 1
    return {"r_m": np.arange(m) * dx, "sigma_zz_Pa": szz[0, :m].copy(),
            "sigma_xz_Pa": sxz[0, :m].copy()}


def flat_punch_base_stresses(load_N: float = 1.0, radius_m: float = 250e-6,
                             thickness_m: float = 2e-3, dx_m: float | None = None,
                             r_max_m: float | None = None) -> dict:
    """Radial base-stress profiles under a frictionless rigid flat punch (half-space pressure
    distribution, see the module docstring).  Linear in ``load_N``; ``thickness_m``: h [m] or
    a ``Film``."""
    for name, v in (("load_N", load_N), ("radius_m", radius_m)):
        if not (math.isfinite(float(v)) and float(v) > 0):
            raise InputError(f"{name} must be > 0; got {v}")
    return base_stresses_axisym(
        thickness_m, pressure_transform=lambda k: flat_punch_transform(k, load_N, radius_m),
        dx_m=dx_m, r_max_m=r_max_m)


def punch_sensitivity(radius_m: float = 250e-6, thickness_m: float = 2e-3) -> dict:
    """Max difference between the base stresses of the punch distribution and of a uniform
    pressure on the same disc, relative to the peak |sigma_zz| (a bound on the effect of the
    pressure-distribution assumption)."""
    a = flat_punch_base_stresses(1.0, radius_m, thickness_m)
    b = base_stresses_axisym(thickness_m,
                             pressure_transform=lambda k: uniform_disc_transform(k, 1.0, radius_m))
    peak = np.abs(a["sigma_zz_Pa"]).max()
    return {"zz": float(np.abs(a["sigma_zz_Pa"] - b["sigma_zz_Pa"]).max() / peak),
            "xz": float(np.abs(a["sigma_xz_Pa"] - b["sigma_xz_Pa"]).max() / peak)}
