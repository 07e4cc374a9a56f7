"""An adversarial audit of the viscoelastic solver's error estimates (tenth session).

    python -m studies.viscoelastic_audit [--quick] [--out DIR] [--scenes N] [--seed S]
                                         [--workers W] [--timeout SECONDS] [--only I,J,...]

The claim under audit (README, "Viscoelastic film"): every result's ``error_estimate`` bounds
its true relative error in the controlled measures, or the solve is refused (InputError /
ConvergenceError) -- never a silent wrong answer.  Lines: half-width a, contact centre x_c,
indentation d, p_max, pressure centroid (lengths over a, d and p_max over themselves,
``studies.viscoelastic._line_changes``); surfaces: contact radius sqrt(A/pi), pressure
centroid (over the radius), indentation, p_max, line load at y = 0 (over themselves); the x
extents against ``info["extent_error_estimate"]`` (not controlled by tol).

Scenes (``--scenes N``, default 60; seeded, ``--seed``, default 10): random choices a user
would plausibly make that the earlier parts of studies.viscoelastic did not sweep: 1-3 Prony
terms with tau_i log-uniform in 1e-4 ... 10 s (at least half a decade apart) and weights
E_i/E_inf log-uniform in 0.05 ... 10 (the verified range per term); the speed near where
|V| tau_i ~ the contact's half-width for one term (a factor 10^U(-1.5, 1.5)), or log-uniform
1e-5 ... 1 m/s, |V| in [1e-6, 3] m/s, a random sign; mu in {0, 0.5, 2} signed like V; lines
(3 in 4) of Hertz half-width a_H/h log-uniform 0.05 ... 3, tol 1e-2, 1e-3, 1e-4; the sphere
(force log-uniform 0.2 ... 3 N, mu 0 or 0.5), tol 1e-2, 1e-3.  Film h = 2 mm, E_inf = 2.2 MPa,
R = 130 mm.

Per scene (each in a forked child, ``--timeout`` s, default 420):
- the automatic solve at tol (refused: a row saying so; that keeps the claim);
- two references.  Lines: A = 2^20 points over twice the solve's period (2^18 with --quick;
  where that fine grid's active set does not settle, 2^21 points on the solve's period, then
  2^19 on twice it: ``ref_A``), B = the automatic solve at tol/10 (its own period and path;
  if refused, 2^21 points on twice the period).  Surfaces: A = 4x the cells per axis on the solve's period (capped at
  2^23 points), B = the automatic solve at tol/10 for tol 1e-2, else 4x cells along x and 2x
  along y on twice the period along x;
- ``true_error`` = the error against A; ``status``: "bounded" (against A and B), "OVER"
  (against both), "inconclusive" (one says bounded, the other over), "refused", "no
  reference", "timeout"; ``ref_spread``: A against B (the references' own disagreement);
- sanity: |Q_over_P - (mu + deformation_friction)|; the mirrored scene (V -> -V, mu -> -mu)
  at the same tol: a, d, p_max equal and x_c, centroid, mu_def negated (``mirror_change``,
  relative as the estimate's measures; lines and tol 1e-2 spheres);
- limits (lines, first term's scene only with ``limits``): speed 1e-12 m/s against the
  relaxed elastic solve (E_inf) and |V| tau_min = 1e7 h against the glassy one (E_inf + sum
  E_i), the change against the sum of both estimates (``limit_slow_ratio``,
  ``limit_fast_ratio``: <= 1 expected).
"""
from __future__ import annotations

import math
import sys
import time
import warnings

import numpy as np

from spectral_contact import solve
from spectral_contact.errors import ConvergenceError, InputError

from ._common import parse, progress, table
from .viscoelastic import FILM, _in_child, _line_changes, load_for

E_INF = FILM["young"]
H = FILM["thickness"]
SPHERE_MEASURES = ("contact_radius_m", "pressure_centroid_x_m", "indentation_m",
                   "max_pressure_Pa", "line_load_y0_N_per_m")
SPHERE_EXTENTS = ("contact_x_min_m", "contact_x_max_m")
LINE_NAMES = ("a", "x_c", "d", "p_max", "centroid")


def _sphere_changes(d, ref, keys) -> list:
    """Relative changes of ``keys`` from ``ref`` to ``d``: lengths over the reference's radius,
    d, p_max and the line load over themselves."""
    rad = ref["contact_radius_m"]
    own = ("indentation_m", "max_pressure_Pa", "line_load_y0_N_per_m")
    return [abs(d[k] - ref[k]) / (abs(ref[k]) if k in own else rad) for k in keys]


def scenes(n: int, seed: int, quick: bool) -> list[dict]:
    """``n`` seeded random scenes (module docstring); each a dict of solve's keywords plus
    ``kind``, ``a_h`` (lines: the Hertz half-width in h) and ``limits``."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        sphere = rng.random() < 0.25
        nterms = int(rng.integers(1, 4))
        while True:  # taus at least half a decade apart
            lt = np.sort(rng.uniform(-4.0, 1.0, nterms))
            if nterms == 1 or np.min(np.diff(lt)) >= 0.5:
                break
        taus = 10.0 ** lt
        weights = 10.0 ** rng.uniform(math.log10(0.05), 1.0, nterms)
        prony = tuple((float(E_INF * w), float(t)) for w, t in zip(weights, taus))
        if sphere:
            force = float(10.0 ** rng.uniform(math.log10(0.2), math.log10(3.0)))
            a_h = 1.2 * (force / 1.0) ** (1.0 / 3.0)  # rough contact radius in h
            mu = float(rng.choice([0.0, 0.5]))
            tol = float(rng.choice([1e-2, 1e-3]))
        else:
            a_h = float(10.0 ** rng.uniform(math.log10(0.05), math.log10(3.0)))
            mu = float(rng.choice([0.0, 0.5, 2.0]))
            tol = float(rng.choice([1e-2, 1e-3, 1e-4]))
        if rng.random() < 0.7:  # |V| tau_i ~ the contact's half-width for one term
            j = int(rng.integers(nterms))
            V = a_h * H / taus[j] * 10.0 ** rng.uniform(-1.5, 1.5)
        else:
            V = 10.0 ** rng.uniform(-5.0, 0.0)
        V = float(min(max(V, 1e-6), 3.0))
        sign = -1.0 if rng.random() < 0.5 else 1.0
        kw = dict(speed=sign * V, prony=prony, mu=sign * mu or 0.0, tol=tol, **FILM)
        if sphere:
            kw |= dict(indenter="sphere", force=force)
        else:
            kw |= dict(load=float(load_for(a_h)))
        out.append({"i": i, "kind": "sphere" if sphere else "line", "a_h": a_h, "kw": kw,
                    "limits": (not sphere) and i % 3 == 0})
    return out


def call(kw: dict) -> str:
    """The scene's reproduction call."""
    args = ", ".join(f"{k}={v!r}" for k, v in kw.items() if k not in FILM)
    return f"solve({args}, young=2.2e6, thickness=0.002, radius=0.13)"


def _line_measures(r) -> dict:
    return {"a": r.half_width, "x_c": r.center, "d": r.indentation, "p_max": r.max_pressure,
            "centroid": r.info["pressure_centroid"]}


def _si_changes(r, ref) -> list:
    """Relative changes of a, x_c (over a), d and p_max from ``ref`` to ``r``, in SI (films of
    different moduli: different units); elastic solves carry no pressure centroid."""
    d, e = r.to_dict(), ref.to_dict()
    a = e["half_width_m"]
    return [abs(d["half_width_m"] - a) / a, abs(d["contact_center_m"] - e["contact_center_m"]) / a,
            abs(d["indentation_m"] - e["indentation_m"]) / abs(e["indentation_m"]),
            abs(d["max_pressure_Pa"] - e["max_pressure_Pa"]) / e["max_pressure_Pa"]]


def _mirror_change_line(r, m) -> float:
    a = r.half_width
    return max(abs(m.half_width - a) / a, abs(m.center + r.center) / a,
               abs(m.indentation - r.indentation) / abs(r.indentation),
               abs(m.max_pressure - r.max_pressure) / r.max_pressure,
               abs(m.info["pressure_centroid"] + r.info["pressure_centroid"]) / a)


def _solve_or_refused(kw: dict):
    """(result, None), or (None, the row of a refused solve: the claim kept)."""
    try:
        return solve(**kw), None
    except (InputError, ConvergenceError) as exc:
        return None, {"refused": type(exc).__name__ + ": " + str(exc).splitlines()[0][:100]}


def audit_line(sc: dict, quick: bool) -> dict:
    kw = sc["kw"]
    tol = kw["tol"]
    row: dict = {}
    r, refused = _solve_or_refused(kw)
    if refused:
        return refused
    d = r.to_dict()
    row |= {"grid_points": r.grid_points, "period_h": r.domain_length,
            "error_estimate": r.error_estimate, "estimate_over_tol": r.error_estimate / tol,
            "tolerance_met": bool(r.tolerance_met),
            "path": "slow" if "slow_sliding" in r.info else "full",
            "edge_structure_resolved": bool(r.info.get("edge_structure_resolved")),
            "mu_def": d["deformation_friction"],
            "QP_identity": abs(d["Q_over_P"] - (kw["mu"] + d["deformation_friction"]))}
    L = 2.0 * r.domain_length * H
    nA = 2**18 if quick else 2**20
    refA = None
    # (fine fixed grids of heavy films may not settle: the ninth session's wandering active
    # set; then 2^21 points on the solve's own period, then 2^19 on twice it)
    for n_ref, L_ref in ((nA, L), (2 * nA, L / 2), (nA // 2, L)):
        try:
            refA = solve(**kw, grid_points=n_ref, domain_length=L_ref)
            row["ref_A"] = f"{n_ref} on {'2L' if L_ref == L else 'L'}"
            break
        except ConvergenceError as exc:
            last = exc
    if refA is None:
        raise last
    try:
        refB = solve(**kw | {"tol": tol / 10.0})
        row["ref_B"] = f"auto tol {tol / 10:g}, N {refB.grid_points}"
    except (InputError, ConvergenceError) as exc:
        row["ref_B_refused"] = type(exc).__name__
        refB = solve(**kw, grid_points=2 * nA, domain_length=L)
        row["ref_B"] = f"{2 * nA} on 2L"
    eA, eB = _line_changes(r, refA), _line_changes(r, refB)
    row |= {"true_error": max(eA), "carrier": LINE_NAMES[eA.index(max(eA))],
            "true_error_B": max(eB), "ref_spread": max(_line_changes(refA, refB)),
            "ref_A_estimate": refA.error_estimate}
    row |= {f"err_{n}": e for n, e in zip(LINE_NAMES, eA)}
    m = solve(**kw | {"speed": -kw["speed"], "mu": -kw["mu"]})
    row["mirror_change"] = _mirror_change_line(r, m)
    row["mirror_mu_def"] = abs(m.to_dict()["deformation_friction"] + d["deformation_friction"])
    if sc["limits"]:
        el0 = {k: v for k, v in kw.items() if k not in ("speed", "prony")}
        E0 = E_INF + sum(e for e, _ in kw["prony"])
        tmin = min(t for _, t in kw["prony"])
        sgn = math.copysign(1.0, kw["speed"])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the inertia flag at the fast limit
            slow = solve(**kw | {"speed": sgn * 1e-12})
            relaxed = solve(**el0)
            fast = solve(**kw | {"speed": sgn * 1e7 * H / tmin})
            glassy = solve(**el0 | {"young": E0})
        # in SI (the glassy film's units differ): a, x_c (over a), d, p_max (over themselves)
        ch_slow, ch_fast = _si_changes(slow, relaxed), _si_changes(fast, glassy)
        row["limit_slow_ratio"] = max(ch_slow) / (slow.error_estimate + relaxed.error_estimate)
        row["limit_fast_ratio"] = max(ch_fast) / (fast.error_estimate + glassy.error_estimate)
    return row


def audit_sphere(sc: dict, quick: bool) -> dict:
    kw = sc["kw"]
    tol = kw["tol"]
    row: dict = {}
    r, refused = _solve_or_refused(kw)
    if refused:
        return refused
    d = r.summary()
    (nx, ny), (Lx, Ly) = r.grid_points, r.domain_length
    row |= {"grid_points": f"{nx}x{ny}", "period_h": f"{Lx:.3g}x{Ly:.3g}",
            "error_estimate": r.error_estimate, "estimate_over_tol": r.error_estimate / tol,
            "tolerance_met": bool(d["tolerance_met"]), "mu_def": d["deformation_friction"],
            "QP_identity": abs(d["Q_over_P"] - (kw["mu"] + d["deformation_friction"]))}
    cap = 2**20 if quick else 2**23
    k = 4 if 16 * nx * ny <= cap else 2
    refA = solve(**kw, grid_points=(k * nx, k * ny), domain_length=(Lx * H, Ly * H)).summary()
    if tol >= 1e-2:
        try:
            rb = solve(**kw | {"tol": tol / 10.0})
            refB = rb.summary()
            row["ref_B"] = f"auto tol {tol / 10:g}, N {rb.grid_points}"
        except (InputError, ConvergenceError) as exc:
            refB = None
            row["ref_B"] = "refused: " + type(exc).__name__
    else:
        refB = None
    if refB is None:
        n2 = (k * nx, max(32, k * ny // 2))
        refB = solve(**kw, grid_points=n2, domain_length=(2 * Lx * H, Ly * H)).summary()
        row["ref_B"] = row.get("ref_B", "") + f" {n2[0]}x{n2[1]} on 2Lx"
    row["ref_A"] = f"{k * nx}x{k * ny}"
    eA, eB = _sphere_changes(d, refA, SPHERE_MEASURES), _sphere_changes(d, refB, SPHERE_MEASURES)
    names = ("radius", "centroid", "d", "p_max", "line_load")
    row |= {"true_error": max(eA), "carrier": names[eA.index(max(eA))],
            "true_error_B": max(eB),
            "ref_spread": max(_sphere_changes(refA, refB, SPHERE_MEASURES))}
    row |= {f"err_{n}": e for n, e in zip(names, eA)}
    ext = max(_sphere_changes(d, refA, SPHERE_EXTENTS))
    row |= {"extent_estimate": r.info["extent_error_estimate"], "extent_error": ext,
            "extent_bounded": bool(ext <= r.info["extent_error_estimate"])}
    if tol >= 1e-2:
        m = solve(**kw | {"speed": -kw["speed"], "mu": -kw["mu"]}).summary()
        rad = d["contact_radius_m"]
        row["mirror_change"] = max(
            [abs(m[q] - d[q]) / abs(d[q]) for q in ("contact_radius_m", "indentation_m",
                                                   "max_pressure_Pa", "line_load_y0_N_per_m")]
            + [abs(m["pressure_centroid_x_m"] + d["pressure_centroid_x_m"]) / rad])
        row["mirror_mu_def"] = abs(m["deformation_friction"] + d["deformation_friction"])
    return row


def audit(sc: dict, quick: bool) -> dict:
    """The scene's row; a reference refused or not converged raises (the row: "no
    reference"); any other exception is a row, not a silent child."""
    try:
        return (audit_sphere if sc["kind"] == "sphere" else audit_line)(sc, quick)
    except (InputError, ConvergenceError):
        raise
    except Exception as exc:  # noqa: BLE001 (recorded: a crash is a finding)
        return {"crash": f"{type(exc).__name__}: {exc}"[:120]}


def _status(row: dict) -> str:
    est = row["error_estimate"]
    a, b = row["true_error"] <= est, row["true_error_B"] <= est
    return "bounded" if a and b else "OVER" if not (a or b) else "inconclusive"


def run(sc: dict, quick: bool, timeout: float) -> dict:
    kw = sc["kw"]
    terms = kw["prony"]
    row = {"i": sc["i"], "kind": sc["kind"], "tol": kw["tol"], "speed_m_per_s": kw["speed"],
           "mu": kw["mu"], "load": kw.get("load", kw.get("force")),
           "a_h": sc["a_h"], "n_terms": len(terms),
           "weights": " ".join(f"{e / E_INF:.3g}" for e, _ in terms),
           "taus_s": " ".join(f"{t:.3g}" for _, t in terms),
           "V_tau_over_a": " ".join(f"{abs(kw['speed']) * t / H / sc['a_h']:.3g}"
                                    for _, t in terms)}
    t = time.perf_counter()
    status, value = _in_child(lambda: audit(sc, quick), timeout)
    row["wall_s"] = time.perf_counter() - t
    if status == "ok" and "refused" in value:
        row["status"] = "refused: " + value["refused"]
    elif status == "ok" and "crash" in value:
        row["status"] = "CRASH: " + value["crash"]
    elif status == "ok":
        row |= value
        row["ratio"] = row["true_error"] / row["error_estimate"]
        row["status"] = _status(row)
    elif status == "refused":  # raised by a reference: no verdict on the claim
        row["status"] = "no reference: " + value
    else:
        row["status"] = f"timeout after {value:.0f} s"
    row["call"] = call(kw)
    return row


COLUMNS = ("i", "kind", "tol", "speed_m_per_s", "mu", "load", "a_h", "n_terms", "weights",
           "taus_s", "V_tau_over_a", "grid_points", "period_h", "path",
           "edge_structure_resolved", "error_estimate", "estimate_over_tol", "tolerance_met",
           "true_error", "true_error_B", "ratio", "carrier", "ref_spread", "ref_B", "ref_A",
           "ref_A_estimate", "err_a", "err_x_c", "err_d", "err_p_max", "err_centroid",
           "err_radius", "err_line_load", "extent_estimate", "extent_error", "extent_bounded",
           "mu_def", "QP_identity", "mirror_change", "mirror_mu_def", "limit_slow_ratio",
           "limit_fast_ratio", "wall_s", "status", "call")


def main(argv=None) -> int:
    def extra(p):
        p.add_argument("--scenes", type=int, default=60, help="number of scenes (default 60)")
        p.add_argument("--seed", type=int, default=10, help="the scenes' seed (default 10)")
        p.add_argument("--timeout", type=float, default=420.0,
                       help="seconds per scene, its references included (default 420)")
        p.add_argument("--only", default="", help="comma list of scene indices to run alone")
        p.add_argument("--jobs", type=int, default=1, help="scenes run at once (default 1)")

    args, out = parse(argv, __doc__.splitlines()[0], "out/viscoelastic_audit", extra=extra)
    if args.scenes < 1 or args.jobs < 1:
        print("--scenes and --jobs must be >= 1", file=sys.stderr)
        raise SystemExit(2)
    todo = scenes(args.scenes, args.seed, args.quick)
    if args.quick:  # the first two lines at tol >= 1e-3 and the first sphere at tol 1e-2
        lines = [s for s in todo if s["kind"] == "line" and s["kw"]["tol"] >= 1e-3][:2]
        todo = lines + [s for s in todo if s["kind"] == "sphere" and s["kw"]["tol"] >= 1e-2][:1]
    if args.only:
        keep = {int(v) for v in args.only.split(",")}
        todo = [s for s in todo if s["i"] in keep]
    t0 = time.perf_counter()
    rows = []

    done = []  # (scenes finished: the progress count, also from --jobs threads)

    def one(sc):
        row = run(sc, args.quick, args.timeout)
        done.append(sc["i"])
        progress(len(done), len(todo), f"#{sc['i']} {sc['kind']} tol {sc['kw']['tol']:g} "
                 f"V {sc['kw']['speed']:.2g}: {row['status'][:50]} "
                 f"{row.get('true_error', math.nan):.2g} / "
                 f"{row.get('error_estimate', math.nan):.2g}", t0)
        return row

    if args.jobs == 1:
        for sc in todo:
            rows.append(one(sc))
    else:
        from concurrent.futures import ThreadPoolExecutor  # each scene is its own child process

        with ThreadPoolExecutor(args.jobs) as ex:
            for row in ex.map(one, todo):
                rows.append(row)
    rows = [{c: row.get(c, math.nan if c not in ("status", "call") else "") for c in COLUMNS}
            for row in rows]
    table(rows, out / "viscoelastic_audit.csv",
          f"viscoelastic audit (seed {args.seed}): the automatic solve's estimate against its "
          f"true error (reference A: lines 2^20 points on twice the period, spheres 4x cells per "
          f"axis), reference B as said; status bounded/OVER/inconclusive/refused/timeout")
    st = [r["status"] for r in rows]
    print(f"{st.count('bounded')} bounded, {st.count('OVER')} OVER, "
          f"{st.count('inconclusive')} inconclusive, "
          f"{sum(s.startswith('refused') for s in st)} refused, "
          f"{sum(s.startswith('timeout') for s in st)} timeout, of {len(rows)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
