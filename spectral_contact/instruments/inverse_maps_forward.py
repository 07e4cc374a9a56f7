"""The maps' forward operator (issue 21, surfaces): the per-mode symbol M(k) from the surface
tractions (p, q_x, q_y) to the data (-sigma_zz, sigma_xz, sigma_yz at the base, or the S maps
through the 2D apparatus), and the base maps of given tractions.  See ``inverse_maps``."""
from __future__ import annotations

import numpy as np

from ..numerics.grid import Grid
from ..physics.film import Film

__all__ = ["symbol", "base_maps_from_tractions", "mode_weights", "inv_logdet3"]


def _symbol(grid: Grid, film: Film, apparatus=None, h_m: float = 1.0):
    """M(k): (kshape + (3, 3)) complex, data (d_zz, d_xz, d_yz)^ per traction (p, q_x, q_y)^,
    on ``grid`` (lengths in h).  apparatus: None or (G_zz, G_xz) ApparatusFunction [m]."""
    kmag = grid.kmag
    coef = film.base_coefficients(kmag)
    one, zero = np.ones(grid.kshape, complex), np.zeros(grid.kshape, complex)
    cols = []
    for szz, tx, ty in ((-one, zero, zero), (zero, one, zero), (zero, zero, one)):
        s0, (x0, y0) = grid.alias_average(
            lambda n, szz=szz, tx=tx, ty=ty: film.base_transfer(n, kmag, szz, (tx, ty), coef))
        cols.append((-s0, x0, y0))
    M = np.empty(grid.kshape + (3, 3), complex)
    for j, col in enumerate(cols):
        for i, c in enumerate(col):
            M[..., i, j] = c
    if apparatus is not None:
        gzz = np.asarray(apparatus[0].transform(kmag / h_m), float)
        gxz = np.asarray(apparatus[1].transform(kmag / h_m), float)
        M[..., 0, :] *= gzz[..., None]
        M[..., 1:, :] *= gxz[..., None, None]
    return M


def base_maps_from_tractions(x_m, y_m, p_Pa, qx_Pa, qy_Pa, thickness: float,
                             poisson: float = 0.5):
    """Base stresses (sigma_zz, sigma_xz, sigma_yz)(x, y, 0) [Pa] of surface tractions on a
    uniform grid taken as one period (pad the tractions with zeros well beyond them).  Signs of
    the package: p >= 0 in compression, q = (sigma_xz, sigma_yz)(h); sigma_zz(base) < 0 in
    compression.  (The film's ``base_stresses`` on the grid.)"""
    from ..numerics.fft import get_rfft

    x, y = np.asarray(x_m, float), np.asarray(y_m, float)
    dx, dy = (x[-1] - x[0]) / (x.size - 1), (y[-1] - y[0]) / (y.size - 1)
    grid = Grid((x.size, y.size), (x.size * dx / thickness, y.size * dy / thickness))
    film = Film(1.0, poisson)
    szz, (sxz, syz) = film.base_stresses(get_rfft(grid.shape), grid, -np.asarray(p_Pa, float),
                                         (np.asarray(qx_Pa, float), np.asarray(qy_Pa, float)))
    return szz, sxz, syz


def _weights(shape):
    """Multiplicity of each rfft2 mode in the full spectrum (2, or 1 on the ky = 0 and
    ky = Nyquist columns)."""
    ny = shape[1]
    w = np.full(ny // 2 + 1, 2.0)
    w[0] = 1.0
    if ny % 2 == 0:
        w[-1] = 1.0
    return w[None, :]


symbol = _symbol
mode_weights = _weights


def inv_logdet3(S):
    """Inverse and log|det| of Hermitian positive-definite 3x3 matrices (..., 3, 3), by
    cofactors (several times faster than ``numpy.linalg.inv`` and ``slogdet`` on the per-mode
    batches of the maps; relative error ~ condition number x 1e-16).  Raises LinAlgError where
    a determinant is not positive."""
    a = S
    c00 = a[..., 1, 1] * a[..., 2, 2] - a[..., 1, 2] * a[..., 2, 1]
    c01 = a[..., 1, 2] * a[..., 2, 0] - a[..., 1, 0] * a[..., 2, 2]
    c02 = a[..., 1, 0] * a[..., 2, 1] - a[..., 1, 1] * a[..., 2, 0]
    det = (a[..., 0, 0] * c00 + a[..., 0, 1] * c01 + a[..., 0, 2] * c02).real
    if not np.all(det > 0):
        raise np.linalg.LinAlgError("a per-mode covariance is not positive definite")
    inv = np.empty_like(S)
    inv[..., 0, 0] = c00
    inv[..., 1, 0] = c01
    inv[..., 2, 0] = c02
    inv[..., 0, 1] = a[..., 0, 2] * a[..., 2, 1] - a[..., 0, 1] * a[..., 2, 2]
    inv[..., 1, 1] = a[..., 0, 0] * a[..., 2, 2] - a[..., 0, 2] * a[..., 2, 0]
    inv[..., 2, 1] = a[..., 0, 1] * a[..., 2, 0] - a[..., 0, 0] * a[..., 2, 1]
    inv[..., 0, 2] = a[..., 0, 1] * a[..., 1, 2] - a[..., 0, 2] * a[..., 1, 1]
    inv[..., 1, 2] = a[..., 0, 2] * a[..., 1, 0] - a[..., 0, 0] * a[..., 1, 2]
    inv[..., 2, 2] = a[..., 0, 0] * a[..., 1, 1] - a[..., 0, 1] * a[..., 1, 0]
    inv /= det[..., None, None]
    return inv, np.log(det)
