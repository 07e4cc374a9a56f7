"""Restarted GMRES with right preconditioning (true residual is what is monitored)."""
from __future__ import annotations

import numpy as np

__all__ = ["gmres"]


def gmres(matvec, psolve, b, x0, rtol=1e-10, restart=60, maxiter=600):
    """Solve A x = b, A given by ``matvec``, right preconditioner ``psolve`` ~ A^-1.

    Returns (x, iterations, relative residual).  Stops when ||b - A x|| <= rtol ||b|| or after
    ``maxiter`` matrix-vector products.
    """
    n = b.size
    x = x0.copy()
    bnorm = np.linalg.norm(b) or 1.0
    r = b - matvec(x)
    beta = np.linalg.norm(r)
    its = 0
    while beta > rtol * bnorm and its < maxiter:
        m = min(restart, maxiter - its)
        V = np.empty((m + 1, n))
        Z = np.empty((m, n))
        Hh = np.zeros((m + 1, m))
        cs = np.zeros(m)
        sn = np.zeros(m)
        g = np.zeros(m + 1)
        g[0] = beta
        V[0] = r / beta
        j_done = 0
        for j in range(m):
            Z[j] = psolve(V[j])
            w = matvec(Z[j])
            its += 1
            # classical Gram-Schmidt, twice (as stable as modified, but vectorised)
            h = V[: j + 1] @ w
            w -= h @ V[: j + 1]
            h2 = V[: j + 1] @ w
            w -= h2 @ V[: j + 1]
            Hh[: j + 1, j] = h + h2
            Hh[j + 1, j] = np.sqrt(w @ w)
            if Hh[j + 1, j] > 0:
                V[j + 1] = w / Hh[j + 1, j]
            for i in range(j):  # previous Givens rotations
                t = cs[i] * Hh[i, j] + sn[i] * Hh[i + 1, j]
                Hh[i + 1, j] = -sn[i] * Hh[i, j] + cs[i] * Hh[i + 1, j]
                Hh[i, j] = t
            den = np.hypot(Hh[j, j], Hh[j + 1, j])
            cs[j], sn[j] = (1.0, 0.0) if den == 0 else (Hh[j, j] / den, Hh[j + 1, j] / den)
            Hh[j, j] = den
            Hh[j + 1, j] = 0.0
            g[j + 1] = -sn[j] * g[j]
            g[j] = cs[j] * g[j]
            j_done = j + 1
            if abs(g[j + 1]) <= rtol * bnorm or Hh[j, j] == 0:
                break
        y = np.linalg.solve(np.triu(Hh[:j_done, :j_done]), g[:j_done]) if j_done else np.zeros(0)
        x += y @ Z[:j_done]
        r = b - matvec(x)
        beta = np.linalg.norm(r)
    return x, its, beta / bnorm
