"""Restarted GMRES with right preconditioning (true residual is what is monitored).

The loop is written for the contact solver's many small solves (a few hundred to a few
thousand unknowns, ~10 iterations each), where Python bookkeeping, not arithmetic, dominated:

* the Krylov bases V (m + 1 rows) and Z = M^-1 V (m rows) live in one flat buffer per thread,
  reused by later calls (kept only while it holds <= ``_KEEP_FLOATS`` numbers: larger systems
  allocate per call, which costs nothing next to their transforms);
* classical Gram-Schmidt twice, vectorised (two matrix-vector products per pass);
* the Hessenberg columns, the Givens rotations and the back substitution use plain Python
  floats (the same IEEE operations, in the same order, as on numpy scalars).

The iterates are those of the textbook algorithm (Saad, Iterative Methods, alg. 6.9 with right
preconditioning): only the order of a few round-off-level operations differs from a numpy
formulation.
"""
from __future__ import annotations

import math
import threading

import numpy as np

__all__ = ["gmres"]

_KEEP_FLOATS = 2**22  # buffers up to 32 MB are kept for the next call (per thread)
_local = threading.local()


def _bases(m: int, n: int):
    """Views V (m + 1, n) and Z (m, n) on this thread's buffer (fresh arrays when it is busy,
    i.e. a re-entrant call, or when the system is too large to keep)."""
    need = (2 * m + 1) * n
    buf = getattr(_local, "buf", None)
    if getattr(_local, "busy", False) or need > _KEEP_FLOATS:
        buf = np.empty(need)
    elif buf is None or buf.size < need:
        # a little slack: the active set (hence n) grows by a few nodes between solves
        buf = _local.buf = np.empty(min(_KEEP_FLOATS, need + need // 4))
    return buf[: (m + 1) * n].reshape(m + 1, n), buf[(m + 1) * n: need].reshape(m, n)


def gmres(matvec, psolve, b, x0, rtol=1e-10, restart=60, maxiter=600, step=None):
    """Solve A x = b, A given by ``matvec``, right preconditioner ``psolve`` ~ A^-1.

    Returns (x, iterations, relative residual).  Stops when ||b - A x|| <= rtol ||b|| or after
    ``maxiter`` matrix-vector products.  ``matvec`` and ``psolve`` must not keep the vectors
    they are given (they are rows of a reused buffer).  ``step(v, z)``, optional, does one
    iteration's two products at once: z[:] = M^-1 v, returns A z (an array GMRES may overwrite
    and that ``step`` may reuse at its next call); the last call of ``matvec`` is always at
    the x returned.
    """
    n = b.size
    x = x0.copy()
    bnorm = math.sqrt(float(b @ b)) or 1.0
    tol = rtol * bnorm
    r = b - matvec(x)
    beta = math.sqrt(float(r @ r))
    its = 0
    busy = getattr(_local, "busy", False)
    try:
        while beta > tol and its < maxiter:
            m = min(restart, maxiter - its)
            V, Z = _bases(m, n)
            _local.busy = True
            R = []        # columns of the rotated (upper triangular) Hessenberg matrix
            cs = []
            sn = []
            g = [beta]
            np.divide(r, beta, out=V[0])
            for j in range(m):
                if step is None:
                    Z[j] = psolve(V[j])
                    w = matvec(Z[j])
                else:
                    w = step(V[j], Z[j])
                its += 1
                # classical Gram-Schmidt, twice (as stable as modified, but vectorised)
                Vj = V[: j + 1]
                h = Vj @ w
                w -= h @ Vj
                h2 = Vj @ w
                w -= h2 @ Vj
                col = (h + h2).tolist()
                hn = math.sqrt(float(w @ w))
                if hn > 0:
                    np.divide(w, hn, out=V[j + 1])
                for i in range(j):  # previous Givens rotations
                    c, s = cs[i], sn[i]
                    a, e = col[i], col[i + 1]
                    col[i] = c * a + s * e
                    col[i + 1] = -s * a + c * e
                a = col[j]
                den = float(np.hypot(a, hn))
                if den == 0:
                    c, s = 1.0, 0.0
                else:
                    c, s = a / den, hn / den
                cs.append(c)
                sn.append(s)
                col[j] = den
                R.append(col)
                gj = g[j]
                g.append(-s * gj)
                g[j] = c * gj
                if abs(g[j + 1]) <= tol or den == 0:
                    break
            # back substitution R y = g (column by column, as LAPACK's trsv)
            k_done = len(R)
            y = g[:k_done]
            for k in range(k_done - 1, -1, -1):
                colk = R[k]
                if colk[k] == 0:  # A singular on the Krylov space (as numpy's solve says)
                    raise np.linalg.LinAlgError("Singular matrix")
                yk = y[k] = y[k] / colk[k]
                for i in range(k):
                    y[i] -= yk * colk[i]
            if k_done:
                x += np.asarray(y) @ Z[:k_done]
            _local.busy = busy
            r = b - matvec(x)
            beta = math.sqrt(float(r @ r))
    finally:
        _local.busy = busy
    return x, its, beta / bnorm
