"""Incremental Coulomb contact (partial slip) of a 3D indenter on the film: one load step on a
2D surface grid (dimensionless core), the surface form of ``numerics.partial_slip``.

Unknowns: the pressure p on the contact C, the shear vector q = (q_x, q_y) on the stick set S,
the indentation d and the indenter's tangential displacement (delta_x, delta_y).  The surface
moves by (u_x, u_y) and sinks by w through the film's 3 x 3 compliance
(``Film.surface_displacement_transfer``).  Conditions as in 1D, with vectors:

* stick: the slip increment s = (delta - delta_n) - (u - u_n) vanishes, |q| <= |mu| p;
* slip: q = |mu| p t with t the unit vector of s (the slip direction is solved, not assumed
  along Q).  For fixed sets the linear system holds q . t = |mu| p and the Newton
  linearisation of q = |mu| p s/|s| across t, (|s|/(|mu| p)) q_perp = s_perp (|s|, p of the
  last iteration; a node that has just begun to slip keeps s along t); t is then turned to
  q/|q| until the change this makes in q, |mu| p |dt|, is below ``dir_tol`` |mu| p_max
  (default: the accepted residual; a Newton iteration on the directions whose inner
  tolerance follows that change, rtol <= tolerance <= the search's);
* sum q = (Q_x, Q_y), sum p = P.

Set updates: a stick node whose |q| exceeds |mu| p slips along q/|q|; a slip node whose s
points against t (s . t < 0) sticks; a node coming into contact slips along its s.  Cycles are
handled as in 1D (full inner tolerance, then one change per iteration, then a one-node
boundary accepted with a friction-law violation <= 1e-2).  The preconditioner is the inverse
3 x 3 symbol clipped below k_c = pi / W (W the contact's width, sqrt of its area).
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import ConvergenceError
from ..physics.film import Film
from .grid import Grid
from .krylov import gmres
from .partial_slip import _MARGINAL, _SEARCH_RTOL, _SET_TOL, SlipState

__all__ = ["PartialSlipOperator2D", "solve_slip_step_2d", "SlipState2D"]

_DIR_TOL = 1e-6  # (the friction-law check accepts a direction residual of 1e3 x this)
_PLANS: dict = {}


class SlipState2D(SlipState):
    """``SlipState`` with vector shear and displacements: ``q``, ``u`` of shape (2, n),
    ``delta`` a length-2 array, ``t`` (2, n) the slip directions (0 off the slip set); the
    scalar ``sigma`` is unused (0)."""

    t: np.ndarray | None = None

    @staticmethod
    def unloaded(n: int) -> SlipState2D:
        z = np.zeros(n)
        b = np.zeros(n, dtype=bool)
        s = SlipState2D(z, np.zeros((2, n)), z.copy(), np.zeros((2, n)), 0.0, np.zeros(2), b,
                        b.copy(), np.zeros(n, dtype=np.int8), slip=np.zeros((2, n)))
        s.t = np.zeros((2, n))
        return s


def _plan(shape):
    """A batched real FFT of three fields on ``shape``: (real buffer (3, nx, ny), the forward
    transform's complex output (3, nx, ny/2 + 1), the backward transform's complex input (a
    second buffer: the symbol product is written into it without copies), forward, backward)."""
    import pyfftw

    from . import fft as _fft

    plan = _PLANS.get(shape)
    if plan is None:
        nx, ny = shape
        r = pyfftw.empty_aligned((3, nx, ny), dtype="float64")
        c = pyfftw.empty_aligned((3, nx, ny // 2 + 1), dtype="complex128")
        o = pyfftw.empty_aligned((3, nx, ny // 2 + 1), dtype="complex128")
        effort = _fft._PLANNER_EFFORT
        fwd = pyfftw.FFTW(r, c, axes=(-2, -1), direction="FFTW_FORWARD", flags=(effort,))
        bwd = pyfftw.FFTW(o, r, axes=(-2, -1), direction="FFTW_BACKWARD",
                          flags=(effort, "FFTW_DESTROY_INPUT"))
        plan = _PLANS[shape] = (r, c, o, fwd.execute, bwd.execute)
        if len(_PLANS) > 4:
            _PLANS.pop(next(iter(_PLANS)))
    return plan


def _pack(M, scale: float):
    """The 3 x 3 symbol ``M`` (nested tuples of complex arrays) in the form ``transform``
    applies: each entry is real or imaginary (the film's symbol: [[F, i B], [i B, T]], F, T
    real, the pressure-shear coupling imaginary; checked here), stored as a real array on
    interleaved (re, im) pairs, times ``scale`` (the inverse transform's 1/(nx ny)); an
    imaginary entry i b acts on the swapped pair (re, im) -> (-b im, b re)."""
    out = []
    for row in M:
        packed = []
        for m in row:
            m = np.asarray(m)
            re, im = np.abs(m.real).max(), np.abs(m.imag).max()
            if im <= 1e-13 * re or im == 0.0:
                packed.append((False, np.repeat((scale * m.real)[..., None], 2, axis=-1)))
            elif re <= 1e-13 * im:
                packed.append((True, np.stack([-scale * m.imag, scale * m.imag], axis=-1)))
            else:  # a general complex entry (not the film's): no packed form
                raise ValueError("partial slip: a symbol entry is neither real nor imaginary")
        out.append(tuple(packed))
    return tuple(out)


class PartialSlipOperator2D:
    """(p, q_x, q_y) -> (w, u_x, u_y) on a 2D periodic ``grid``: the 3 x 3 symbol, applied to
    three fields in one batched transform (three FFT pairs)."""

    def __init__(self, grid: Grid, film: Film | None = None):
        if grid.ndim != 2:
            raise ValueError("PartialSlipOperator2D needs a 2D grid")
        self.grid = grid
        self.film = film or Film()
        self._scale = 1.0 / grid.size
        self.M = _pack(self._symbols(grid.kmag), self._scale)
        self._pre: dict = {}
        self._plan = _plan(grid.shape)
        self._tmp = np.empty(grid.kshape + (2,))

    def _symbols(self, kmag):
        g = self.grid
        film = self.film
        one = np.ones(g.kshape)
        zero = np.zeros(g.kshape)

        def evaluate(n):
            cols = []
            for src in ((one, (zero, zero)), (zero, (one, zero)), (zero, (zero, one))):
                (ux, uy), w = film.surface_displacement_transfer(n, kmag, src[0], src[1])
                cols.append((w, ux, uy))
            return tuple(tuple(np.broadcast_to(cols[j][i], g.kshape).astype(complex)
                               for j in range(3)) for i in range(3))

        return g.alias_average(evaluate)  # M[i][j]: output i (w, ux, uy), input j (p, qx, qy)

    def transform(self, M):
        """The packed symbol ``M`` (``_pack``: ``self.M`` or a ``preconditioner``) applied to
        the plan's real buffer (filled by the caller, shape (3, nx, ny)); returns that buffer,
        overwritten by the result (valid until the next call).  Real arithmetic on the
        interleaved pairs: 9 products and 6 sums of real arrays per call."""
        r, c, o, fwd, bwd = self._plan
        fwd()
        X = c.view(np.float64).reshape(c.shape + (2,))
        Y = o.view(np.float64).reshape(o.shape + (2,))
        tmp = self._tmp
        for i in range(3):
            Oi = Y[i]
            for j in range(3):
                swap, S = M[i][j]
                xj = X[j][..., ::-1] if swap else X[j]
                if j == 0:
                    np.multiply(S, xj, out=Oi)
                else:
                    np.multiply(S, xj, out=tmp)
                    Oi += tmp
        bwd()
        return r

    def preconditioner(self, k_cut: float):
        P = self._pre.get(k_cut)
        if P is None:
            g = self.grid
            low = g.kmag < k_cut
            Mc = self._symbols(np.where(low, k_cut, g.kmag))
            A = np.empty(g.kshape + (3, 3), dtype=complex)
            for i in range(3):
                for j in range(3):
                    A[..., i, j] = Mc[i][j]
            inv = np.linalg.inv(A)
            P = _pack(tuple(tuple(inv[..., i, j] for j in range(3)) for i in range(3)),
                      self._scale)
            if len(self._pre) > 16:
                self._pre.clear()
            self._pre[k_cut] = P
        return P

    def self_compliance(self) -> float:
        """The tangential displacement of a node under a unit tangential force on it (the
        symbol's mean: the operator's diagonal), dimensionless."""
        if not hasattr(self, "_a0"):
            r = self._plan[0]
            r.fill(0.0)
            r[1, 0, 0] = 1.0
            self._a0 = float(self.transform(self.M)[1, 0, 0])
        return self._a0

    def apply(self, p, q):
        r = self._plan[0]
        shape = self.grid.shape
        r[0] = p.reshape(shape)
        r[1] = q[0].reshape(shape)
        r[2] = q[1].reshape(shape)
        out = self.transform(self.M)
        return out[0].ravel().copy(), np.stack([out[1].ravel(), out[2].ravel()])


def _unit(v):
    n = np.sqrt(v[0] ** 2 + v[1] ** 2)
    return v / np.where(n > 0, n, 1.0), n


def solve_slip_step_2d(op: PartialSlipOperator2D, f: np.ndarray, prev: SlipState2D, P: float,
                       Q, mu: float, *, guess: SlipState2D | None = None,
                       rtol: float = 1e-10, search_rtol: float | None = _SEARCH_RTOL,
                       accept: float = 1e-8, max_outer: int = 200, max_krylov: int = 2000,
                       dir_tol: float | None = None) -> SlipState2D:
    """One load step from ``prev`` to the normal load P and the tangential load Q = (Q_x, Q_y)
    (dimensionless forces), Coulomb coefficient |mu|; ``f`` the heights (flat, n = nx ny)."""
    grid = op.grid
    shape = grid.shape
    n = grid.size
    cell = grid.cell
    mu = abs(float(mu))
    Q = np.asarray(Q, dtype=float)
    g = guess or prev
    contact = g.contact.copy()
    if not contact.any():
        contact[int(np.argmin(f))] = True
    stick = g.stick & contact
    t = np.where(contact & ~stick, g.t, 0.0)
    tl, tn = _unit(t)
    slipping = contact & ~stick
    if np.any(slipping & (tn == 0)):  # no direction yet: along Q (or +x)
        q_dir = Q / np.hypot(*Q) if np.hypot(*Q) > 0 else np.array([1.0, 0.0])
        tl[:, slipping & (tn == 0)] = q_dir[:, None]
    t = np.where(slipping, tl, 0.0)
    if not stick.any():
        stick[np.flatnonzero(contact)[np.argmax(g.p[contact])]] = True
    p = np.where(contact, g.p, 0.0)
    q = np.where(contact, g.q, 0.0)
    d, delta = g.d, np.array(g.delta, dtype=float)
    u_prev, delta_prev = prev.u, np.asarray(prev.delta, dtype=float)
    counters = {"fft": 0, "krylov": 0}
    rbuf = op._plan[0]
    flat = rbuf.reshape(3, n)
    rt = max(rtol, search_rtol or rtol)
    dir_tol = accept if dir_tol is None else dir_tol
    seen = set()
    cautious = marginal = False
    cycles = 0
    result = None
    Qn = max(mu * P, 1e-300)
    # gross sliding (|Q| = mu P): the slip grows without bound, so its direction is Q's at
    # every slipping node (q = mu p Q/|Q|: the steady state); the kept stick node fixes delta
    Qmag = float(np.hypot(*Q))
    gross = Qmag >= mu * P * (1.0 - 1e-12)
    qdir = Q / Qmag if Qmag > 0 else np.array([1.0, 0.0])
    slip_mag = np.zeros(n)  # |s| of the last iteration
    a0 = op.self_compliance()
    for outer in range(1, max_outer + 1):  # noqa: B007 (the count is reported after the loop)
        C = np.flatnonzero(contact)
        S = np.flatnonzero(stick)
        Lm = contact & ~stick
        L = np.flatnonzero(Lm)
        nC, nS = C.size, S.size
        posL = np.searchsorted(C, L)
        tL = t[:, L]
        nL = L.size
        # the Newton linearisation of q = mu p s/|s| across t: q_perp = (mu p/|s|) s_perp,
        # written as (|s|/(mu p)) q_perp + t_perp . (u - delta) = t_perp . (u_n - delta_n), with
        # |s| and p of the last iteration (0 for a node that has just begun to slip: its slip
        # then stays along t for this solve)
        compl = np.where(p[L] > 0, slip_mag[L] / (mu * np.maximum(p[L], 1e-300)), 0.0)
        # the preconditioner of those rows: the operator's inverse, times a0/(a0 + compl)
        # (a0 the operator's diagonal: (A + D)^-1 ~ (1 + D/a0)^-1 A^-1 for a diagonal D;
        # compl is up to 5-20 x a0 on the slip zone: 22-34 -> ~11 GMRES iterations per solve)
        damp = a0 / (a0 + compl)
        rhs_gap = -f[C]
        gap_norm = max(math.sqrt(float(rhs_gap @ rhs_gap)), 1e-300)
        wP = gap_norm / P
        wQ = gap_norm / Qn
        Mi = op.preconditioner(math.pi / 2.0 ** (round(8.0 * math.log2(
            math.sqrt(max(nC, 1) * cell))) / 8.0))
        # unknowns: p on C, q_x and q_y on S, the shear across t on L (q = mu p t + r t_perp
        # there), then d, delta_x, delta_y; rows: gap on C, stick (x, y) on S, no slip across t
        # on L (t_perp . s = 0: the Newton linearisation of "s parallel to q"), the loads
        i_s, i_l, i_d = nC, nC + 2 * nS, nC + 2 * nS + nL

        def scatter(v):
            flat.fill(0.0)
            pv = v[:nC]
            flat[0, C] = pv
            flat[1, S] = v[i_s:i_s + nS]
            flat[2, S] = v[i_s + nS:i_l]
            if nL:
                pl = mu * pv[posL]
                r = v[i_l:i_d]
                flat[1, L] = tL[0] * pl - tL[1] * r
                flat[2, L] = tL[1] * pl + tL[0] * r
            return pv

        def matvec(v):
            counters["fft"] += 3
            pv = scatter(v)
            qs = (flat[1].sum(), flat[2].sum())
            out = op.transform(op.M).reshape(3, n)
            last[0] = out
            res = np.empty_like(v)
            res[:nC] = out[0, C] - v[i_d]
            res[i_s:i_s + nS] = out[1, S] - v[i_d + 1]
            res[i_s + nS:i_l] = out[2, S] - v[i_d + 2]
            if nL and gross:
                res[i_l:i_d] = v[i_l:i_d]
            elif nL:
                res[i_l:i_d] = (-tL[1] * (out[1, L] - v[i_d + 1])
                                + tL[0] * (out[2, L] - v[i_d + 2]) + compl * v[i_l:i_d])
            res[i_d] = wP * cell * pv.sum()
            res[i_d + 1] = wQ * cell * qs[0]
            res[i_d + 2] = wQ * cell * qs[1]
            return res

        def psolve(r):
            counters["fft"] += 3
            flat.fill(0.0)
            flat[0, C] = r[:nC]
            flat[1, S] = r[i_s:i_s + nS]
            flat[2, S] = r[i_s + nS:i_l]
            if nL:
                flat[1, L] = -tL[1] * r[i_l:i_d]
                flat[2, L] = tL[0] * r[i_l:i_d]
            out = op.transform(Mi).reshape(3, n)
            z = np.empty_like(r)
            z[:nC] = out[0, C]
            z[i_s:i_s + nS] = out[1, S]
            z[i_s + nS:i_l] = out[2, S]
            if nL:
                z[i_l:i_d] = r[i_l:i_d] if gross else \
                    (-tL[1] * out[1, L] + tL[0] * out[2, L]) * damp
            z[i_d:] = r[i_d:]
            return z

        rhs_l = np.zeros(nL) if gross else (-tL[1] * (u_prev[0, L] - delta_prev[0])
                                            + tL[0] * (u_prev[1, L] - delta_prev[1]))
        b = np.concatenate([rhs_gap, u_prev[0, S] - delta_prev[0], u_prev[1, S] - delta_prev[1],
                            rhs_l, [wP * P, wQ * Q[0], wQ * Q[1]]])
        r0 = -tL[1] * q[0, L] + tL[0] * q[1, L]
        v0 = np.concatenate([p[C], q[0, S], q[1, S], r0, [d, delta[0], delta[1]]])
        last = [None]
        v, its, rel = gmres(matvec, psolve, b, v0, rtol=rt, maxiter=max_krylov)
        counters["krylov"] += its
        # the fields of the solution: (w, u) from GMRES's last matvec (always at the returned
        # v, and its output buffer is not touched after it), then (p, q) scattered again
        out = last[0]
        w, u = out[0].copy(), np.stack([out[1].copy(), out[2].copy()])
        scatter(v)
        p = flat[0].copy()
        q = np.stack([flat[1].copy(), flat[2].copy()])
        d = float(v[i_d])
        delta = np.array([v[i_d + 1], v[i_d + 2]])
        gap = f - d + w
        ds = (delta - delta_prev)[:, None] - (u - u_prev)
        dsu, dsn = _unit(ds)
        slip_mag = dsn
        pmax = max(float(p.max()), 1e-300)
        ds_scale = max(float(dsn[contact].max()) if contact.any() else 0.0,
                       float(np.hypot(*(delta - delta_prev))), 1e-300)
        qn = np.hypot(q[0], q[1])
        new_contact = np.where(contact, p >= 0.0, gap < 0.0)
        was_stick = stick & new_contact
        excess = qn - mu * p
        to_slip = was_stick & (excess > _SET_TOL * mu * pmax)
        was_slip = Lm & new_contact
        along = t[0] * ds[0] + t[1] * ds[1]
        back = was_slip & (along < -_SET_TOL * ds_scale)
        if cautious:
            to_slip = _worst(to_slip, excess / pmax)
            back = _worst(back, -along / ds_scale)
        new_stick = (was_stick & ~to_slip) | back
        new_t = np.zeros((2, n))
        qu, _ = _unit(q)
        new_t[:, to_slip] = qdir[:, None] if gross else qu[:, to_slip]
        keep = was_slip & ~back
        # slip directions: along the shear the solve needed to keep the slip along t
        new_t[:, keep] = qdir[:, None] if gross else qu[:, keep]
        entered = new_contact & ~contact
        new_t[:, entered] = qdir[:, None] if gross else np.where(
            dsn[entered] > 0, dsu[:, entered], qdir[:, None])
        if not new_stick.any() and new_contact.any():
            cand = np.flatnonzero(stick & new_contact)
            if not cand.size:
                cand = np.flatnonzero(new_contact)
            j = cand[np.argmin(excess[cand] / pmax)]
            new_stick[j] = True
            new_t[:, j] = 0.0
        # the directions' change weighted by p / p_max: the change of q it makes, over |mu| p_max
        # (a node at the contact's edge, where p vanishes, may turn a lot and change nothing)
        turn = float(np.max((np.hypot(*(new_t - t)) * p)[keep])) / pmax if keep.any() else 0.0
        if keep.any():  # and the largest turn itself, below sqrt(dir_tol)
            turn = max(turn, float(np.max(np.hypot(*(new_t - t))[keep])) ** 2)
        same_sets = (np.array_equal(new_contact, contact) and np.array_equal(new_stick, stick))
        if same_sets and turn <= dir_tol and rel <= rtol:
            result = (p, q, w, u, gap, ds, rel)
            break
        key = (new_contact.tobytes(), new_stick.tobytes())
        if same_sets:
            # settled sets: the directions (a Newton iteration, quadratic: the next solve
            # needs an inner tolerance ~ turn^2) and then the inner tolerance, down to rtol
            seen.clear()
            t = new_t
            rt = rtol if turn <= dir_tol else max(rtol, min(rt, turn))
            continue
        if key in seen:
            cycles += 1
            seen.clear()
            if rt > rtol:
                rt = rtol
                continue
            if not cautious:
                cautious = True
                continue
            marginal = True
            result = (p, q, w, u, gap, ds, rel)
            break
        seen.add(key)
        contact, stick, t = new_contact, new_stick, new_t
    if result is None:
        raise ConvergenceError(f"partial slip (surface): the sets did not settle in {max_outer} "
                               f"iterations (P = {P:.4g}, Q = {Q})", iterations=max_outer)
    p, q, w, u, gap, ds, rel = result
    if gross and stick.sum() == 1:
        j = np.flatnonzero(stick)[0]
        q[:, j] = mu * p[j] * qdir
    off = ~contact
    slipn = contact & ~stick
    dsu, dsn = _unit(ds)
    qu, qn = _unit(q)
    ds_scale = max(float(dsn[contact].max()), float(np.hypot(*(delta - delta_prev))), 1e-300)
    along = qu[0] * dsu[0] + qu[1] * dsu[1]
    res = {
        "linear": rel,
        "penetration": float(max(-gap[off].min(), 0.0)) / max(abs(d), 1e-300) if off.any()
        else 0.0,
        "tension": float(max(-p.min(), 0.0)) / max(float(p.max()), 1e-300),
        "coulomb": float(max((qn - mu * p).max(), 0.0)) / max(mu * float(p.max()), 1e-300),
        # slip against the shear (or off its direction), weighted by the slip's size
        # (not at gross sliding: there the slip is unbounded along Q, this step's finite
        # increment is not its direction)
        # (nodes without pressure carry no shear: no direction to check)
        "slip_direction": float(np.max(np.where(qn > 0, (1.0 - along) * dsn, 0.0)[slipn]))
        / ds_scale if slipn.any() and not gross else 0.0,
        "load": abs(cell * p.sum() - P) / P,
        "tangential_load": float(np.hypot(*(cell * q.sum(axis=1) - Q))) / Qn,
    }
    friction = max(res["coulomb"], res["slip_direction"])
    worst = max(v for k, v in res.items() if k not in ("linear", "coulomb", "slip_direction"))
    if friction > (_MARGINAL if marginal else max(accept, 1e3 * _DIR_TOL)):
        raise ConvergenceError(f"partial slip (surface) step: friction-law violation "
                               f"{friction:.1e}", residuals=[friction], iterations=outer)
    res["marginal_nodes"] = int(marginal)
    res["cycles"] = cycles
    if worst > accept:
        raise ConvergenceError(f"partial slip (surface) step (P = {P:.4g}): residual "
                               f"{worst:.1e} > {accept:.0e} ({max(res, key=res.get)})",
                               residuals=[worst], iterations=outer)
    old = prev.slip if prev.slip is not None else np.zeros((2, n))
    slip = np.where(contact & prev.contact, old + ds, 0.0)
    p = np.where(contact, np.maximum(p, 0.0), 0.0)
    s = SlipState2D(p=p, q=q, w=w, u=u, d=d, delta=delta, contact=contact, stick=stick,
                    sigma=np.zeros(n, dtype=np.int8), P=P, Q=float(np.hypot(*Q)), slip=slip,
                    iterations=outer, krylov_iterations=counters["krylov"],
                    fft_pairs=counters["fft"], residuals=res)
    s.t = np.where(slipn, _unit(q)[0], 0.0)
    s.shape = shape
    return s


def _worst(mask, score):
    out = np.zeros_like(mask)
    idx = np.flatnonzero(mask)
    if idx.size:
        out[idx[np.argmax(score[idx])]] = True
    return out
