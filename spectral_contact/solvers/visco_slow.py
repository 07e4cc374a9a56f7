"""Slow sliding on a viscoelastic film by the first-order theory (issue 23).

At low speed the film's new scales are the edge layers, of width |V| tau_i, far below the
contact's and the film's lengths: a uniform periodic grid that resolves them costs up to 1000
times the elastic solve (a_H/h 0.1 at 1e-5 m/s: 2^22 points, 213 s against 0.3 s), although
their effect on the outputs is first order in |V| tau and known in closed form
(``ViscoelasticFilm.slow_shift``: found in Hunter's solution, ``reference.hunter``): the relaxed
elastic contact with the trailing edge moved toward the centre by |delta|, delta = V sum (E_i /
E_inf) tau_i, and the pressure translated by delta (a frictionless cylinder's by delta plus
the derived second-order centroid term, ``ViscoelasticFilm.slow_centroid_second_order``: the
centroid's remainder is then third order; the other outputs' second-order terms are not
derived and their bound stays).  When the second-order remainder
(``ViscoelasticFilm.slow_remainder``) is at most tol/4, the solve is the relaxed elastic one
(at tol; again at tol less the remainder where the remainder does not fit in what its estimate
left) plus that correction, with the remainder added to its error estimate (at most tol).
Otherwise the full viscoelastic solve runs.
"""
from __future__ import annotations

import dataclasses
import logging
import math
import time

import numpy as np

from ..numerics.grid import periodic_interpolator
from ..result import ContactResult

__all__ = ["slow_sliding", "edge_amplitudes"]

_log = logging.getLogger("spectral_contact.solvers.fft")

REMAINDER_SHARE = 0.25  # the largest share of tol the remainder may take (the theory's range)


EDGE_REACH = 0.3  # the edge fits' reach, in min(a, h)


def edge_amplitudes(x, p, edge, reach: float):
    """(A_1^2, A_2^2) of a line pressure ``p`` on nodes ``x`` whose contact is ``edge`` = (b1,
    b2): p = A_e sqrt(eps) + O(eps^{3/2}) at distance eps inside edge e, from p^2 fitted by a
    cubic in eps over the nodes with one cell < eps < max(``reach``, 12 cells) (its constant
    term takes up the edge's sub-cell error).  None when a side has fewer than 6 nodes.
    Against the same fit on 2^16-2^17 points (relaxed film, a_H/h 0.03-3): within 3.3 % at
    tol 1e-3, 1.5 % at 1e-4."""
    dx = x[1] - x[0]
    reach = max(reach, 12.0 * dx)
    out = []
    for e, sign in ((edge[0], -1.0), (edge[1], 1.0)):
        lo, hi = sorted((e - sign * dx, e - sign * reach))  # the nodes inside, within reach
        i, j = np.searchsorted(x, (lo, hi))  # (x ascending: the period's nodes in order)
        eps = sign * (e - x[i:j])
        if j - i < 6:
            return None
        out.append(float(np.polynomial.polynomial.polyfit(eps, p[i:j] ** 2, 3)[1]))
    return out[0], out[1]


def slow_sliding(scene, film, model: str, tol: float, solve_elastic):
    """The slow-sliding result of ``scene`` (a viscoelastic line), or None when the theory's
    remainder exceeds tol/4.  ``solve_elastic(scene, model, tol)``: the line solver.  (Where
    it applies it is also the cheaper solve: one elastic solve (two at most), against 0.8-2.4
    times its FFT pairs on grids up to 1000 times finer for the full one.)

    The elastic solve runs at tol first, the elastic solve of the same scene and tol (its
    grids and period exactly), and is kept when the remainder fits in what its estimate left
    of tol (the remainder is usually far below tol/4: 1e-6 at tol 1e-4 on the paper's scene
    at 1e-4 m/s); else once more at tol less the remainder (<= tol/4), so the estimate, the
    elastic one plus the remainder, is at most tol.  (Before: at 3 tol/4, whose grids could
    be others than the elastic solve's: the paper's scene at tol 1e-4, 16384 points against
    2048; at 9.9e-5 already 8192, its period 0.01 h longer: the estimates are not monotone
    in N, the edges falling elsewhere within their cells.)
    """
    P = scene.P
    if not (P > 0.0 and film.moving):
        return None
    # a screen before any solve: the remainder decreases with a, and the frictionless a is
    # below a_bound (friction widens it: a case the screen may send to the full solve)
    a_bound = min(math.sqrt(P / (2.0 * math.pi)), (3.75 * P) ** 0.2)
    rem = film.slow_remainder(a_bound)
    if rem > REMAINDER_SHARE * tol:
        return None
    t0 = time.perf_counter()
    relaxed = dataclasses.replace(scene, speed=0.0, prony=())
    rem = 0.0
    spent = {}  # the work of every elastic solve run (two: the first's counted too)
    for _ in range(2):
        el = solve_elastic(relaxed, model, tol - rem)
        for k, v in el.counters.items():
            spent[k] = spent.get(k, 0) + v
        a = el.half_width
        rem = film.slow_remainder(a)
        if not (a > 0.0 and rem <= REMAINDER_SHARE * tol):
            return None
        if el.error_estimate + rem <= tol:
            break
    else:
        return None  # (the remainder moved with a past what the second solve left)
    delta = film.slow_shift
    edges = sorted(tuple(e) for e in (el.info.get("edges") or ()))
    # the centroid's second-order term (frictionless cylinder: the energy identity,
    # ViscoelasticFilm.slow_centroid_second_order); the pressure fields move with it
    x2 = 0.0
    if (scene.mu == 0.0 or model == "goodman") and scene.height is None and len(edges) == 1:
        amp = edge_amplitudes(el.x, el.pressure, edges[0], EDGE_REACH * min(a, film.thickness))
        if amp is not None:
            x2 = film.slow_centroid_second_order(sum(amp), float(np.sum(el.pressure))
                                                 * (el.x[1] - el.x[0]))
    _log.info("viscoelastic line, slow sliding: the relaxed elastic solve with the first-order "
              "correction (shift %.3g h, remainder %.1e)", delta, rem)
    x, L = el.x, el.domain_length
    # f(x - delta - x2) on the same periodic grid (linear: sums kept exactly): np.interp's
    # periodic interpolation, its sort and normalisation done once for the fields
    shifted = periodic_interpolator(x - delta - x2, x, L)

    P_el = float(np.sum(el.pressure))
    if (scene.mu == 0.0 or model == "goodman") and scene.height is None:
        m_el = el.center  # a symmetric elastic contact: its centroid is its (averaged) centre
    else:  # (the final grid's centroid)
        m_el = el.info.get("pressure_centroid", float(np.dot(el.pressure, x)) / P_el)
    if edges:  # the trailing edge moves in by |delta|; the leading one stays
        if delta > 0:
            edges[0] = (edges[0][0] + delta, edges[0][1])
        else:
            edges[-1] = (edges[-1][0], edges[-1][1] + delta)
    est = el.error_estimate + rem
    parts = dict(el.info.get("estimate_parts", {}))
    parts["slow_sliding_remainder"] = rem
    info = dict(el.info) | {
        "edges": edges, "pressure_centroid": m_el + delta + x2, "tail_length": film.tail_length,
        "estimate_parts": parts, "tolerance_met": bool(est <= tol),
        "slow_sliding": {"shift_h": delta, "remainder": rem, "centroid_second_order_h": x2,
                         "elastic_error_estimate": el.error_estimate}}
    if "fft_pairs" in info:  # (the work of both elastic solves, as ``counters``)
        info["fft_pairs"] = spent.get("transforms", info["fft_pairs"])
    if "krylov_iterations" in info:
        info["krylov_iterations"] = spent.get("linear_iterations", info["krylov_iterations"])
    return ContactResult(
        scene=scene, model=el.model, method=el.method, x=x, pressure=shifted(el.pressure),
        base_sigma_zz=shifted(el.base_sigma_zz), base_sigma_xz=shifted(el.base_sigma_xz),
        half_width=a - 0.5 * abs(delta), center=el.center + 0.5 * delta,
        indentation=el.indentation, max_pressure=el.max_pressure,
        max_pressure_x=el.max_pressure_x + delta + x2, grid_points=el.grid_points,
        domain_length=L, iterations=el.iterations, residual=el.residual, error_estimate=est,
        wall_time_s=time.perf_counter() - t0 - el.plan_time_s,
        plan_time_s=el.plan_time_s, info=info, counters=spent,
        shear=None if el.shear is None else shifted(el.shear))
