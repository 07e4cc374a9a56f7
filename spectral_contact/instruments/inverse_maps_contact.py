"""The maps' contact prior (issue 21, surfaces): tractions shaped as a contact's are, the
surface analogue of the line inverse's ``inverse_prior`` (its hyperparameters by evidence).

Prior (cells x_i of the record's grid, lengths in h).  An ellipse of centre (c_x, c_y) and
semi-axes (a_x, a_y) (axis-aligned; hyperparameters), u^2 = ((x - c_x)/a_x)^2 +
((y - c_y)/a_y)^2, z = 1 - u^2, carries

    p = W g_p + n_p,
    q = mu0 e p + W (g_x, g_y) + I (tau_x, tau_y) + n_q,

with W = diag(w), w = sqrt(z+) the square-root profile of a contact's edges (a smooth indenter's
pressure falls as the square root of the distance to the edge), I = (1 on the ellipse) (a shear
strength makes q step at the edge), e the unit vector of the total tangential force (from the
stationary fit), g_p, g_x, g_y independent zero-mean Matern-5/2 fields (lengths l_p, l_r;
amplitude s_p for all three, tied as in the line prior: a local mu departing from mu0 by ~1 is
allowed a priori), tau_x, tau_y ~ N(0, s_p^2), and n an independent white nugget of sd s_out on
every cell of the record (what the shapes above do not hold, inside or outside the ellipse).
``z+`` is z rounded over half a cell (softplus), so that the evidence is smooth in c and a.
g lives on a lattice of step ``LATTICE`` a (bilinear to the cells): smooth fields, the sqrt
edge carried by W at the cells' own resolution.

The eight hyperparameters (c_x, c_y, log a_x, log a_y, log s_p, log l_p, mu0, log l_r) maximise
the evidence with the nugget s_out and the noise fixed (the noise at the stationary fit's
values, which 3 N samples determine; s_out chosen among decades at the end point, the fit
repeated until that choice settles).  l_p and l_r are at most the contact's width
(``LP_MAX_WIDTH``, ``LR_MAX_WIDTH``).
The fit runs to convergence with the analytic gradient below (L-BFGS-B), and reports it: the
Newton step its end point leaves, in each hyperparameter's Laplace sd (``remaining_step``).
(It used to stop after 15 + 8 iterations with differenced gradients, unconverged: 1e-12 of
the data moved a study record's answer by 1 sd, a slightly moved start the test disc's by 4.)

Evidence and posterior.  The nugget's part is stationary: S0(k) = s_out^2 M M^H + D per mode.
The window's part has few unknowns (g on the lattice, tau): with U the cells-from-unknowns map
and K their prior covariance, Woodbury and the matrix-determinant lemma give

    log det S = Sum_k log det S0(k) + log det B,   B = I + L^T G L,  K = L L^T,
    y^T S^-1 y = y^T S0^-1 y - |chol(B)^-1 L^T v|^2,  G = U^T (M^H S0^-1 M) U,  v = U^T M^H S0^-1 y,

where M^H S0^-1 M, a convolution, is gathered from its kernel on the ellipse's cells.  The
posterior of g is N(L B^-1 L^T v, L B^-1 L^T); given g the nugget's part is the stationary
posterior of the residual data.  So the tractions' posterior mean is U g + R0 (y - M U g) and
their covariance C0 + T U Sigma_g U^T T^T, with R0 = s_out^2 M^H S0^-1 M, T = I - R0 and C0 =
s_out^2 T (per mode): the pointwise variance is C0's (the same everywhere) plus the window's
part, large where the contact's shape leaves the tractions uncertain.

Gradient.  With Sigma = L B^-1 L^T and m = Sigma v (the unknowns' posterior covariance and
mean), the prior's covariance K = L L^T (s_p, l_p, l_r) enters as d log Z = (a^T dK a -
tr(W dK)) / 2 with a = v - G m, W = G - G Sigma G, and U (the ellipse through w and I, and
mu0) as d log Z = <dU, R> (Frobenius) with R = b m^T - Gc U (m m^T + Sigma), b the cells'
M^H S0^-1 y and Gc the cells' M^H S0^-1 M.  A value with its gradient costs ~1.8 values
(with forward differences: 9).
"""
from __future__ import annotations

import math

import numpy as np

from .inverse_maps_forward import inv_logdet3
from .inverse_maps_forward import mode_weights as _weights

__all__ = ["ContactMapPrior", "fit_contact", "propagate", "PRIOR_NAMES"]

PRIOR_NAMES = ("centre_x_h", "centre_y_h", "log_semi_axis_x", "log_semi_axis_y", "log_s_p",
               "log_l_p", "mu0", "log_l_r")

LATTICE = 0.33
"""The lattice step of g in units of the initial mean semi-axis."""
_ROUND = 0.1
"""The ellipse's edge is rounded over this fraction of a cell (in z's own scale)."""
_SUPER = 1.5
"""The ellipse may grow to this factor of its initial semi-axes (the lattice covers it)."""
_JITTER = 1e-9
OPT_GTOL = 1e-3
"""The fit stops when no component of the log-evidence's projected gradient exceeds this (nats
per unit of theta: h for the centre, 1 for the logs and mu0)."""
OPT_FTOL = 1e-15
"""L-BFGS-B's relative-decrease test, set below what the evidence's rounding (~1e-16 of its
~1e5 nats) resolves, so that the gradient test decides."""
OPT_MAXITER = 300
"""L-BFGS-B iterations per round at most."""
CONVERGED_STEP_SD = 0.02
"""The fit counts as converged when the Newton step Sigma_theta g that its end point leaves (g
the projected gradient, Sigma_theta the Laplace covariance of ``propagate``) is at most this
fraction of each hyperparameter's sd (``remaining_step``), and the nugget's choice settled.
(The gradient alone is no measure: the ellipse's curvature is ~1e6 per h^2, where a gradient
of 1e-3 is a step of 1e-9 h and the evidence's rounding leaves ~1e-2.)"""
NUGGET_ROUNDS = 4
"""Rounds of (fit over theta, nugget's choice) at most."""
LP_MAX_WIDTH = 2.0
"""p's length l_p is at most this many times the starting ellipse's mean semi-axis (the
contact's width), as the line inverse's (``inverse_prior.LP_MAX_WIDTH``, same reason): on an
ellipse of semi-axis a a Matern process of length l >> a is a constant plus terms of prior
variance ~ (a/l)^(2k), so longer lengths only turn p into the parametric Hertz shape, which a
sliding contact's pressure on a film is not; the converged fit went there (l_p 3-4 h on the
studies' a = 1.35 h) and its bands lost coverage (studies/README, inverse_maps)."""
LR_MAX_WIDTH = 2.0
"""q's length l_r likewise (unlike the line inverse, where capping it widened q's bands past
nominal): with l_r free the converged fit took it to its 20 h bound on every study record (q =
mu0 p + a constant times the sqrt profile) and the law fits' bands came out too narrow (10 seeds
of the strength record: z of tau0 rms 1.64, of alpha 1.46, 8 of 10 within 2 sigma; Amontons
tied by the linear law on 5 of 20 Amontons records); capped, 0.93 and 0.89, 10 of 10, and
20 of 20; on held-out seeds 10-19 1.22 and 1.17, 8 of 10 (free: 1.79, 1.57, 7 of 10; the code
before this cap's session 1.14, 1.12, 9 of 10) (studies/README, inverse_maps)."""
NUGGET_DECADES = 4
"""The nugget sd is chosen by evidence among s0, s0/10, ... (this many values; s0 the
stationary fit's pointwise sd)."""
_REACH = 8.0
"""Cells where z > -_REACH eps (w > ~1e-2 of its centre value) carry the window's part."""
_TAPER = 2.0
"""w and I fall to zero over the outermost ``_TAPER`` eps of the active band (``window``)."""
_UG_KEEP = 12
"""``ContactMapPrior._projected`` keeps this many (U, G, v) (~1 MB each on the studies'
records), and Gc U for the last one (for the gradient at the point just evaluated)."""
LAG_TABLE_MAX_CELLS = 4000
"""Up to this many reachable cells the lags between them are tabulated once (int32, at most
64 MB; 990 cells on the studies' 160^2 sphere records)."""


def _matern52(d, length):
    r = math.sqrt(5.0) * d / length
    return (1.0 + r + r * r / 3.0) * np.exp(-r)


def _logistic(u):
    return 0.5 * (1.0 + np.tanh(0.5 * u))


def _softplus(z, eps):
    return eps * np.logaddexp(0.0, z / eps)




def start_geometry(p, steps):
    """Centre and semi-axes of a contact from a pressure estimate p [x, y] (moments of its part
    above 10 % of the peak: <x^2> = a^2/5 for p ~ sqrt(1 - r^2/a^2)), in cells' units x steps."""
    dx, dy = steps
    nx, ny = p.shape
    w = np.where(p > 0.1 * p.max(), p, 0.0)
    X, Y = np.meshgrid(np.arange(nx) * dx, np.arange(ny) * dy, indexing="ij")
    s = w.sum()
    cx, cy = (w * X).sum() / s, (w * Y).sum() / s
    vx, vy = (w * (X - cx) ** 2).sum() / s, (w * (Y - cy) ** 2).sum() / s
    return cx, cy, math.sqrt(5.0 * vx), math.sqrt(5.0 * vy)


class ContactMapPrior:
    """The contact prior on one record (scaled data): evidence(theta), posterior(theta).

    M : (kshape, 3, 3) symbol; Y : (kshape, 3) rfft2 of the scaled data; shape (nx, ny);
    steps (dx, dy) [h]; noise : the three noise sd (scaled, fixed); e : the direction of the
    total shear; geom : (c_x, c_y, a_x, a_y) the starting ellipse [h, from the grid's origin].
    """

    def __init__(self, M, Y, shape, steps, noise, e, geom):
        from scipy import sparse

        self.M, self.Y = M, Y
        self.shape = shape
        self.N = shape[0] * shape[1]
        self.steps = steps
        self.noise2 = np.asarray(noise, float) ** 2
        self.e = e
        self.w = np.broadcast_to(_weights(shape), M.shape[:-2])
        cx, cy, ax, ay = geom
        self.geom0 = geom
        dx, dy = steps
        # the cells the ellipse may reach
        X, Y_ = np.meshgrid(np.arange(shape[0]) * dx, np.arange(shape[1]) * dy, indexing="ij")
        Rx, Ry = _SUPER * ax + 2 * dx, _SUPER * ay + 2 * dy
        sup = ((X - cx) / Rx) ** 2 + ((Y_ - cy) / Ry) ** 2 <= 1.0
        self.cells = np.argwhere(sup)
        self.cx_, self.cy_ = self.cells[:, 0] * dx, self.cells[:, 1] * dy
        # lattice for g (bilinear to the cells)
        step = LATTICE * 0.5 * (ax + ay)
        x0, y0 = self.cx_.min(), self.cy_.min()
        nlx = int(math.ceil((self.cx_.max() - x0) / step)) + 1
        nly = int(math.ceil((self.cy_.max() - y0) / step)) + 1
        fx, fy = (self.cx_ - x0) / step, (self.cy_ - y0) / step
        ix, iy = np.minimum(np.floor(fx).astype(int), nlx - 2), np.minimum(
            np.floor(fy).astype(int), nly - 2)
        tx, ty = fx - ix, fy - iy
        rows, cols, vals = [], [], []
        n = len(self.cells)
        for ox, oy, wv in ((0, 0, (1 - tx) * (1 - ty)), (1, 0, tx * (1 - ty)),
                           (0, 1, (1 - tx) * ty), (1, 1, tx * ty)):
            rows.append(np.arange(n))
            cols.append((ix + ox) * nly + (iy + oy))
            vals.append(wv)
        P = sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                       np.concatenate(cols))),
                              shape=(n, nlx * nly))
        used = np.unique(P.indices)  # lattice nodes that touch a cell
        self.P = P[:, used].tocsr()
        lx = x0 + (used // nly) * step
        ly = y0 + (used % nly) * step
        self.m = used.size
        self.dist = np.hypot(lx[:, None] - lx[None, :], ly[:, None] - ly[None, :])
        self._s0 = {}
        self._gsub = {}
        self._ug = {}
        self._lag = None

    # -- the nugget's stationary part ------------------------------------------------------
    def _stationary(self, s_out):
        """Per-mode S0^-1, kernel of M^H S0^-1 M, b = M^H S0^-1 y, y^T S0^-1 y, log det S0."""
        if s_out in self._s0:
            return self._s0[s_out]
        M = self.M
        S0 = s_out**2 * np.einsum("...ij,...kj->...ik", M, M.conj())
        S0[..., [0, 1, 2], [0, 1, 2]] += self.noise2
        Si, logdet = inv_logdet3(S0)
        Kn = np.einsum("...ki,...kl,...lj->...ij", M.conj(), Si, M)
        Kn = 0.5 * (Kn + np.swapaxes(Kn.conj(), -1, -2))
        a = np.einsum("...ij,...j->...i", Si, self.Y)
        quad = float(np.sum(self.w * np.einsum("...i,...i->...", self.Y.conj(), a).real)) / self.N
        ld = float(np.sum(self.w * logdet))
        bk = np.einsum("...ki,...k->...i", M.conj(), a)
        b = np.fft.irfft2(np.moveaxis(bk, -1, 0), s=self.shape, axes=(1, 2))
        kern = np.empty((3, 3) + self.shape)
        for i in range(3):
            for j in range(3):
                kern[i, j] = np.fft.irfft2(Kn[..., i, j], s=self.shape)
        ci, cj = self.cells[:, 0], self.cells[:, 1]
        bw = np.concatenate([b[f][ci, cj] for f in range(3)])
        out = {"Si": Si, "Kn": Kn, "quad": quad, "logdet": ld, "kern": kern, "bw": bw}
        self._s0[s_out] = out
        self._gsub = {}
        return out

    def _lags(self, act):
        """Flat index (into a [nx, ny] map) of the periodic lag between every two active cells.
        From a table over every two reachable cells, computed once when it is small enough
        (``LAG_TABLE_MAX_CELLS``): the index arithmetic was half of a Gram matrix's cost, and
        the active set changes whenever the ellipse crosses a cell (~80 times in a fit)."""
        def lags(ci, cj):
            di = (ci[:, None] - ci[None, :]) % self.shape[0]
            dj = (cj[:, None] - cj[None, :]) % self.shape[1]
            return di * self.shape[1] + dj

        if len(self.cells) > LAG_TABLE_MAX_CELLS:
            return lags(self.cells[act, 0], self.cells[act, 1])
        if self._lag is None:
            self._lag = lags(self.cells[:, 0], self.cells[:, 1]).astype(np.int32)
        return self._lag[np.ix_(act, act)]

    def _gram(self, kern, act):
        """M^H S0^-1 M between the active cells (3 n_a x 3 n_a), from its kernel."""
        lag = self._lags(act)
        n = act.size
        Gc = np.empty((3 * n, 3 * n))
        for i in range(3):
            for j in range(3):
                Gc[i * n:(i + 1) * n, j * n:(j + 1) * n] = kern[i, j].ravel().take(lag)
        return 0.5 * (Gc + Gc.T)

    # -- the window's part -------------------------------------------------------------------
    def window(self, th, deriv=False):
        """w and I on the reachable cells, and the active cells (z > -``_REACH`` eps, where w
        is ~2e-2 sqrt(eps) of its centre value).  Both are tapered to zero over the outermost
        ``_TAPER`` eps of that band (a C^1 smoothstep), so that a cell enters the active set
        with zero weight: the evidence is then continuous (C^1) in the ellipse, as a
        gradient-based fit needs (it jumped by ~2e-2 nats when a cell entered, on the study's
        amontons sensor record seed 3; now its second differences at those points are those of
        its curvature, ~1e-4).
        ``deriv``: also d w / d theta[0:4] and d I / d theta[0:4] on the active cells
        (4, n_a) each."""
        cx, cy = th[0], th[1]
        ax, ay = math.exp(th[2]), math.exp(th[3])
        X, Y = (self.cx_ - cx) / ax, (self.cy_ - cy) / ay
        z = 1.0 - X * X - Y * Y
        eps = _ROUND * 2.0 * max(self.steps) / min(ax, ay)
        active = np.nonzero(z > -_REACH * eps)[0]
        sp = _softplus(z, eps)
        sig = _logistic(z / eps)
        zeta = np.clip((z + _REACH * eps) / (_TAPER * eps), 0.0, 1.0)
        taper = zeta * zeta * (3.0 - 2.0 * zeta)
        root = np.sqrt(sp)
        w, ind = taper * root, taper * sig
        if not deriv:
            return w, ind, active
        a = active
        X, Y, z, sp, sig, zeta, taper, root = (v[a] for v in (X, Y, z, sp, sig, zeta, taper,
                                                               root))
        dz = np.stack([2.0 * X / ax, 2.0 * Y / ay, 2.0 * X * X, 2.0 * Y * Y])
        # eps = c / min(ax, ay): d eps / d log a = -eps for the smaller semi-axis
        de = np.array([0.0, 0.0, -eps if ax <= ay else 0.0, -eps if ax > ay else 0.0])[:, None]
        dsp = sig * dz + (sp / eps - z / eps * sig) * de
        dsig = sig * (1.0 - sig) * (dz / eps - z / eps**2 * de)
        inner = zeta < 1.0
        dzeta = np.where(inner, (dz + _REACH * de) / (_TAPER * eps) - zeta * de / eps, 0.0)
        dtaper = 6.0 * zeta * (1.0 - zeta) * dzeta
        dw = dtaper * root + taper * dsp / (2.0 * root)
        dind = dtaper * sig + taper * dsig
        return w, ind, active, dw, dind

    def U(self, th):
        """(U on the active cells' rows (3 n_a) and the active lattice nodes' columns, active
        cells, active nodes)."""
        from scipy import sparse

        w, ind, act = self.window(th)
        P = self.P[act]
        nodes = np.unique(P.indices)
        P = P[:, nodes]
        mu0 = th[6]
        WP = sparse.diags(w[act]) @ P
        n, m = act.size, nodes.size
        Z = sparse.csr_matrix((n, m))
        ex, ey = self.e
        ind_c = sparse.csr_matrix(ind[act][:, None])
        z1 = sparse.csr_matrix((n, 1))
        U = sparse.bmat([[WP, Z, Z, z1, z1],
                         [mu0 * ex * WP, WP, Z, ind_c, z1],
                         [mu0 * ey * WP, Z, WP, z1, ind_c]], format="csr")
        return U, act, nodes

    def Lchol(self, th, nodes, blocks=False):
        """The prior's Cholesky factor on the active nodes (block diagonal: g_p, g_x, g_y, tau);
        ``blocks``: the list of the four blocks instead of the matrix."""
        from scipy.linalg import block_diag

        s = math.exp(th[4])
        lp, lr = math.exp(th[5]), math.exp(th[7])
        d = self.dist[np.ix_(nodes, nodes)]
        eye = np.eye(nodes.size)
        Lp = s * np.linalg.cholesky(_matern52(d, lp) + _JITTER * eye)
        Lr = Lp if lr == lp else s * np.linalg.cholesky(_matern52(d, lr) + _JITTER * eye)
        parts = [Lp, Lr, Lr, s * np.eye(2)]
        return parts if blocks else block_diag(*parts)

    def _rows(self, act):
        n = len(self.cells)
        return np.concatenate([act, act + n, act + 2 * n])

    def _projected(self, th, st):
        """(U, active cells, active nodes, G = U^T Gc U, v = U^T b, Gc U) at theta: they depend on
        the ellipse and mu0 (theta[0:4], theta[6]) only, so they are kept for the last few
        of those (``_UG_KEEP``): the Laplace step's differences in s_p, l_p, l_r reuse their
        centre's (U^T Gc U is half of an evaluation's time); Gc U (None in all but the last
        entry) is for the gradient."""
        key = (id(st), np.asarray(th, float)[[0, 1, 2, 3, 6]].tobytes())
        hit = self._ug.get(key)
        if hit is not None:
            return hit
        U, act, nodes = self.U(th)
        gkey = (id(st), act.tobytes())
        Gc = self._gsub.get(gkey)
        if Gc is None:  # the active cells change only when the ellipse crosses a cell
            Gc = self._gram(st["kern"], act)
            self._gsub = {gkey: Gc}
        GU = (U.T @ Gc).T          # Gc U (Gc symmetric)
        G = np.asarray(U.T @ GU)
        G = 0.5 * (G + G.T)
        v = U.T @ st["bw"][self._rows(act)]
        if len(self._ug) >= _UG_KEEP:
            self._ug.pop(next(iter(self._ug)))
        for k, old in self._ug.items():  # Gc U (3 n_a x ~350, ~8 MB) kept for the last only
            self._ug[k] = old[:5] + (None,)
        self._ug[key] = out = (U, act, nodes, G, v, GU)
        return out

    def _core(self, th, s_out):
        st = self._stationary(s_out)
        U, act, nodes, G, v, _ = self._projected(th, st)
        parts = self.Lchol(th, nodes, blocks=True)
        from scipy.linalg import block_diag

        L = block_diag(*parts)
        # L^T G L block by block (L is block diagonal)
        cuts = np.cumsum([0] + [q.shape[0] for q in parts])
        B = np.empty_like(G)
        for i, Li in enumerate(parts):
            GiL = [G[cuts[i]:cuts[i + 1], cuts[j]:cuts[j + 1]] @ Lj for j, Lj in enumerate(parts)]
            for j in range(len(parts)):
                B[cuts[i]:cuts[i + 1], cuts[j]:cuts[j + 1]] = Li.T @ GiL[j]
        B[np.diag_indices_from(B)] += 1.0
        cB = np.linalg.cholesky(B)
        t = np.linalg.solve(cB, L.T @ v)
        return st, (U, act), L, cB, v, t

    def evidence(self, th, s_out, grad=False):
        """The log-evidence at theta (nugget sd s_out fixed) [, its gradient in theta (8,)]
        (-1e300 [, zeros] where B is not positive definite)."""
        try:
            st, U, L, cB, v, t = self._core(th, s_out)
        except np.linalg.LinAlgError:
            return (-1e300, np.zeros(len(th))) if grad else -1e300
        quad = st["quad"] - float(t @ t)
        logdet = st["logdet"] + 2.0 * float(np.sum(np.log(np.diag(cB))))
        value = -0.5 * (quad + logdet) - 1.5 * self.N * math.log(2 * math.pi)
        if not grad:
            return value
        return value, self._gradient(th, s_out, L, cB, t)

    def _gradient(self, th, s_out, L, cB, t):
        """d log-evidence / d theta from the Woodbury form (module docstring, Gradient)."""
        from scipy.linalg import solve_triangular

        st = self._stationary(s_out)
        U, act, nodes, G, v, GU = self._projected(th, st)
        if GU is None:
            GU = (U.T @ self._gram(st["kern"], act)).T
        F = L @ solve_triangular(cB.T, np.eye(cB.shape[0]), lower=False)
        Sig = F @ F.T                          # posterior covariance of the unknowns
        m = F @ t                              # their posterior mean, Sig v
        g = np.zeros(len(th))
        # the prior's covariance K (s_p, l_p, l_r): 0.5 (a^T dK a - tr(W dK))
        a = v - G @ m
        W = G - G @ Sig @ G
        s = math.exp(th[4])
        mn = nodes.size
        d = self.dist[np.ix_(nodes, nodes)]
        K = L @ L.T
        g[4] = 0.5 * (a @ (2.0 * K) @ a - float(np.sum(W * (2.0 * K))))
        for k, blocks in ((5, (0,)), (7, (1, 2))):
            r = math.sqrt(5.0) * d / math.exp(th[k])
            dC = s * s * (r * r / 3.0) * (1.0 + r) * np.exp(-r)   # d K_block / d log l
            for b in blocks:
                sl = slice(b * mn, (b + 1) * mn)
                ab = a[sl]
                g[k] += 0.5 * (ab @ dC @ ab - float(np.sum(W[sl, sl] * dC)))
        # U (the ellipse and mu0): d log Z = <dU, R>, R = b m^T - Gc U (m m^T + Sig)
        n = act.size
        R = np.outer(st["bw"][self._rows(act)], m) - GU @ (np.outer(m, m) + Sig)
        Rp, Rx, Ry = R[:n], R[n:2 * n], R[2 * n:]
        P = self.P[act][:, nodes]
        ex, ey = self.e
        w, _, _, dw, dind = self.window(th, deriv=True)
        gp, gx, gy = slice(0, mn), slice(mn, 2 * mn), slice(2 * mn, 3 * mn)
        mixed = ex * Rx[:, gp] + ey * Ry[:, gp]
        Dw = np.asarray(P.multiply(Rp[:, gp] + th[6] * mixed + Rx[:, gx] + Ry[:, gy])
                        .sum(axis=1)).ravel()
        Dind = Rx[:, 3 * mn] + Ry[:, 3 * mn + 1]
        g[:4] = dw @ Dw + dind @ Dind
        g[6] = float(w[act] @ np.asarray(P.multiply(mixed).sum(axis=1)).ravel())
        return g

    # -- the posterior -------------------------------------------------------------------------
    def _embed(self, cols, act):
        """Dense (3, nx, ny, k) maps of the columns (3 n_a, k) given on the active cells."""
        n = act.size
        out = np.zeros((3,) + self.shape + (cols.shape[1],))
        ci, cj = self.cells[act, 0], self.cells[act, 1]
        for f in range(3):
            out[f, ci, cj] = cols[f * n:(f + 1) * n]
        return out

    def posterior(self, th, s_out, margin=3.0, chunk=48):
        """Mean (3, nx, ny), pointwise variance (3, nx, ny) and the pieces of the covariance
        Cov = C0 (*) + Z Z^T: C0 per mode (kshape, 3, 3); Z on a box of the grid (the ellipse's
        reach and ``margin`` h around it; index arrays ``box``), (3, bx, by, r), and Z's sums over
        the whole grid (3, r) for the totals.  Outside the box the window's part of the
        variance is still summed (from the full transforms), only Z is not kept."""
        st, (U, act), L, cB, v, t = self._core(th, s_out)
        from scipy.linalg import solve_triangular

        g = L @ solve_triangular(cB.T, t, lower=False)
        Kn, Si = st["Kn"], st["Si"]
        s2 = s_out**2
        # mean: U g + R0 (y - M U g)
        Ug = self._embed(np.asarray(U @ g)[:, None], act)[..., 0]
        Ugk = np.moveaxis(np.fft.rfft2(Ug, axes=(1, 2)), 0, -1)
        r = self.Y - np.einsum("...ij,...j->...i", self.M, Ugk)
        corr = s2 * np.einsum("...ki,...kl,...l->...i", self.M.conj(), Si, r)
        mean = Ug + np.fft.irfft2(np.moveaxis(corr, -1, 0), s=self.shape, axes=(1, 2))
        # covariance: C0 + T U Sigma_g U^T T^T, Sigma_g = F F^T, F = L chol(B)^-T
        T = np.eye(3) - s2 * Kn
        C0 = s2 * T
        C0 = 0.5 * (C0 + np.swapaxes(C0.conj(), -1, -2))
        F = L @ solve_triangular(cB.T, np.eye(cB.shape[0]), lower=False)
        UF = np.asarray(U @ F)
        nr = UF.shape[1]
        nx, ny = self.shape
        dx, dy = self.steps
        ci, cj = self.cells[act, 0], self.cells[act, 1]
        mx, my = int(math.ceil(margin / dx)), int(math.ceil(margin / dy))
        bx = np.arange(ci.min() - mx, ci.max() + mx + 1)
        by = np.arange(cj.min() - my, cj.max() + my + 1)
        bx = np.unique(bx % nx) if bx.size >= nx else bx % nx
        by = np.unique(by % ny) if by.size >= ny else by % ny
        Z = np.empty((3, bx.size, by.size, nr))
        var = np.zeros((3, nx, ny))
        n = act.size
        Zsum = np.empty((3, nr))
        T0 = T[0, 0].real
        for j0 in range(0, nr, chunk):
            cols = UF[:, j0:j0 + chunk]
            blk = self._embed(cols, act)                                 # (3, nx, ny, k)
            bk = np.fft.rfft2(blk, axes=(1, 2))
            tk = np.einsum("xyij,jxyc->ixyc", T, bk)
            z = np.fft.irfft2(tk, s=self.shape, axes=(1, 2))
            var += np.einsum("fxyc,fxyc->fxy", z, z)
            Z[..., j0:j0 + chunk] = z[:, bx][:, :, by]
            sums = np.stack([cols[f * n:(f + 1) * n].sum(0) for f in range(3)])
            Zsum[:, j0:j0 + chunk] = T0 @ sums
        w = self.w
        var0 = np.array([float(np.sum(w * C0[..., i, i].real)) / self.N for i in range(3)])
        var += var0[:, None, None]
        return mean, var, C0, Z, (bx, by), Zsum

    def mean_of(self, th, s_out, Yk):
        """The posterior mean (3, nx, ny) of data with spectrum Yk (for the resolution
        operator): linear in the data."""
        st = self._stationary(s_out)
        _, (U, act), L, cB, _, _ = self._core(th, s_out)
        from scipy.linalg import solve_triangular

        Si = st["Si"]
        a = np.einsum("...ij,...j->...i", Si, Yk)
        bk = np.einsum("...ki,...k->...i", self.M.conj(), a)
        b = np.fft.irfft2(np.moveaxis(bk, -1, 0), s=self.shape, axes=(1, 2))
        ci, cj = self.cells[act, 0], self.cells[act, 1]
        v = U.T @ np.concatenate([b[f][ci, cj] for f in range(3)])
        g = L @ solve_triangular(cB.T, np.linalg.solve(cB, L.T @ v), lower=False)
        Ug = self._embed(np.asarray(U @ g)[:, None], act)[..., 0]
        Ugk = np.moveaxis(np.fft.rfft2(Ug, axes=(1, 2)), 0, -1)
        r = Yk - np.einsum("...ij,...j->...i", self.M, Ugk)
        corr = s_out**2 * np.einsum("...ki,...kl,...l->...i", self.M.conj(), Si, r)
        return Ug + np.fft.irfft2(np.moveaxis(corr, -1, 0), s=self.shape, axes=(1, 2))


def _maximise(prior, th0, s_out, lo, hi):
    """L-BFGS-B with the analytic gradient from th0 at the nugget s_out; stops when the
    projected gradient is below ``OPT_GTOL`` (or after ``OPT_MAXITER`` iterations).  Returns
    (theta, log-evidence, gradient, iterations, L-BFGS-B's message) of the best point
    evaluated."""
    from scipy.optimize import minimize

    best = [th0, -np.inf, np.zeros(len(th0))]

    def f(z):
        v, g = prior.evidence(z, s_out, grad=True)
        if not v > -1e299:
            return 1e300, np.zeros(z.size)
        if v > best[1]:
            best[:] = [z.copy(), v, g]
        return -v, -g

    res = minimize(f, th0, jac=True, method="L-BFGS-B", bounds=list(zip(lo, hi)),
                   options={"maxiter": OPT_MAXITER, "ftol": OPT_FTOL, "gtol": OPT_GTOL,
                            "maxls": 40})
    return best[0], best[1], best[2], int(res.nit), str(res.message)


def fit_contact(M, Y, shape, steps, noise, e, p_start, s_out0, mu_start, progress=None,
                start=None):
    """Maximise the contact prior's evidence (module docstring).  p_start: a pressure estimate
    (scaled) for the starting ellipse; s_out0: the starting nugget sd; mu_start: Q/P; start:
    None, or a theta to start from instead of the default (clipped to the search's bounds).
    Alternates a maximisation over theta (``_maximise``) with the nugget's choice at its end
    point until the nugget stays (at most ``NUGGET_ROUNDS`` rounds).  Returns (prior, theta,
    s_out, log_evidence, fit) with fit = {iterations, gradient_norm (the projected gradient's
    largest component at theta), gradient (8,: the projected one), rounds, nugget_settled,
    message (L-BFGS-B's last), converged: the gradient norm at most ``OPT_GTOL`` and the
    nugget settled (``remaining_step`` gives the rule the result reports)}."""
    say = progress or (lambda s: None)
    geom = start_geometry(p_start, steps)
    cx, cy, ax, ay = geom
    prior = ContactMapPrior(M, Y, shape, steps, noise, e, geom)
    lo, hi = _bounds(geom, float(np.max(p_start)), max(steps), mu_start)
    th = np.array([cx, cy, math.log(ax), math.log(ay), math.log(float(np.max(p_start))),
                   math.log(0.7 * ax), mu_start, math.log(0.7 * ax)])
    if start is not None:
        th = np.clip(np.asarray(start, float), lo, hi)
    s_out = s_out0
    iters, settled = 0, False
    for rnd in range(NUGGET_ROUNDS):
        say(f"contact prior: evidence over the ellipse and the fields (round {rnd + 1})")
        th, value, grad, nit, message = _maximise(prior, th, s_out, lo, hi)
        iters += nit
        say(f"contact prior: round {rnd + 1}: {nit} iterations, {message}")
        say("contact prior: evidence over the nugget")
        cands = [s_out0 * 10.0 ** (-k) for k in range(NUGGET_DECADES)]
        evs = [prior.evidence(th, s) for s in cands]
        s_new = cands[int(np.argmax(evs))]
        if s_new == s_out:
            settled = True
            break
        if rnd + 1 < NUGGET_ROUNDS:
            s_out = s_new   # else theta stays fitted at s_out: reported as not converged
    if not value > -1e299:
        raise np.linalg.LinAlgError("the contact prior's evidence could not be evaluated")
    pg = np.clip(th + grad, lo, hi) - th
    gnorm = float(np.max(np.abs(pg)))
    fit = {"iterations": iters, "rounds": rnd + 1, "gradient_norm": gnorm,
           "gradient": pg, "nugget_settled": settled, "message": message,
           "converged": bool(settled and gnorm <= OPT_GTOL)}
    return prior, th, s_out, value, fit


def _bounds(geom, pk, dmin, mu_start):
    """The search box of theta around the starting ellipse (cx, cy, ax, ay), the pressure
    estimate's peak pk and Q/P."""
    cx, cy, ax, ay = geom
    lo = np.array([cx - 0.3 * ax, cy - 0.3 * ay, math.log(max(0.5 * ax, 2 * dmin)),
                   math.log(max(0.5 * ay, 2 * dmin)), math.log(1e-3 * pk),
                   math.log(max(0.3 * ax, 2 * dmin)), mu_start - 3.0,
                   math.log(max(0.3 * ax, 2 * dmin))])
    lp_max = min(20.0, LP_MAX_WIDTH * 0.5 * (ax + ay))
    lr_max = min(20.0, LR_MAX_WIDTH * 0.5 * (ax + ay))
    hi = np.array([cx + 0.3 * ax, cy + 0.3 * ay, math.log(1.2 * ax), math.log(1.2 * ay),
                   math.log(1e2 * pk), math.log(lp_max), mu_start + 3.0, math.log(lr_max)])
    return lo, hi


LAPLACE_STEPS = (0.01, 0.01, 0.005, 0.005, 0.02, 0.05, 0.02, 0.05)
"""Difference steps of the hyperparameters (c_x, c_y [h]; the others in log or plain units)
for the Hessian of the log-evidence and the Jacobian of the mean."""
MIN_CURVATURE = 1.0
"""Directions of the hyperparameters where the log-evidence curves less than this (its width
above 1 unit: a length the data hardly constrain) are given this curvature."""


def propagate(prior, th, s_out):
    """The hyperparameters' uncertainty (Laplace, flat prior on theta): Sigma_theta = (-H)^-1
    from central differences of the log-evidence, and J = d mean / d theta (central
    differences of the posterior mean, scaled units, (3, nx, ny, 8)).  The tractions'
    covariance gains J Sigma_theta J^T.  Returns (J, Sigma_theta, sd_theta)."""
    n = len(th)
    hs = np.asarray(LAPLACE_STEPS, float)
    f0 = prior.evidence(th, s_out)
    E = np.eye(n) * hs
    fp = np.array([prior.evidence(th + E[i], s_out) for i in range(n)])
    fm = np.array([prior.evidence(th - E[i], s_out) for i in range(n)])
    H = np.diag((fp - 2.0 * f0 + fm) / hs**2)
    for i in range(n):
        for j in range(i):
            fpp = prior.evidence(th + E[i] + E[j], s_out)
            H[i, j] = H[j, i] = (fpp - fp[i] - fp[j] + f0) / (hs[i] * hs[j])
    w, V = np.linalg.eigh(-0.5 * (H + H.T))
    Sig = (V / np.maximum(w, MIN_CURVATURE)) @ V.T
    J = np.stack([(prior.mean_of(th + E[i], s_out, prior.Y)
                   - prior.mean_of(th - E[i], s_out, prior.Y)) / (2.0 * hs[i])
                  for i in range(n)], -1)
    return J, Sig, np.sqrt(np.diag(Sig))


def remaining_step(fit, Sig, sd):
    """The largest |(Sigma_theta g)_i| / sd_i at the fit's end point (``CONVERGED_STEP_SD``),
    and whether the fit converged by that rule."""
    step = float(np.max(np.abs(Sig @ fit["gradient"]) / sd))
    return step, bool(fit["nugget_settled"] and step <= CONVERGED_STEP_SD)
