"""Incremental Coulomb contact (partial slip) on the film: one load step, for a line (1D grid)
and a surface (2D grid) alike (dimensionless core).

A rigid indenter of heights ``f`` (above its apex) is pressed with the normal load P and pulled
with the tangential load Q (a number on a line, (Q_x, Q_y) on a surface); it moves rigidly by
the indentation d (down) and the tangential displacement delta.  The film's surface, loaded by
the pressure p (p >= 0, p = -sigma_zz(h)) and the shear q (= sigma_xz(h), and sigma_yz(h) on a
surface: q > 0 drags the surface toward +x), sinks by w and moves tangentially by u, both from
the film's coupled compliance (``Film.surface_displacement_transfer``: the (1 + D) x (1 + D)
symbol, D = 1 or 2 tangential components, units 1/G; its pressure-shear coupling (F1) makes a
pressure move the surface tangentially and a shear sink it, unlike on an incompressible
half-space).

Coulomb's law in incremental (quasi-static, history-dependent) form, from the state n of the
previous step (u_n, delta_n) to this one:

* contact C: gap = f - d + w = 0, p >= 0; outside: gap >= 0, p = 0, q = 0;
* slip increment of the indenter relative to the surface: s = (delta - delta_n) - (u - u_n);
* stick nodes (S, in C): s = 0, |q| <= |mu| p;
* slip nodes (C \\ S): q = |mu| p t with t the unit vector of s (on a line t = sigma = +-1);
* cell * sum p = P, cell * sum q = Q (these fix d and delta).

The sets (C, S, t) are found by a primal-dual active-set iteration (a semismooth Newton method
for the complementarity conditions, as ``numerics.contact`` does for the normal problem); for
fixed sets the bordered linear system in (p on C, q on S, d, delta) is solved by
right-preconditioned GMRES (``numerics.krylov``).  On a surface the slip direction is solved,
not assumed along Q: the system also holds, on each slip node, the shear r across t
(q = |mu| p t + r t_perp) and the Newton linearisation of "s parallel to q" across t,
((s . t)/(|mu| p)) r = s . t_perp (s, p of the last iteration; s . t floored at
``_NEWTON_FLOOR`` |s|; a node that has just begun to slip keeps s along t); t is then turned to
q/|q| until the change this makes in q, |mu| p |dt|, and the excess |q| - |mu| p (r makes |q|
exceed |mu| p by its square) are below ``dir_tol`` |mu| p_max (default: the accepted residual),
the inner tolerance following the turn (inexact Newton).  The turn is weighed by p as the
friction-law check weighs it (below): the direction at the contact's edge, where p vanishes,
moves no shear (the largest turn was also held below sqrt(dir_tol): edge nodes with p ~ 1e-3
p_max then took 2-4 extra solves per tangential step of a sphere on 256^2).  Set updates: a
stick node whose |q| exceeds |mu| p slips along q/|q|; a slip node whose s points against t
sticks; a node coming into contact slips along its s (it sticks at a later iteration if that
reverses).  A cycle of the sets is retried at the full inner tolerance, then with one change of
each kind per iteration, then accepted as a one-node stick-slip boundary if its friction-law
violation is below ``_MARGINAL``.

The Newton term's coefficient: s . t, the exact linearisation of s x q = 0 at q = |mu| p t
(r = |mu| p tan(angle) for a node whose slip the others set); |s| (as before) turned a
misaligned node by atan(sin(angle)) only, so a flipped edge node took 3-4 solves to settle.  The
floor 0.1 |s| keeps the term positive; on the 1 N sphere's 256^2 level (20 + 20 steps): FFT
pairs 9028 (floor 0.3), 8911 (0.1), 8929 (0.01) against 9550 with |s| (studies/README.md,
onset).

The preconditioner is the inverse symbol clipped below k_c = pi / W (W the contact's width:
the same order-0 argument as ``FourierOperator.preconditioner``), masked to the sets; on the
rows across t it is scaled by a0/(a0 + (s . t)/(|mu| p)), a0 the operator's diagonal (the Newton
term is a diagonal D: (A + D)^-1 ~ (1 + D/a0)^-1 A^-1).  One matrix-vector product is one
batched transform of the 1 + D fields (1 + D FFT pairs), one preconditioner application the
same; on a surface both on the contact's band of rows (``PartialSlipOperator.transform``), the
fields completed on every row once per solve.

At gross sliding (|Q| = |mu| P) Coulomb's |q| <= |mu| p and the sum of q = Q leave q =
|mu| p Q/|Q| at every contact node: the stick zone is empty and the tractions are the steady
sliding ones (``solve``'s), whatever the history.  Only the contact set is searched (every
contact node slips along Q; one node, the most stuck of the previous stick set, sticks to close
the system while searching); the accepted state is then made exact (``_gross_finish``): p
balanced, q = |mu| p Q/|Q| on the contact, and delta the least that lets no contact node slip
against Q, delta_n + the largest step of the surface along Q, u - u_n (the limit of the
partial slip states as Q -> |mu| P: the last node to stick is the one that moved furthest);
that node is the state's one stick node.  (Before, the slip nodes that moved back relative to
the indenter stuck again and the stick set could cycle: the 1 N sphere at mu 0.02 on 256^2
between 1 and 16 nodes, a Coulomb violation 0.55, exit 3; where it settled the tangential
displacement agrees with this to < 5e-6 of its value, studies/README.md, onset.)  Below gross
sliding (a stick zone narrower than a cell: e.g. the normal loading
at a small |mu|, where the film's coupling makes every node slip outward) it keeps the node
whose shear would balance the others' |mu| p t best.

The accepted solve's loads are then held exactly (``balance``): uniform shifts of p on the
contact and of q on the stick nodes, of the order of the inner residual, and one product for
the displacements; the inner tolerance need only follow the accepted residual.  Its friction
law is checked (ConvergenceError beyond ``accept`` on a line, beyond the larger of ``accept``
and ``_SURFACE_LAW`` = 1e-3 on a surface, as before): the Coulomb excess |q| - |mu| p over
|mu| p_max, and the slip against the shear over the step's largest slip: on a line the
reverse slip, on a surface the slip's part off q's direction, |s| - s . q/|q|, weighed by
p / p_max (the share of the shear it misdirects, as the Coulomb excess is weighed).  (Unweighted,
it held the directions of edge nodes carrying ~1e-3 of p_max, and the inner tolerance at 1e-4
of the accepted residual, for nothing the measures see: the 1 N sphere's answers moved by
< 2e-6 of their values, its FFT pairs fell by 23 %.)
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ConvergenceError
from .krylov import gmres
from .slip_operator import PartialSlipOperator, PartialSlipOperator2D

__all__ = ["SlipState", "SlipState2D", "PartialSlipOperator", "PartialSlipOperator2D",
           "solve_slip_step", "solve_slip_step_2d", "entry_motion"]

_SET_TOL = 1e-9  # relative margins of the set updates (round-off of marginal nodes)
_SEARCH_RTOL = 1e-3  # GMRES tolerance while the sets are searched (then rtol on the last set)
_MARGINAL = 1e-2  # a persistent one-node stick-slip cycle: largest friction-law violation
# accepted (Coulomb excess over mu p_max, reverse slip over the step's largest slip in the
# contact): an error of the order of the stick edge's node position, which the grid's estimate
# already carries
_NEWTON_FLOOR = 0.1  # surfaces: the Newton term's s . t is at least this times |s|
_SURFACE_LAW = 1e-3  # surfaces: the friction-law check's limit (at least ``accept``): the
# Coulomb excess and the (weighed) slip direction; with ``accept`` (1e-4 at the default tol) a
# sphere on 512^2 stopped at 3.5e-4 in its loading


@dataclass
class SlipState:
    """The state after a load step (dimensionless fields on the grid, flat).  On a line ``q``,
    ``u``, ``slip`` have shape (n,), ``delta`` is a number and ``sigma`` the slip directions
    (+-1, 0 off the slip set); on a surface (``SlipState2D``) they have shape (2, n), delta is
    a length-2 array and ``t`` (2, n) holds the slip directions."""
    p: np.ndarray          # pressure
    q: np.ndarray          # surface shear
    w: np.ndarray          # sinking (-u_z) of the surface
    u: np.ndarray          # tangential displacement of the surface
    d: float               # indentation
    delta: float           # indenter's tangential displacement
    contact: np.ndarray    # bool
    stick: np.ndarray      # bool (subset of contact)
    sigma: np.ndarray      # int8: slip direction on slip nodes of a line (0 elsewhere)
    P: float = 0.0
    Q: float = 0.0
    slip: np.ndarray | None = None  # accumulated slip (delta - u, relative to contact entry)
    iterations: int = 0
    krylov_iterations: int = 0
    fft_pairs: int = 0
    residuals: dict = field(default_factory=dict)
    t: np.ndarray | None = None  # surfaces: unit slip directions (2, n), 0 off the slip set

    @staticmethod
    def unloaded(n: int) -> SlipState:
        z = np.zeros(n)
        b = np.zeros(n, dtype=bool)
        return SlipState(z, z.copy(), z.copy(), z.copy(), 0.0, 0.0, b, b.copy(),
                         np.zeros(n, dtype=np.int8), slip=z.copy())


class SlipState2D(SlipState):
    """``SlipState`` of a surface (vector shear, displacements and directions)."""

    @staticmethod
    def unloaded(n: int) -> SlipState2D:
        z = np.zeros(n)
        b = np.zeros(n, dtype=bool)
        return SlipState2D(z, np.zeros((2, n)), z.copy(), np.zeros((2, n)), 0.0, np.zeros(2), b,
                           b.copy(), np.zeros(n, dtype=np.int8), slip=np.zeros((2, n)),
                           t=np.zeros((2, n)))


def _unit(v):
    """(v / |v|, |v|) column-wise for v of shape (D, n) (0 where |v| = 0)."""
    n = np.abs(v[0]) if v.shape[0] == 1 else np.hypot(v[0], v[1])
    return v / np.where(n > 0, n, 1.0), n


def _run(idx: np.ndarray):
    """A slice for a contiguous run of indices (gathers and scatters the same values)."""
    if idx.size and idx[-1] - idx[0] + 1 == idx.size:
        return slice(int(idx[0]), int(idx[-1]) + 1)
    return idx


def _vec(x, nd: int) -> np.ndarray:
    """A field of D components as a (D, n) array (a line's (n,) -> (1, n)), a vector as (D,)."""
    x = np.asarray(x, dtype=float)
    return x.reshape(nd, -1) if x.ndim > 1 or x.size > nd else x.reshape(nd)


def _directions(g: SlipState, nd: int) -> np.ndarray:
    """The slip directions of a state as (D, n) (a line's sigma as +-1.0)."""
    if g.t is not None:
        return _vec(g.t, nd)
    return g.sigma.astype(float)[None] if nd == 1 else np.zeros((nd, g.p.size))


class _Linear:
    """The bordered linear system for fixed sets (C, S, slip directions t on L = C \\ S):
    unknowns p on C, q (each component) on S, on a surface the shear r across t on L, then d
    and delta; rows: gap on C, stick on S, on a surface no slip across t on L (the Newton
    linearisation), the loads.  ``solve(x0, rt)`` runs GMRES and sets the fields."""

    def __init__(self, op, f, sets, prev, P, Q, mu, gross, slip_along, p_last):
        contact, stick, t = sets
        nd, n = op.ndim, op.size
        self.op, self.nd, self.mu, self.gross = op, nd, mu, gross
        self.C, self.S = np.flatnonzero(contact), np.flatnonzero(stick)
        self.L = np.flatnonzero(contact & ~stick)
        C, S, L = self.C, self.S, self.L
        self.Cs, self.Ss = _run(C), _run(S)
        self.posL = np.searchsorted(C, L)
        self.tL = t[:, L]
        nC, nS, nL = C.size, S.size, L.size
        self.nr = nL if nd == 2 else 0  # unknowns across t (none on a line)
        self.i_s, self.i_l = nC, nC + nd * nS
        self.i_d = self.i_l + self.nr
        self.sL = mu * self.tL[0] if nd == 1 else None
        if self.nr:  # the Newton term across t, (s . t)/(|mu| p), and its rows' preconditioner
            pl = p_last[L]
            self.compl = np.where(pl > 0, slip_along[L] / (mu * np.maximum(pl, 1e-300)), 0.0)
            a0 = op.self_compliance()
            self.damp = a0 / (a0 + self.compl)
        rhs_gap = -f[C]
        gap_norm = max(math.sqrt(float(rhs_gap @ rhs_gap)), 1e-300)
        self.wP, self.wQ = gap_norm / P, gap_norm / max(mu * P, 1e-300)
        self.wPc, self.wQc = self.wP * op.cell, self.wQ * op.cell
        self.Mi = op.preconditioner(op.cut(C))
        self.flat = op._plan[0].reshape(op.m, n)
        # a surface's fields vanish outside the contact's rows: the transforms and the fills
        # run on those (``PartialSlipOperator.transform``'s rows)
        self.rows = op.band(C) if nd == 2 and C.size else None
        self.live = self.flat if self.rows is None else \
            op._plan[0][:, self.rows[0]:self.rows[1]]
        u_prev, d_prev = prev
        rhs_l = np.zeros(self.nr)
        if self.nr and not gross:
            rhs_l = -self.tL[1] * (u_prev[0, L] - d_prev[0]) + self.tL[0] * (u_prev[1, L] - d_prev[1])
        self.b = np.concatenate([rhs_gap] + [u_prev[c, S] - d_prev[c] for c in range(nd)]
                                + [rhs_l, [self.wP * P], self.wQ * Q])
        self.counters = {"fft": 0, "krylov": 0}

    def scatter(self, v, full=False):
        flat, nd, nS = self.flat, self.nd, self.S.size
        (flat if full else self.live).fill(0.0)
        pv = v[:self.i_s]
        flat[0, self.Cs] = pv
        for c in range(nd):
            flat[1 + c, self.Ss] = v[self.i_s + c * nS:self.i_s + (c + 1) * nS]
        if self.L.size:
            if nd == 1:
                flat[1, self.L] = self.sL * pv[self.posL]
            else:
                pl, r, tL = self.mu * pv[self.posL], v[self.i_l:self.i_d], self.tL
                flat[1, self.L] = tL[0] * pl - tL[1] * r
                flat[2, self.L] = tL[1] * pl + tL[0] * r
        return pv

    def matvec(self, v):
        op, nd, nS, i_d = self.op, self.nd, self.S.size, self.i_d
        self.counters["fft"] += op.m
        pv = self.scatter(v)
        qs = self.live[1:].reshape(nd, -1).sum(axis=1)
        out = op.transform(op.M, self.rows).reshape(op.m, -1)
        self.last = out
        res = np.empty_like(v)
        np.subtract(out[0, self.Cs], v[i_d], out=res[:self.i_s])
        for c in range(nd):
            np.subtract(out[1 + c, self.Ss], v[i_d + 1 + c],
                        out=res[self.i_s + c * nS:self.i_s + (c + 1) * nS])
        if self.nr:
            L, tL, r = self.L, self.tL, v[self.i_l:i_d]
            res[self.i_l:i_d] = r if self.gross else (
                -tL[1] * (out[1, L] - v[i_d + 1]) + tL[0] * (out[2, L] - v[i_d + 2])
                + self.compl * r)
        res[i_d] = self.wPc * pv.sum()
        res[i_d + 1:] = self.wQc * qs
        return res

    def psolve(self, r):
        op, flat, nd, nS = self.op, self.flat, self.nd, self.S.size
        self.counters["fft"] += op.m
        self.live.fill(0.0)
        flat[0, self.Cs] = r[:self.i_s]
        for c in range(nd):
            flat[1 + c, self.Ss] = r[self.i_s + c * nS:self.i_s + (c + 1) * nS]
        if self.nr:
            flat[1, self.L] = -self.tL[1] * r[self.i_l:self.i_d]
            flat[2, self.L] = self.tL[0] * r[self.i_l:self.i_d]
        out = op.transform(self.Mi, self.rows).reshape(op.m, -1)
        z = np.empty_like(r)
        z[:self.i_s] = out[0, self.Cs]
        for c in range(nd):
            z[self.i_s + c * nS:self.i_s + (c + 1) * nS] = out[1 + c, self.Ss]
        if self.nr:
            L, tL = self.L, self.tL
            z[self.i_l:self.i_d] = r[self.i_l:self.i_d] if self.gross else \
                (-tL[1] * out[1, L] + tL[0] * out[2, L]) * self.damp
        z[self.i_d:] = r[self.i_d:]
        return z

    def solve(self, state, rt, max_krylov):
        """GMRES from the fields ``state`` = (p, q, d, delta); returns (p, q, w, u, d, delta,
        relative residual)."""
        p, q, d, delta = state
        C, S, L = self.C, self.S, self.L
        r0 = (-self.tL[1] * q[0, L] + self.tL[0] * q[1, L]) if self.nr else np.zeros(0)
        v0 = np.concatenate([p[C]] + [q[c, S] for c in range(self.nd)] + [r0, [d], delta])
        v, its, rel = gmres(self.matvec, self.psolve, self.b, v0, rtol=rt, maxiter=max_krylov)
        self.counters["krylov"] += its
        # (w, u) from GMRES's last matvec (always at the returned v; its output buffer is not
        # touched after it: on a surface completed outside the contact's rows), then (p, q)
        # scattered again
        self.op.full_output()
        out = self.last
        w, u = out[0].copy(), out[1:].copy()
        self.scatter(v, full=True)
        return (self.flat[0].copy(), self.flat[1:].copy(), w, u, float(v[self.i_d]),
                v[self.i_d + 1:].copy(), rel)


def _update(sets, fields, prev_delta, u_prev, mu, gross, qdir, cautious, load):
    """The next sets from the last solve: (contact, stick, t), the slip increment's
    (ds, the next Newton term's s . t, scale) and the directions' turn (see the module).
    Only the nodes in contact before or after are looked at (p and q vanish elsewhere): the
    rules run on them (``_update_nodes``) and the results are scattered."""
    contact, stick, t = sets
    p, q, w, u, d, delta, gap = fields
    ds = (delta - prev_delta)[:, None] - (u - u_prev)
    new_contact = np.where(contact, p >= 0.0, gap < 0.0)
    idx = np.flatnonzero(contact | new_contact)
    (c_i, s_i, t_i), newton_i, ds_scale, turn = _update_nodes(
        contact[idx], stick[idx], t[:, idx], p[idx], q[:, idx], ds[:, idx], new_contact[idx],
        delta - prev_delta, mu, gross, qdir, cautious, load)
    new_stick = np.zeros_like(stick)
    new_stick[idx] = s_i
    new_t = np.zeros_like(t)
    new_t[:, idx] = t_i
    newton = np.zeros(p.size)
    newton[idx] = newton_i
    return (new_contact, new_stick, new_t), (ds, newton, ds_scale), turn


def _update_nodes(contact, stick, t, p, q, ds, new_contact, ddelta, mu, gross, qdir, cautious,
                  load):
    """``_update``'s rules on the nodes it looks at (all arrays restricted to them)."""
    dsu, dsn = _unit(ds)
    pmax = max(float(p.max()) if p.size else 0.0, 1e-300)
    ds_scale = max(float(dsn[contact].max()) if contact.any() else 0.0,
                   float(np.sqrt((ddelta ** 2).sum())), 1e-300)
    if gross:  # only the contact set is searched (``_gross_sets``)
        new_stick = _gross_stick(stick & new_contact, new_contact, p)
        new_t = np.where(new_contact & ~new_stick, qdir[:, None], 0.0)
        return (new_contact, new_stick, new_t), dsn, ds_scale, 0.0
    qu, qn = _unit(q)
    was_stick = stick & new_contact
    excess = qn - mu * p
    to_slip = was_stick & (excess > _SET_TOL * mu * pmax)
    was_slip = contact & ~stick & new_contact
    along = (t * ds).sum(axis=0)
    back = was_slip & (along < -_SET_TOL * ds_scale)
    if cautious:
        # after a cycle: only the worst violation of each kind changes (a cycle of the full
        # update swaps whole bands of nodes between stick and slip)
        to_slip = _worst(to_slip, excess / pmax)
        back = _worst(back, -along / ds_scale)
    new_stick = (was_stick & ~to_slip) | back
    new_t = np.zeros_like(t)
    keep = was_slip & ~back
    # along the shear the solve needed to keep the slip along t
    new_t[:, to_slip] = qu[:, to_slip]
    new_t[:, keep] = np.where(qn[keep] > 0, qu[:, keep], t[:, keep])
    # a node coming into contact slips the way it moved relative to the indenter while it was
    # free (sticking there would hold it where it was at the last step: at a trailing edge, a
    # large shear on a vanishing pressure); it sticks at a later iteration if that reverses
    entered = new_contact & ~contact
    new_t[:, entered] = np.where(dsn[entered] > 0, dsu[:, entered], qdir[:, None])
    if not new_stick.any() and new_contact.any():
        # a stick zone narrower than a cell (below gross sliding: ``_gross_sets`` keeps its
        # own node); the node whose shear would balance the others' mu p t best (their sum
        # with it slipping too, and the load per cell ``load``) stands for it
        cand = np.flatnonzero(new_contact)
        slide = mu * np.where(new_contact, np.maximum(p, 0.0), 0.0) * new_t
        need = load[:, None] - slide.sum(axis=1)[:, None] + slide[:, cand]
        _, nn = _unit(need)
        j = cand[np.argmin(nn - mu * p[cand])]
        new_stick[j] = True
        new_t[:, j] = 0.0
    turn = 0.0
    if keep.any() and t.shape[0] > 1:  # (on a line the directions are +-1 and stay)
        # how far q is from |mu| p along the new direction, over |mu| p_max: the turn
        # |mu| p |dt| and the excess |q| - |mu| p (the shear across t makes |q| exceed |mu| p,
        # by its square; at the contact's edge, where p vanishes, neither moves any shear)
        # (gross sliding does not come here: t = Q/|Q| does not turn, and the excess of its
        # r = 0 rows is resolved only at the full inner tolerance; counted here, the settled
        # sets were solved again at the search tolerance for ever: the 1 N sphere at mu 0.02
        # on 512^2)
        dt = np.sqrt(((new_t - t) ** 2).sum(axis=0))[keep]
        turn = float(np.max(dt * p[keep])) / pmax
        turn = max(turn, float(np.max(excess[keep])) / max(mu * pmax, 1e-300))
    # the next solve's Newton term across t: the slip along the new direction (floored)
    newton = np.clip((new_t * ds).sum(axis=0), _NEWTON_FLOOR * dsn, dsn)
    return (new_contact, new_stick, new_t), newton, ds_scale, turn


def _start(g: SlipState, f, nd, qdir):
    """First sets and fields from the state ``g`` (the previous step or a guess)."""
    contact = g.contact.copy()
    if not contact.any():
        contact[int(np.argmin(f))] = True
    stick = g.stick & contact
    slipping = contact & ~stick
    t, tn = _unit(np.where(slipping, _directions(g, nd), 0.0))
    missing = slipping & (tn == 0)
    t[:, missing] = qdir[:, None]  # no direction yet: along Q (or +x)
    if not stick.any():
        j = np.flatnonzero(contact)[np.argmax(g.p[contact])]
        stick[j] = True
        t[:, j] = 0.0
    fields = (np.where(contact, g.p, 0.0), np.where(contact, _vec(g.q, nd), 0.0), float(g.d),
              _vec(g.delta, nd).copy())
    return (contact, stick, t), fields


def solve_slip_step(op: PartialSlipOperator, f: np.ndarray, prev: SlipState, P: float, Q,
                    mu: float, *, guess: SlipState | None = None, rtol: float = 1e-10,
                    search_rtol: float | None = _SEARCH_RTOL, accept: float = 1e-8,
                    max_outer: int = 200, max_krylov: int = 2000,
                    dir_tol: float | None = None, entry=None, balance: bool = True) -> SlipState:
    """One quasi-static load step from the state ``prev`` to the loads (P, Q) (dimensionless:
    forces in the core's units; Q a number on a line, (Q_x, Q_y) on a surface; ``f`` the
    indenter's heights above its apex, flat), Coulomb friction coefficient |mu|.

    guess : first sets and fields (default ``prev``; for the first step of a loading from
            nothing, e.g. a frictionless solution: its contact set, all stuck).
    search_rtol : the inner (GMRES) tolerance while the sets are searched; once they repeat,
            the solve is redone to ``rtol`` on them (and must confirm them).  Only the path
            changes, not what is accepted (None: ``rtol`` throughout).
    dir_tol : surfaces: the slip directions' convergence (see the module; default ``accept``).
    entry : the motion of each node relative to the indenter (``slip`` layout) made in this
            step before it touched, should it come into contact (``entry_motion``); it is not
            slip: a node entering contact sticks or slips from where it touched (None: from
            where it was at the previous step).
    balance : hold the loads exactly on the accepted solve (uniform shifts of p on the
            contact and of q on the stick nodes, of the order of the inner residual, and one
            product for the new displacements): equilibrium to round-off whatever ``rtol``.
            (Gross sliding's step is always made exact: ``_gross_finish``.)
    Returns the new state (its ``slip``: the accumulated slip delta - u relative to where each
    node was when it came into contact, 0 off the contact).  ConvergenceError if the sets do
    not settle or the final residual exceeds ``accept``.
    """
    nd = op.ndim
    mu = abs(float(mu))
    Qv = np.atleast_1d(np.asarray(Q, dtype=float)).reshape(nd)
    Qmag = float(np.sqrt((Qv * Qv).sum()))
    gross = Qmag >= mu * P * (1.0 - 1e-12)
    qdir = Qv / Qmag if Qmag > 0 else np.eye(nd)[0]
    dir_tol = accept if dir_tol is None else dir_tol
    u_prev, d_prev = _vec(prev.u, nd), _vec(prev.delta, nd)
    if entry is not None:  # (only nodes out of contact before: entry is 0 elsewhere)
        u_prev = u_prev - np.where(prev.contact, 0.0, _vec(entry, nd))
    sets, fields = _start(guess or prev, f, nd, qdir)
    if gross:
        sets = _gross_sets(sets, fields, mu, qdir)
    counters = {"fft": 0, "krylov": 0}
    seen = set()
    result = None
    rt = max(rtol, search_rtol or rtol)
    cautious = marginal = False
    cycles = 0
    slip_along = np.zeros(f.size)  # s . t of the last iteration (surfaces' Newton term)
    for outer in range(1, max_outer + 1):  # noqa: B007 (the count is reported after the loop)
        lin = _Linear(op, f, sets, (u_prev, d_prev), P, Qv, mu, gross, slip_along, fields[0])
        p, q, w, u, d, delta, rel = lin.solve(fields, rt, max_krylov)
        for k in counters:
            counters[k] += lin.counters[k]
        fields = (p, q, d, delta)
        gap = f - d + w
        new, (ds, slip_along, _), turn = _update(sets, (p, q, w, u, d, delta, gap), d_prev,
                                               u_prev, mu, gross, qdir, cautious,
                                               Qv / op.cell)
        same = np.array_equal(new[0], sets[0]) and np.array_equal(new[1], sets[1])
        if same and turn <= dir_tol and rel <= rtol:
            result = (p, q, w, u, d, delta, gap, ds, rel)
            break
        if same:
            # settled sets: the directions (a Newton iteration: the next solve's inner
            # tolerance follows their turn) and the inner tolerance, down to rtol
            seen.clear()
            sets = (sets[0], sets[1], new[2])
            rt = rtol if turn <= dir_tol else max(rtol, min(rt, turn))
            continue
        key = (new[0].tobytes(), new[1].tobytes())
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
            result = (p, q, w, u, d, delta, gap, ds, rel)
            break
        seen.add(key)
        sets = new
    if result is None:
        raise ConvergenceError(f"partial slip: the stick-slip sets did not settle in {max_outer} "
                               f"iterations (P = {P:.4g}, Q = {Q})", iterations=max_outer)
    if gross:
        sets, result = _gross_finish(op, f, sets, result, P, mu, qdir, u_prev, d_prev)
        counters["fft"] += op.m
    elif balance:
        result = _balance(op, f, sets, result, P, Qv, mu, u_prev, d_prev)
        counters["fft"] += op.m
    return _finish(op, prev, sets, result, P, Qv, mu, gross, accept, marginal, cycles,
                   outer, counters)


def _gross_stick(stick, contact, p):
    """Gross sliding's one stick node during the search: the kept one (``stick``, at most
    one node) while it stays in contact, else the contact node of largest p."""
    if stick.any():
        return stick
    out = np.zeros_like(contact)
    idx = np.flatnonzero(contact)
    if idx.size:
        out[idx[np.argmax(p[idx])]] = True
    return out


def _gross_sets(sets, fields, mu, qdir):
    """Gross sliding's first sets: the contact of ``sets``, one stick node (the most stuck of
    its stick set: the largest margin |mu| p - |q|) and every other contact node slipping
    along Q.  The node only closes the system (its stick row fixes delta for the search);
    the tractions do not depend on it and ``_gross_finish`` sets delta."""
    contact, stick, _ = sets
    p, q = fields[0], fields[1]
    idx = np.flatnonzero(stick)
    j = idx[np.argmax(mu * p[idx] - np.sqrt((q[:, idx] ** 2).sum(axis=0)))]
    one = np.zeros_like(stick)
    one[j] = True
    return contact, one, np.where(contact & ~one, qdir[:, None], 0.0)


def _gross_finish(op, f, sets, result, P, mu, qdir, u_prev, d_prev):
    """Gross sliding's accepted solve made exact: p shifted uniformly on the contact to hold P,
    q = |mu| p Q/|Q| on every contact node (Coulomb with the sum of q = |mu| P leaves no
    other shear: the stick zone is empty; this is ``solve``'s steady sliding state), (w, u) of
    these tractions (one product), and the indenter's displacement the least that lets no
    contact node slip against the shear: delta = delta_n + max over the contact of the
    surface's step along Q, u - u_n (the limit of the partial slip states as Q -> |mu| P,
    where the last stick node is the one that moved furthest along Q).  That node is the
    state's one stick node (its slip increment 0; every other one slips along Q, by >= 0).
    Returns (sets, result) as ``_balance``."""
    contact = sets[0]
    p, q, w, u, d, delta, gap, ds, rel = result
    cell = op.grid.cell
    C = np.flatnonzero(contact)
    p = p.copy()
    p[C] += (P - cell * p.sum()) / (cell * C.size)
    q = np.where(contact, mu * p, 0.0)[None] * qdir[:, None]
    w, uu = op.apply(p, q)
    u = np.reshape(uu, q.shape)
    du = u - u_prev
    j = C[np.argmax((qdir[:, None] * du[:, C]).sum(axis=0))]
    delta = d_prev + du[:, j]
    stick = np.zeros_like(contact)
    stick[j] = True
    t = np.where(contact & ~stick, qdir[:, None], 0.0)
    gap = f - d + w
    ds = (delta - d_prev)[:, None] - du
    return (contact, stick, t), (p, q, w, u, d, delta, gap, ds, rel)


def _balance(op, f, sets, result, P, Qv, mu, u_prev, d_prev):
    """The accepted solve with the loads held exactly: p shifted uniformly on the contact
    (and q = |mu| p t with it on the slip nodes), then q shifted uniformly on the stick nodes,
    the surface's (w, u) of the new tractions (one product).  The shifts are of the order of
    the inner solve's residual (the load rows are in its system), far below ``accept``: the
    inner tolerance can follow ``accept`` while equilibrium holds to round-off."""
    contact, stick, t = sets
    p, q, w, u, d, delta, gap, ds, rel = result
    cell = op.grid.cell
    C, S = np.flatnonzero(contact), np.flatnonzero(stick)
    L = np.flatnonzero(contact & ~stick)
    p = p.copy()
    q = q.copy()
    dp = (P - cell * p.sum()) / (cell * C.size)
    p[C] += dp
    q[:, L] += mu * dp * t[:, L]
    if S.size:
        q[:, S] += ((Qv - cell * q.sum(axis=1)) / (cell * S.size))[:, None]
    u_solved = u
    w, uu = op.apply(p, q)
    u = np.reshape(uu, q.shape)
    if S.size:  # the stick nodes held where they were on average: the indenter moves with
        # them (the shifts' smooth displacement, of the order of the inner residual, would
        # else show as slip; where the step barely slips, e.g. the normal loading, it reversed
        # the slip of a node just come into contact: the paper line, 16 loading steps on 1024
        # points, exit 3)
        delta = delta + (u[:, S] - u_solved[:, S]).mean(axis=1)
    gap = f - d + w
    ds = (delta - d_prev)[:, None] - (u - u_prev)
    return p, q, w, u, d, delta, gap, ds, rel


def _finish(op, prev, sets, result, P, Qv, mu, gross, accept, marginal, cycles, outer,
            counters) -> SlipState:
    """The accepted step: the residuals (max-norm, relative; ConvergenceError beyond
    ``accept``), the accumulated slip, the state in the grid's shapes."""
    nd, cell = op.ndim, op.grid.cell
    contact, stick, t = sets
    p, q, w, u, d, delta, gap, ds, rel = result
    off, slipn = ~contact, contact & ~stick
    # the friction law on the contact's nodes (p and q vanish elsewhere)
    C = np.flatnonzero(contact)
    dsC, pC, slipC = ds[:, C], p[C], slipn[C]
    _, dsn = _unit(dsC)
    qu, qn = _unit(q[:, C])
    pmax = max(float(p.max()), 1e-300)
    ds_scale = max(float(dsn.max()) if C.size else 0.0,
                   float(np.sqrt(((delta - _vec(prev.delta, nd)) ** 2).sum())), 1e-300)
    along = (qu * dsC).sum(axis=0)
    if nd == 1:  # reverse slip (over the step's largest slip in the contact)
        direction = float(max((-along)[slipC].max(), 0.0)) if slipC.any() else 0.0
    else:  # slip against the shear or off its direction (not at gross sliding: there the slip
        # is unbounded along Q, this step's finite increment is not its direction), weighed by
        # p / p_max as the Coulomb excess is (over |mu| p_max): the shear it misdirects
        direction = float(np.max((np.where(qn > 0, dsn - along, 0.0) * pC / pmax)[slipC])) \
            if slipC.any() and not gross else 0.0
    res = {
        "linear": rel,
        "penetration": float(max(-gap[off].min(), 0.0)) / max(abs(d), 1e-300) if off.any()
        else 0.0,
        "tension": float(max(-p.min(), 0.0)) / pmax,
        "coulomb": float(max((qn - mu * pC).max() if C.size else 0.0, 0.0))
        / max(mu * pmax, 1e-300),
        "slip_direction": direction / ds_scale,
        "load": abs(cell * p.sum() - P) / P,
        "tangential_load": float(np.sqrt(((cell * q.sum(axis=1) - Qv) ** 2).sum()))
        / max(mu * P, 1e-300),
    }
    friction = max(res["coulomb"], res["slip_direction"])
    worst = max(v for k, v in res.items() if k not in ("linear", "coulomb", "slip_direction"))
    limit = accept if nd == 1 else max(accept, _SURFACE_LAW)
    if friction > (_MARGINAL if marginal else limit):
        raise ConvergenceError(
            f"partial slip step (P = {P:.4g}, Q = {Qv}): the stick-slip sets "
            f"{'cycle' if marginal else 'settle'} with a friction-law violation {friction:.1e} "
            f"({'coulomb' if res['coulomb'] >= res['slip_direction'] else 'slip direction'})",
            residuals=[friction], iterations=outer)
    res["marginal_nodes"] = int(marginal)
    res["cycles"] = cycles
    if worst > accept:
        raise ConvergenceError(f"partial slip step (P = {P:.4g}, Q = {Qv}): residual "
                               f"{worst:.1e} > {accept:.0e} ({max(res, key=res.get)})",
                               residuals=[worst], iterations=outer)
    # accumulated slip: the previous one plus this step's increment, on nodes in contact
    # before and now; a node entering contact starts from 0
    old = _vec(prev.slip, nd) if prev.slip is not None else np.zeros_like(ds)
    slip = np.where(contact & prev.contact, old + ds, 0.0)
    p = np.where(contact, np.maximum(p, 0.0), 0.0)
    t = np.where(slipn, t, 0.0)
    info = dict(P=P, iterations=outer, krylov_iterations=counters["krylov"],
                fft_pairs=counters["fft"], residuals=res)
    if nd == 1:
        return SlipState(p=p, q=q[0], w=w, u=u[0], d=d, delta=float(delta[0]), contact=contact,
                         stick=stick, sigma=np.sign(t[0]).astype(np.int8), Q=float(Qv[0]),
                         slip=slip[0], **info)
    t = np.zeros_like(q)
    t[:, C] = np.where(slipC, qu, 0.0)
    s = SlipState2D(p=p, q=q, w=w, u=u, d=d, delta=delta, contact=contact, stick=stick,
                    sigma=np.zeros(p.size, dtype=np.int8), Q=float(np.hypot(*Qv)), slip=slip,
                    t=t, **info)
    s.shape = op.grid.shape
    return s


solve_slip_step_2d = solve_slip_step


def entry_motion(f: np.ndarray, s0: SlipState, s1: SlipState) -> np.ndarray:
    """The next step's motion relative to the indenter of each node out of contact at the
    state ``s1`` before it would touch, predicted from the last two states (equal steps): the
    fraction theta of the step before its gap closes (the gap continued linearly; theta in
    [0, 1], 1 where it is not closing) times the relative motion delta - u of the last step;
    0 on nodes in contact at s0 or s1.

    Without it a node coming into contact within a step is held from where it was at the
    step's start (its stick condition is no slip over the whole step, though it moved freely
    for part of it): an error of the order of the step in every node's locked-in shear, first
    order in the step overall.  Measured on the paper's frictional normal loading (2048
    points): the indentation's error at 10 steps 6.6e-3 -> 3.5e-3 (studies/README.md,
    onset).  ``solvers.onset_core`` uses it for the normal loading only: on the tangential
    steps after a frictional loading it made the tangential displacement's step error larger
    (the final one at 10/20/40/80 steps, 2048 points: 10.584/10.555/10.540/10.533 with it,
    10.534/10.531/10.528/10.527 without), though after a frictionless loading it made it
    about 10 x smaller."""
    nd = 1 if np.ndim(s1.q) == 1 else 2
    g0, g1 = f - s0.d + s0.w, f - s1.d + s1.w
    rate = g0 - g1  # the gap's closing over the last step
    theta = np.clip(np.divide(g1, rate, out=np.ones_like(g1), where=rate > 0), 0.0, 1.0)
    moved = (_vec(s1.delta, nd) - _vec(s0.delta, nd))[:, None] - (_vec(s1.u, nd) - _vec(s0.u, nd))
    out = np.where(s0.contact | s1.contact, 0.0, theta * moved)
    return out[0] if nd == 1 else out


def _worst(mask: np.ndarray, score: np.ndarray) -> np.ndarray:
    """``mask`` reduced to its node of largest ``score`` (all False if none)."""
    out = np.zeros_like(mask)
    idx = np.flatnonzero(mask)
    if idx.size:
        out[idx[np.argmax(score[idx])]] = True
    return out
