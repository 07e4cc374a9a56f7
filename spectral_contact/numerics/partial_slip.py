"""Incremental Coulomb contact (partial slip) on the film: one load step (dimensionless core).

A rigid indenter of heights ``f`` (above its apex) is pressed with the normal load P and pulled
with the tangential load Q; the indenter moves rigidly by the indentation d (down) and the
tangential displacement delta (along +x).  The film's surface, loaded by the pressure p
(p >= 0, p = -sigma_zz(h)) and the shear q (= sigma_xz(h): q > 0 drags the surface toward +x),
sinks by w and moves tangentially by u, both from the film's coupled surface compliance
(``Film.surface_displacement_transfer``: the 2 x 2 symbol [[F0, i F1], [-i F1, F2]] / 2|k| in
1D, units 1/G; its coupling F1 makes a pressure move the surface tangentially and a shear sink
it, unlike on an incompressible half-space).

Coulomb's law in incremental (quasi-static, history-dependent) form, from the state n of the
previous step (u_n, delta_n) to this one:

* contact C: gap = f - d + w = 0, p >= 0; outside: gap >= 0, p = 0, q = 0;
* slip increment of the indenter relative to the surface: s = (delta - delta_n) - (u - u_n);
* stick nodes (S, in C): s = 0, |q| <= |mu| p;
* slip nodes (C \\ S): q = sigma |mu| p with sigma = +-1 the sign of s (q drags the surface the
  way the indenter slips over it);
* cell * sum p = P, cell * sum q = Q (these fix d and delta).

The sets (C, S, sigma) are found by a primal-dual active-set iteration (a semismooth Newton
method for the two complementarity conditions), as ``numerics.contact`` does for the normal
problem; for fixed sets the bordered linear system in (p on C, q on S, d, delta) is solved by
right-preconditioned GMRES (``numerics.krylov``).  The preconditioner is the inverse of the 2 x 2
symbol clipped below k_c = pi / W (W the contact's width: the same order-0 argument as
``FourierOperator.preconditioner``), masked to the sets.  One matrix-vector product is two FFT
pairs (p and q through the 2 x 2 symbol), one preconditioner application two more.

When no node would stick (|Q| = |mu| P: gross sliding) the iteration keeps the most stuck node
of the previous stick set: the sum of q then forces q = sigma |mu| p there too, so the state is
the steady sliding one (q = mu p everywhere) and delta stays defined (the limit of the partial
slip states).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ConvergenceError
from ..physics.film import Film
from .fft import get_rfft
from .grid import Grid
from .krylov import gmres

__all__ = ["SlipState", "PartialSlipOperator", "solve_slip_step"]

_SET_TOL = 1e-9  # relative margins of the set updates (round-off of marginal nodes)
_SEARCH_RTOL = 1e-3  # GMRES tolerance while the sets are searched (then rtol on the last set)
_MARGINAL = 1e-2  # a persistent one-node stick-slip cycle: largest friction-law violation
# accepted (Coulomb excess over mu p_max, reverse slip over the step's largest slip in the
# contact): an error of the order of the stick edge's node position, which the grid's estimate
# already carries


@dataclass
class SlipState:
    """The state after a load step (dimensionless fields on the grid, flat)."""
    p: np.ndarray          # pressure
    q: np.ndarray          # surface shear sigma_xz(h)
    w: np.ndarray          # sinking (-u_z) of the surface
    u: np.ndarray          # tangential displacement of the surface
    d: float               # indentation
    delta: float           # indenter's tangential displacement
    contact: np.ndarray    # bool
    stick: np.ndarray      # bool (subset of contact)
    sigma: np.ndarray      # int8: slip direction on slip nodes (0 elsewhere)
    P: float = 0.0
    Q: float = 0.0
    slip: np.ndarray | None = None  # accumulated slip (delta - u, relative to contact entry)
    iterations: int = 0
    krylov_iterations: int = 0
    fft_pairs: int = 0
    residuals: dict = field(default_factory=dict)

    @staticmethod
    def unloaded(n: int) -> SlipState:
        z = np.zeros(n)
        b = np.zeros(n, dtype=bool)
        return SlipState(z, z.copy(), z.copy(), z.copy(), 0.0, 0.0, b, b.copy(),
                         np.zeros(n, dtype=np.int8), slip=z.copy())


class PartialSlipOperator:
    """The film's coupled surface compliance (p, q) -> (w, u) on a 1D periodic ``grid``, and
    the clipped inverse symbols of its preconditioner."""

    def __init__(self, grid: Grid, film: Film | None = None):
        if grid.ndim != 1:
            raise ValueError("PartialSlipOperator takes 1D grids (line contacts); 2D grids: "
                             "numerics.partial_slip2d")
        self.grid = grid
        self.film = film or Film()
        self.fft = get_rfft(grid.shape)
        kmag = grid.kmag
        ks = grid.kshape

        def symbols(kk):
            def evaluate(n):
                (up,), wp = self.film.surface_displacement_transfer(n, kk, 1.0, (0.0,))
                (uq,), wq = self.film.surface_displacement_transfer(n, kk, 0.0, (1.0,))
                return wp, wq, up, uq
            return evaluate

        self.H = tuple(np.broadcast_to(np.asarray(s, dtype=complex), ks).copy()
                       for s in grid.alias_average(symbols(kmag)))
        self._pre: dict = {}
        self._pair = _pair_plan(grid.n)

    def apply(self, p: np.ndarray, q: np.ndarray):
        """(w, u) of the tractions (p, q): two FFT pairs (one batched pair of transforms)."""
        r, _, _, _ = self._pair
        r[0] = p
        r[1] = q
        out = self.transform(self.H)
        return out[0].copy(), out[1].copy()

    def transform(self, M):
        """The 2 x 2 symbol ``M`` = (M00, M01, M10, M11) applied to the two rows of the
        batched plan's real buffer (filled by the caller); returns that buffer, scaled (valid
        until the next call)."""
        r, c, fwd, bwd = self._pair
        fwd()
        c0, c1 = c[0], c[1]
        t = M[0] * c0
        t += M[1] * c1
        c1 *= M[3]
        c1 += M[2] * c0
        c[0] = t
        bwd()
        r *= 1.0 / r.shape[1]
        return r

    def preconditioner(self, k_cut: float):
        """The inverse 2 x 2 symbol for |k| >= k_cut, its value at |k| = k_cut below."""
        M = self._pre.get(k_cut)
        if M is None:
            Hpp, Hpq, Hqp, Hqq = self.H
            kc = np.full((1,), float(k_cut))
            (up,), wp = self.film.surface_displacement_transfer((1.0,), kc, 1.0, (0.0,))
            (uq,), wq = self.film.surface_displacement_transfer((1.0,), kc, 0.0, (1.0,))
            low = self.grid.kmag < k_cut
            a = np.where(low, wp, Hpp)
            b = np.where(low, wq, Hpq)
            c = np.where(low, up, Hqp)
            e = np.where(low, uq, Hqq)
            det = a * e - b * c
            M = (e / det, -b / det, -c / det, a / det)
            if len(self._pre) > 32:
                self._pre.clear()
            self._pre[k_cut] = M
        return M


_PAIRS: dict = {}


def _pair_plan(n: int):
    """A batched real FFT of two rows of n points (pyfftw, the package's planner effort):
    (real buffer (2, n), complex buffer (2, n/2 + 1), forward, backward)."""
    import pyfftw

    from . import fft as _fft

    plan = _PAIRS.get(n)
    if plan is None:
        r = pyfftw.empty_aligned((2, n), dtype="float64")
        c = pyfftw.empty_aligned((2, n // 2 + 1), dtype="complex128")
        effort = _fft._PLANNER_EFFORT
        fwd = pyfftw.FFTW(r, c, axes=(-1,), direction="FFTW_FORWARD", flags=(effort,))
        bwd = pyfftw.FFTW(c, r, axes=(-1,), direction="FFTW_BACKWARD",
                          flags=(effort, "FFTW_DESTROY_INPUT"))
        plan = _PAIRS[n] = (r, c, fwd.execute, bwd.execute)
        if len(_PAIRS) > 8:
            _PAIRS.pop(next(iter(_PAIRS)))
    return plan


def solve_slip_step(op: PartialSlipOperator, f: np.ndarray, prev: SlipState, P: float, Q: float,
                    mu: float, *, guess: SlipState | None = None, rtol: float = 1e-10,
                    search_rtol: float | None = _SEARCH_RTOL, accept: float = 1e-8,
                    max_outer: int = 100, max_krylov: int = 2000) -> SlipState:
    """One quasi-static load step from the state ``prev`` to the loads (P, Q) (dimensionless:
    P, Q per unit length in G h/2R x h; ``f`` the indenter's heights above its apex, in
    h^2/2R), Coulomb friction coefficient |mu|.

    guess : first sets and fields (default ``prev``; for the first step of a loading from
            nothing, e.g. a frictionless solution: its contact set, all stuck).
    search_rtol : the inner (GMRES) tolerance while the sets are searched; once they repeat,
            the solve is redone to ``rtol`` on them (and must confirm them).  Only the path
            changes, not what is accepted (None: ``rtol`` throughout).
    Returns the new state (its ``slip``: the accumulated slip delta - u relative to where each
    node was when it came into contact, 0 off the contact).  ConvergenceError if the sets do not
    settle or the final residual exceeds ``accept``.
    """
    grid = op.grid
    n = grid.n
    cell = grid.cell
    mu = abs(float(mu))
    g = guess or prev
    contact = g.contact.copy()
    if not contact.any():
        contact[int(np.argmin(f))] = True
    stick = g.stick & contact
    sigma = np.where(contact & ~stick, g.sigma, 0).astype(np.int8)
    if not stick.any():
        stick[np.flatnonzero(contact)[np.argmax(g.p[contact])]] = True
        sigma[stick] = 0
    p = np.where(contact, g.p, 0.0)
    q = np.where(contact, g.q, 0.0)
    d, delta = g.d, g.delta
    u_prev, delta_prev = prev.u, prev.delta
    counters = {"fft": 0, "krylov": 0}
    seen = set()
    result = None
    rt = max(rtol, search_rtol or rtol)
    cautious = False
    marginal = False
    cycles = 0
    for outer in range(1, max_outer + 1):  # noqa: B007 (the count is reported after the loop)
        C = np.flatnonzero(contact)
        S = np.flatnonzero(stick)
        L = np.flatnonzero(contact & ~stick)
        sL = mu * sigma[L]
        nC, nS = C.size, S.size
        rhs_gap = -f[C]
        rhs_stick = u_prev[S] - delta_prev
        gap_norm = max(math.sqrt(float(rhs_gap @ rhs_gap)), 1e-300)
        wP = gap_norm / P
        wQ = gap_norm / (mu * P) if mu > 0 else 1.0
        # (the contact's width rounded to 1/16 of an octave: the cut-off need not be exact,
        # and its clipped inverse symbol is then reused from step to step)
        width = 2.0 ** (round(16.0 * math.log2(max(C[-1] - C[0] + 1, 1) * grid.dx)) / 16.0)
        Mi = op.preconditioner(math.pi / width)
        last = [None]
        # position of p's slip nodes within C (q there = sigma mu p)
        posL = np.searchsorted(C, L)

        # (one contiguous run, the common case: slices gather and scatter the same values)
        Cs = slice(int(C[0]), int(C[-1]) + 1) if C[-1] - C[0] + 1 == nC else C
        Ss = slice(int(S[0]), int(S[-1]) + 1) if nS and S[-1] - S[0] + 1 == nS else S
        rbuf = op._pair[0]
        transform = op.transform
        H = op.H

        def matvec(v):
            counters["fft"] += 2
            rbuf.fill(0.0)
            pv = v[:nC]
            rbuf[0, Cs] = pv
            rbuf[1, Ss] = v[nC:nC + nS]
            if L.size:
                rbuf[1, L] = sL * pv[posL]
            qsum = rbuf[1].sum()
            last[0] = (pv.copy(), v[nC:nC + nS].copy())
            out = transform(H)
            wu[0] = out
            res = np.empty_like(v)
            np.subtract(out[0, Cs], v[nC + nS], out=res[:nC])
            np.subtract(out[1, Ss], v[nC + nS + 1], out=res[nC:nC + nS])
            res[nC + nS] = wP * cell * pv.sum()
            res[nC + nS + 1] = wQ * cell * qsum
            return res

        def psolve(r):
            counters["fft"] += 2
            rbuf.fill(0.0)
            rbuf[0, Cs] = r[:nC]
            rbuf[1, Ss] = r[nC:nC + nS]
            out = transform(Mi)
            z = np.empty_like(r)
            z[:nC] = out[0, Cs]
            z[nC:nC + nS] = out[1, Ss]
            z[nC + nS:] = r[nC + nS:]
            return z

        wu = [None]

        def fields():
            """p, q, w, u of the last matvec (GMRES's last one is at the solution)."""
            pv, qv = last[0]
            pf = np.zeros(n)
            pf[C] = pv
            qf = np.zeros(n)
            qf[S] = qv
            qf[L] = sL * pv[posL]
            return pf, qf, wu[0][0].copy(), wu[0][1].copy()

        b = np.concatenate([rhs_gap, rhs_stick, [wP * P, wQ * Q]])
        v0 = np.concatenate([p[C], q[S], [d, delta]])
        v, its, rel = gmres(matvec, psolve, b, v0, rtol=rt, maxiter=max_krylov)
        counters["krylov"] += its
        pf, qf, w, u = fields()
        d, delta = float(v[nC + nS]), float(v[nC + nS + 1])
        p, q = pf, qf
        gap = f - d + w
        ds = (delta - delta_prev) - (u - u_prev)
        pmax = max(float(p.max()), 1e-300)
        ds_scale = max(float(np.abs(ds).max()), abs(delta - delta_prev), 1e-300)
        # new sets
        new_contact = np.where(contact, p >= 0.0, gap < 0.0)
        new_stick = np.zeros(n, dtype=bool)
        new_sigma = np.zeros(n, dtype=np.int8)
        was_stick = stick & new_contact
        excess = np.abs(q) - mu * p
        to_slip = was_stick & (excess > _SET_TOL * mu * pmax)
        was_slip = contact & ~stick & new_contact
        back = was_slip & (sigma * ds < -_SET_TOL * ds_scale)
        if cautious:
            # after a cycle: only the worst violation of each kind changes (a cycle of the
            # full update swaps whole bands of nodes between stick and slip)
            to_slip = _worst(to_slip, excess / pmax)
            back = _worst(back, -(sigma * ds) / ds_scale)
        new_stick[was_stick & ~to_slip] = True
        new_sigma[to_slip] = np.sign(q[to_slip]).astype(np.int8)
        new_stick[back] = True
        keep = was_slip & ~back
        new_sigma[keep] = sigma[keep]
        # a node coming into contact slips the way it moved relative to the indenter while
        # it was free (sticking there would hold it at the position it had at the last
        # step: at a trailing edge, a large shear on a vanishing pressure); it sticks at a
        # later iteration if its slip reverses
        entered = new_contact & ~contact
        new_sigma[entered] = np.where(ds[entered] < 0.0, -1, 1)
        if not new_stick.any() and new_contact.any():
            # gross sliding: keep the most stuck of the old stick nodes still in contact
            cand = np.flatnonzero(stick & new_contact)
            if not cand.size:
                cand = np.flatnonzero(new_contact)
            j = cand[np.argmin(excess[cand] / pmax)]
            new_stick[j] = True
            new_sigma[j] = 0
        key = (new_contact.tobytes(), new_stick.tobytes(), new_sigma.tobytes())
        same = (np.array_equal(new_contact, contact) and np.array_equal(new_stick, stick)
                and np.array_equal(new_sigma, sigma))
        if same and rt > rtol:  # the loose search has settled: confirm at rtol
            rt = rtol
            seen.clear()
            continue
        if same:
            result = (p, q, w, u, gap, ds, rel)
            break
        if key in seen:
            cycles += 1
            seen.clear()
            if rt > rtol:  # first at the full inner tolerance
                rt = rtol
                continue
            if not cautious:
                cautious = True
                continue
            # a cycle of single-node changes: a node at the stick-slip boundary whose two
            # states both violate the law slightly (the discrete boundary falls between
            # nodes); this state is accepted if its violations are below _MARGINAL
            marginal = True
            result = (p, q, w, u, gap, ds, rel)
            break
        seen.add(key)
        contact, stick, sigma = new_contact, new_stick, new_sigma
    if result is None:
        raise ConvergenceError(f"partial slip: the active sets did not settle in {max_outer} "
                               f"iterations (P = {P:.4g}, Q = {Q:.4g})", iterations=max_outer)
    p, q, w, u, gap, ds, rel = result
    if abs(Q) >= mu * P * (1.0 - 1e-12) and stick.sum() == 1:
        # gross sliding: the kept stick node carries q = sigma mu p up to the load residual
        # divided by the cell (the sum fixes it): set it exactly
        j = np.flatnonzero(stick)[0]
        q[j] = math.copysign(mu * p[j], Q)
    # residuals (max-norm, relative)
    off = ~contact
    slipn = contact & ~stick
    ds_scale = max(float(np.abs(ds[contact]).max()), abs(delta - delta_prev), 1e-300)
    res = {
        "linear": rel,
        "penetration": float(max(-gap[off].min(), 0.0)) / max(abs(d), 1e-300) if off.any() else 0.0,
        "tension": float(max(-p.min(), 0.0)) / pmax,
        "coulomb": float(max((np.abs(q) - mu * p).max(), 0.0)) / max(mu * pmax, 1e-300),
        "slip_direction": float(max((-(sigma * ds))[slipn].max(), 0.0)) / ds_scale
        if slipn.any() else 0.0,
        "load": abs(cell * p.sum() - P) / P,
        "tangential_load": abs(cell * q.sum() - Q) / max(mu * P, 1e-300),
    }
    friction = max(res["coulomb"], res["slip_direction"])
    worst = max(v for k, v in res.items() if k not in ("linear", "coulomb", "slip_direction"))
    if friction > (_MARGINAL if marginal else accept):
        raise ConvergenceError(
            f"partial slip step (P = {P:.4g}, Q = {Q:.4g}): the stick-slip sets "
            f"{'cycle' if marginal else 'settle'} with a friction-law violation {friction:.1e}",
            residuals=[friction], iterations=outer)
    res["marginal_nodes"] = int(marginal)
    res["cycles"] = cycles
    if worst > accept:
        raise ConvergenceError(f"partial slip step (P = {P:.4g}, Q = {Q:.4g}): residual "
                               f"{worst:.1e} > {accept:.0e} ({max(res, key=res.get)})",
                               residuals=[worst], iterations=outer)
    # accumulated slip: the previous one plus this step's increment, on nodes in contact
    # before and now; a node entering contact starts from 0
    old = prev.slip if prev.slip is not None else np.zeros(n)
    slip = np.where(contact & prev.contact, old + ds, 0.0)
    p = np.where(contact, np.maximum(p, 0.0), 0.0)
    return SlipState(p=p, q=q, w=w, u=u, d=d, delta=delta, contact=contact, stick=stick,
                     sigma=sigma, P=P, Q=Q, slip=slip, iterations=outer,
                     krylov_iterations=counters["krylov"], fft_pairs=counters["fft"],
                     residuals=res)


def _worst(mask: np.ndarray, score: np.ndarray) -> np.ndarray:
    """``mask`` reduced to its node of largest ``score`` (all False if none)."""
    out = np.zeros_like(mask)
    idx = np.flatnonzero(mask)
    if idx.size:
        out[idx[np.argmax(score[idx])]] = True
    return out
