"""Contact through an exponential interface law (a rough skin): p = p0 exp(-g / lambda) for the
interface gap g = f - d + w (issue 14, ``--interface-law exponential``).

Dimensionless (the core's units: p0 in G h/2R, lambda and g in h^2/2R).  The law has no contact
set: the pressure is positive everywhere and falls off like exp(-x^2/lambda) outside the region
where the surfaces close; there is no complementarity left, only the nonlinear system

    R = f - d + H p + lambda ln(p / p0) = 0   at every node,      cell * sum p = P,

solved by Newton's method in u = ln p (p stays positive): each step solves
(H + diag(lambda / p)) dp - dd = -R with the load row by right-preconditioned GMRES.  The
preconditioner is the contact solver's (the inverse symbol of H clipped below pi/W) on the
nodes where the operator H dominates (lambda/p below the symbol's scale at the contact's width)
and the diagonal lambda/p elsewhere.  Steps are damped (at most one unit of ln p on the nodes
that carry the load, backtracking on the residual); nodes whose pressure is negligible are
reset to the law's value of their gap after each step (they do not move the surface).
Converged when the largest of |R| / (scale of f - d + w) and the load error is below ``rtol``.
A stiff law (small lambda) that Newton does not settle from the first guess is reached by
continuation: lambda x 10, x 100, ... solved first, each from the softer one's pressure.
"""
from __future__ import annotations

import numpy as np

from ..errors import ConvergenceError
from .contact import ContactSolution, compliance_operator
from .grid import Grid
from .krylov import gmres

__all__ = ["solve_exponential_contact"]

_NEGLIGIBLE = 1e-12  # pressure fraction of p_max below which a node is reset to its law value


def solve_exponential_contact(grid: Grid, mu: float, indenter, p0: float, lam: float, *,
                              film=None, p_init=None, rtol: float = 1e-9,
                              max_newton: int = 100, continuation: int = 4) -> ContactSolution:
    """See ``_newton``; if Newton does not settle, continuation in lambda: solve at 10 lambda
    (recursively, up to ``continuation`` decades) and restart from that pressure."""
    try:
        return _newton(grid, mu, indenter, p0, lam, film=film, p_init=p_init, rtol=rtol,
                       max_newton=max_newton)
    except ConvergenceError:
        if continuation <= 0:
            raise
    softer = solve_exponential_contact(grid, mu, indenter, p0, 10.0 * lam, film=film,
                                       p_init=p_init, rtol=max(rtol, 1e-6), max_newton=max_newton,
                                       continuation=continuation - 1)
    return _newton(grid, mu, indenter, p0, lam, film=film, p_init=softer.pressure, rtol=rtol,
                   max_newton=max_newton)


class _Law:
    """The exponential interface problem on a grid: the heights ``f``, the load ``P``, the
    cell, the film's operator (``H``: FFT pairs counted), the law's p0 and lambda."""

    def __init__(self, grid: Grid, mu: float, indenter, p0: float, lam: float, film):
        from ..physics.film import Film

        film = film or Film()
        self.op = compliance_operator(grid.shape, grid.lengths, float(mu), film)
        self.grid, self.shape, self.cell = grid, grid.shape, grid.cell
        self.f = np.broadcast_to(ind_height(indenter, grid), self.shape).ravel()
        self.P = float(indenter.load)
        self.p0, self.lam = p0, lam
        self.fft = 0

    def H(self, v):
        self.fft += 1
        return self.op.apply(v.reshape(self.shape)).ravel()

    def residual(self, p, d):
        """(R, w, scale): the law's residual at every node, the sinking, and the scale of the
        interface gap on the nodes that carry the load."""
        w = self.H(p)
        f = self.f
        R = f - d + w + self.lam * np.log(p / self.p0)
        scale = max(np.max(np.abs(f - d + w)[p > _NEGLIGIBLE * p.max()]), self.lam, 1e-300)
        return R, w, scale

    def first_guess(self, indenter, p_init):
        """(p, d): the given pressure (else the indenter's) carrying the load, d from the law at
        its most loaded node, and the law's value of their gap at the nodes it leaves empty."""
        f, P, p0, lam = self.f, self.P, self.p0, self.lam
        p = np.asarray(indenter.initial_pressure(self.grid) if p_init is None else p_init,
                       dtype=float).ravel().copy()
        p = np.broadcast_to(p, f.shape).copy()
        if not np.any(p > 0):
            raise ValueError("first pressure guess is zero everywhere")
        p *= P / (self.cell * p.sum())
        w = self.H(p)
        inside = p > 0
        j = int(np.argmax(p))
        d = f[j] + w[j] + lam * np.log(p[j] / p0)
        g = f - d + w
        p = np.where(inside, p, p0 * np.exp(-np.clip(g / lam, -700, 700)))
        return np.maximum(p, 1e-300), d

    def direction(self, p, R, err, pmax):
        """Newton's step on the nodes that carry load (``idx``): (H + diag(lambda/p)) dp - dd =
        -R with the load row, by GMRES preconditioned by the inverse symbol where H dominates
        and by the diagonal elsewhere.  (idx, du = dp/p, dd, GMRES iterations)."""
        op, shape, cell, f, P = self.op, self.shape, self.cell, self.f, self.P
        H = self.H
        c = self.lam / p
        sig = p > _NEGLIGIBLE * pmax
        idx = np.flatnonzero(sig)
        ni = idx.size
        # operator-dominated nodes: lambda/p below the symbol at the loaded region's width
        width = max(ni * cell, 4 * cell) ** (1.0 / self.grid.ndim)
        k_c = np.pi / width
        Hinv = op.preconditioner(k_c)
        h_scale = 1.0 / np.max(np.abs(Hinv))  # the symbol's smallest magnitude kept
        dominated = c[idx] < h_scale
        buf = np.zeros(f.size)

        def matvec(v, idx=idx, c=c, ni=ni):
            buf[:] = 0.0
            buf[idx] = v[:ni]
            out = np.empty_like(v)
            out[:ni] = H(buf)[idx] + c[idx] * v[:ni] - v[ni]
            out[ni] = cell * v[:ni].sum() * wload
            return out

        def psolve(r, idx=idx, c=c, ni=ni, dominated=dominated, Hinv=Hinv):
            self.fft += 1
            buf[:] = 0.0
            sel = idx[dominated]
            buf[sel] = r[:ni][dominated]
            z = np.empty_like(r)
            z[:ni] = r[:ni] / c[idx]
            z[:ni][dominated] = op.apply_symbol(buf.reshape(shape), Hinv).ravel()[sel]
            z[ni] = r[ni]
            return z

        wload = max(np.linalg.norm(R[idx]), 1e-300) / P
        b = np.concatenate([-R[idx], [-(cell * p.sum() - P) * wload]])
        v, its, _ = gmres(matvec, psolve, b, np.zeros(ni + 1), rtol=1e-3 * min(1.0, err) + 1e-12,
                          maxiter=400)
        return idx, v[:ni] / p[idx], v[ni], its

    def backtrack(self, p, d, idx, du, dd, err, pmax):
        """The damped step: one unit of ln p at most on the nodes that carry the load (p >
        p_max/e^3), each lightly loaded node clipped to two units on its own (they barely move
        w), halved until the residual's max-norm falls; negligible nodes reset to the law's
        value of their gap.  (p, d, R, w, scale) of the new state, or None."""
        f, P, cell, p0, lam = self.f, self.P, self.cell, self.p0, self.lam
        loaded = p[idx] > pmax * np.exp(-3.0)
        step = min(1.0, 1.0 / max(np.max(np.abs(du[loaded])), 1e-300))
        du = np.clip(du, -2.0 / step, 2.0 / step)
        for _ in range(30):  # backtracking on the residual's max-norm
            pn = p.copy()
            pn[idx] = p[idx] * np.exp(step * du)
            dn = d + step * dd
            Rn, wn, sn = self.residual(pn, dn)
            gn = f - dn + wn
            neg = pn <= _NEGLIGIBLE * pn.max()
            pn[neg] = np.maximum(p0 * np.exp(-np.clip(gn[neg] / lam, -700, 700)), 1e-300)
            if neg.any():
                Rn, wn, sn = self.residual(pn, dn)
            en = max(np.max(np.abs(Rn[pn > _NEGLIGIBLE * pn.max()])) / sn,
                     abs(cell * pn.sum() - P) / P)
            if en < err or step < 1e-6:
                return pn, dn, Rn, wn, sn
            step *= 0.5
        return None


def _newton(grid: Grid, mu: float, indenter, p0: float, lam: float, *,
            film=None, p_init=None, rtol: float = 1e-9, max_newton: int = 100) -> ContactSolution:
    """Contact of one indenter (``physics.indenters``) on ``film`` through the interface law
    p = p0 exp(-g / lam).  Returns a ``ContactSolution`` whose ``gap`` is the interface gap g,
    ``active`` marks the nodes where p > p_max exp(-3) (the region the law has closed to within
    3 lambda of its tightest) and ``indentations`` holds d."""
    law = _Law(grid, mu, indenter, p0, lam, film)
    shape, cell, f, P = law.shape, law.cell, law.f, law.P
    p, d = law.first_guess(indenter, p_init)
    krylov = 0
    history = []
    R, w, scale = law.residual(p, d)
    for it in range(1, max_newton + 1):  # noqa: B007 (reported after the loop)
        pmax = p.max()
        load_err = (cell * p.sum() - P) / P
        err = max(np.max(np.abs(R[p > _NEGLIGIBLE * pmax])) / scale, abs(load_err))
        history.append(err)
        if err <= rtol:
            break
        idx, du, dd, its = law.direction(p, R, err, pmax)
        krylov += its
        new = law.backtrack(p, d, idx, du, dd, err, pmax)
        if new is None:
            break
        p, d, R, w, scale = new
    else:
        it = max_newton
    if history[-1] > rtol:
        raise ConvergenceError(
            f"exponential interface: Newton stopped at relative residual {history[-1]:.1e} "
            f"after {it} iterations (a very stiff law, lambda << the film's sinking: use the "
            f"rigid or linear interface instead)", residuals=history, iterations=it)
    gap = f - d + w
    active = p > p.max() * np.exp(-3.0)
    owner = np.zeros(f.size, dtype=int)
    res = {"law": float(np.max(np.abs(R)) / scale), "load": float(abs(cell * p.sum() - P) / P)}
    return ContactSolution(grid, p.reshape(shape), w.reshape(shape), gap.reshape(shape),
                           active.reshape(shape), owner.reshape(shape), np.array([d]), it,
                           krylov, law.fft, float(history[-1]), res, history)


def ind_height(indenter, grid):
    return indenter.height(grid)
