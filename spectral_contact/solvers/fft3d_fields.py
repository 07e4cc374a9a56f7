"""The surfaces' output fields and open-box helpers (``solvers.fft3d``): the base tractions
and surface displacements of a pressure and its shear through the film's multipliers (cached per
grid), and the open box's contact solve, its box check and its far base fields."""
from __future__ import annotations

import math

import numpy as np

from ..numerics.contact import solve_complementarity
from ..numerics.fft import get_rfft
from ..numerics.open_domain import box_of, open_compliance_operator
from ..physics.film import Film
from ..physics.transfer import F2, compressible_tangential_function, tanh_over, transfer_functions

_FAR_CELLS = 12    # the base fields of an open solve: a periodic grid of cells h / this (the
# base transfer decays as exp(-|k| h): e^-37 at its Nyquist wavenumber)


_MULTIPLIERS: dict = {}  # (film, shape, lengths, mu) -> the output fields' multipliers
_MULTIPLIER_BYTES = 2**28  # the cache's budget: 256 MB (2048^2 with mu given: 6 complex
# arrays of 2048 x 1025, 202 MB, the only entry; 1024^2: 50 MB each).  Measured: their
# evaluation at 2048^2 cost ~12 FFT-pair times of the grid, each solve, when not kept


def _radial_coefficients(film: Film, K):
    """The output fields' coefficients that depend on |k| only (``_multipliers``)."""
    Kh = K * film.thickness
    if film.incompressible:  # one evaluation of the five transfer functions
        F0, F1, A, B, C = transfer_functions(Kh)
        iB = iBp = 1j * B
        e = np.exp(-np.abs(Kh))
        T = 2.0 * e / (1.0 + e * e)  # sech K (Film's)
    else:
        A, iB, iBp, C, T = film.base_coefficients(K)
        F0, F1 = film._F0_F1(K)
    F2_ = F2(Kh) if film.incompressible else compressible_tangential_function(Kh, film.poisson)
    pos = K > 0
    inv2k = np.where(pos, 0.5 / np.where(pos, K, 1.0), 0.0)
    cL = np.where(pos, F2_ * inv2k, film.thickness)
    cT = film.thickness * tanh_over(Kh)
    iF1 = 1j * F1 * inv2k
    d0 = F0 * inv2k
    if not film.incompressible:
        d0 = d0 + np.where(pos, 0.0, film.uniform_compliance)
    return A, iB, iBp, C, T, cL, cT, iF1, d0


def _even_in_kx(fn, K):
    """fn(K) (a tuple of arrays, elementwise in K) on the half spectrum's |k| (shape kshape, the
    first axis in fftfreq order), evaluated on the rows k_x >= 0 only and mirrored: |k| of row
    n - i is |k| of row i bit for bit (fftfreq's values are exact negatives), so the result is
    fn(K)'s, at half the cost (issue 25: the transfer functions were ~1/3 of the outputs' time
    at 2048^2)."""
    n = K.shape[0]
    m = n // 2 + 1
    if K.ndim != 2 or n < 4:
        return fn(K)
    out = []
    for h in fn(K[:m]):
        h = np.broadcast_to(h, (m,) + K.shape[1:])
        out.append(np.concatenate([h, h[1:n - m + 1][::-1]]))
    return tuple(out)


def _multipliers(film: Film, grid, mu):
    """Per-mode multipliers of the output fields (``_output_fields``): with t^ = mu p^
    (``mu`` given) six arrays M with field^ = M p^; otherwise the pairs (M_p, M_t) with
    field^ = M_p p^ + M_t t^.  Averaged over the two aliases on the Nyquist plane of the
    first axis (``Grid.alias_average``; the last axis's is the real transform's).  Cached per
    film, grid shape, periods and mu for the next solve on that grid (issue 25: a sweep over
    forces or friction on one grid; their evaluation cost ~20 FFT pairs at 512^2)."""
    key = (film, grid.shape, grid.lengths, mu)
    out = _MULTIPLIERS.get(key)
    if out is not None:
        return out
    A, iB, iBp, C, T, cL, cT, iF1, d0 = _even_in_kx(lambda K: _radial_coefficients(film, K),
                                                    grid.kmag)

    def pairs(nx, ny, sl):
        """(M_p, M_t) of szz, sxz, syz, ux, uy, delta on the modes ``sl``; a moving
        viscoelastic film's displacements times its R(k) = G_inf/G*(-k_x V) (the stresses
        are the elastic film's: ``ViscoelasticFilm.surface_displacement_transfer``)."""
        a, b, bp, c, t = A[sl], iB[sl], iBp[sl], C[sl], T[sl]
        cl, ct, f1, dd = cL[sl], cT[sl], iF1[sl], d0[sl]
        nx2 = nx * nx
        out = ((-a, b * nx), (-bp * nx, c * nx2 + t * (1.0 - nx2)),
               (-bp * ny, (c - t) * nx * ny), (-f1 * nx, cl * nx2 + ct * (1.0 - nx2)),
               (-f1 * ny, (cl - ct) * nx * ny), (dd, f1 * nx))
        if not getattr(film, "moving", False):
            return out
        R = film.modulus_ratio((nx, ny), grid.kmag[sl])
        return out[:3] + tuple((R * mp, R * mt) for mp, mt in out[3:])

    nx, ny = (np.broadcast_to(n, grid.kshape) for n in grid.direction)
    full = (slice(None),) * 2
    ms = [list(m) for m in pairs(nx, ny, full)]
    mask = grid.nyquist_mask
    if mask is not None:  # the Nyquist plane k_x = -pi/dx: the mean with its alias +pi/dx
        row = (grid.shape[0] // 2, slice(None))
        ax, ay = (np.broadcast_to(n, grid.kshape)[row] for n in grid.alias_direction)
        for m, alias in zip(ms, pairs(ax, ay, row)):
            for i in (0, 1):
                m[i] = np.array(m[i], dtype=complex)
                m[i][row] = 0.5 * (m[i][row] + alias[i])
    if mu is not None:
        out = tuple(mp + mu * mt for mp, mt in ms)
    else:
        out = tuple(tuple(m) for m in ms)
    size = sum(m.nbytes for m in (out if mu is not None else sum(out, ())))
    if size <= _MULTIPLIER_BYTES:
        while _MULTIPLIERS and size + sum(m.nbytes for v in _MULTIPLIERS.values() for m in
                                          (v if isinstance(v[0], np.ndarray) else sum(v, ()))
                                          ) > _MULTIPLIER_BYTES:
            del _MULTIPLIERS[next(iter(_MULTIPLIERS))]  # the oldest first
        _MULTIPLIERS[key] = out
    return out


def _output_fields(film: Film, grid, p, mu, shear):
    """Base tractions (sigma_zz, sigma_xz, sigma_yz at z = 0) and surface displacements
    (u_x, u_y, delta = -u_z) on ``grid`` from the pressure p and the surface shear along x
    (``shear``; = mu p when ``mu`` is given: its spectrum is then mu p^, no transform).  The
    fields of ``Film.base_stresses`` and ``Film.surface_displacements`` (physics3d.md, equal
    to round-off), with one forward transform (two with a friction law) instead of six and
    the transfer functions evaluated once per grid (``_multipliers``): issue 25."""
    fft = get_rfft(grid.shape)
    p_hat = fft.forward(p)
    m = _multipliers(film, grid, mu)
    if mu is not None:
        return tuple(fft.backward(mi * p_hat) for mi in m)
    t_hat = fft.forward(shear)
    return tuple(fft.backward(mp * p_hat + mt * t_hat) for mp, mt in m)


def _open_contact(grid, ind, mu: float, film: Film, c: float, accept: float, p_init=None):
    """The contact solve on an open box (``numerics.open_domain``): the padded ``grid``'s
    nodes outside its central box cannot touch (height +inf)."""
    op = open_compliance_operator(grid.shape, grid.lengths, float(mu), film)
    if c:
        op = op + c
    f = np.full(grid.shape, np.inf)
    box = box_of(grid)
    f[box] = np.broadcast_to(ind.height(grid), grid.shape)[box]
    if p_init is None:
        p_init = np.where(np.isfinite(f), np.broadcast_to(ind.initial_pressure(grid), grid.shape),
                          0.0)
    sol = solve_complementarity(op, f, np.zeros(grid.shape, dtype=np.intp), [ind.load],
                                p_init=p_init, accept=accept, grid=grid)
    if c:
        sol.sinking = sol.sinking - c * sol.pressure  # the film's sinking (as solve_contact_law)
    return sol


def _touches_box(sol) -> bool:
    """Whether the contact comes within 7 nodes of its box's border (the edge fits need 6)."""
    box = box_of(sol.grid)
    act = sol.active[box]
    if not act.any():
        return False
    ix, iy = np.nonzero(act)
    nx, ny = act.shape
    return bool(ix.min() < 7 or iy.min() < 7 or ix.max() > nx - 8 or iy.max() > ny - 8)


def _far_fields(film: Film, grid, p: np.ndarray, mu: float, margin: float, shear=None):
    """Base tractions and surface displacements at the box nodes of an open solve: the
    pressure's Fourier series on a periodic grid of the film's period (box + ``margin``, cells
    h / _FAR_CELLS), taken exactly from the nodes (a non-uniform DFT: no deposit error), through
    the film's transfer functions and summed back at the box nodes.  The base transfer decays
    as exp(-|k| h): exact to round-off there; the surface displacements are band-limited to
    that grid's wavenumbers (resolved at h / _FAR_CELLS, not at the box's cells)."""
    x, y = grid.axes
    Lc = tuple(float(np.ptp(a)) + d + margin for a, d in zip((x, y), grid.spacing))
    nc = tuple(2 * math.ceil(L * _FAR_CELLS / film.thickness / 2) for L in Lc)
    origin = (float(x.mean()) - Lc[0] / 2, float(y.mean()) - Lc[1] / 2)
    kx = 2 * np.pi * np.fft.fftfreq(nc[0], Lc[0] / nc[0])
    ky = 2 * np.pi * np.fft.fftfreq(nc[1], Lc[1] / nc[1])
    Ex = np.exp(-1j * np.outer(kx, x - origin[0]))
    Ey = np.exp(-1j * np.outer(ky, y - origin[1]))
    weight = grid.cell / (Lc[0] * Lc[1] / (nc[0] * nc[1]))

    def spectrum(field):
        return (Ex @ (field * weight)) @ Ey.T

    p_hat = spectrum(p)
    tau = mu * p if shear is None else shear
    t_hat = spectrum(tau)
    K = np.hypot(kx[:, None], ky[None, :])
    safe = np.where(K > 0, K, 1.0)
    n = (np.where(K > 0, kx[:, None] / safe, 1.0), np.where(K > 0, ky[None, :] / safe, 0.0))
    zero = np.zeros_like(p_hat)
    szz, (sxz, syz) = film.base_transfer(n, K, -p_hat, (t_hat, zero))
    (ux, uy), _ = film.surface_displacement_transfer(n, K, p_hat, (t_hat, zero))
    scale = 1.0 / (nc[0] * nc[1])

    def back(spec):
        return ((Ex.conj().T @ spec) @ Ey.conj()).real * scale

    return back(szz), back(sxz), back(syz), back(ux), back(uy), nc[0] * (Lc[0] / nc[0])
