"""Peers: the frictionless contact against ContactMechanics and tamaas, on the same grid.

    python -m studies.peers [--quick] [--surfaces] [--out DIR]

The peers are optional (``pip install contactmechanics tamaas``); each one that is missing is
reported "absent" and the study still does what it can (exit status 0).

Four cases, frictionless (mu_d = 0: neither peer has Amontons coupling):

A. "film": the paper's scene at mu_d = 0 (a/h_hertz = 1.68), the film on its rigid base.
   Peer: ContactMechanics ``PeriodicFFTElasticHalfSpace`` with ``thickness`` = h (Carbone &
   Mangialardi's layer on a rigid flat) and poisson = 1/2 - 1e-8 (its q = 0 stiffness is
   E (1-nu)/((1-2nu)(1+nu)) / h, infinite at nu = 1/2; ours is H(0) = 0).  Its finite-thickness
   Green's function is implemented for 2D grids only (a 1D grid ignores ``thickness``: it is
   the half-space line contact), so the film runs on a y-invariant strip of ny = 1 point (one
   qy = 0 mode: exactly the line contact) of unit length in y, with the load per unit length.
   With nu -> 1/2 its layer factor (3-4nu) cosh 2q + 2q^2 + ... is the paper's D/(sinh 2k - 2k)
   = 1/F0, so the two compliances are the same symbol.
C. "film nu": the paper's scene at mu_d = 0 on a compressible film (nu = 0.3, 0.4; 0.3 only
   with --quick): ContactMechanics' layer with poisson = nu and E = 2G(1 + nu), G = 1 (its
   normal compliance is ours to 7e-16, k = 0 included: tests/test_compressible.py).
B. "thick film vs half-space": a/h_hertz = 0.02 (0.05 with --quick).  Peers: tamaas
   ``model_type.basic_1d`` (1D periodic half-space, plane strain: Westergaard kernel) with its
   Polonsky-Keer-Rey solver, and ContactMechanics on a 1D grid (half-space).  They solve the
   half-space, we solve the film: the expected difference is the film's, ~0.5 (a/h)^2 in a.

D. "fixed grids" (issue 13's targets, ``fixed_grid_comparison``; what studies.benchmark runs):
   N = 2^12, 2^14, 2^16 (2^12 with --quick) on the period of case A, the paper's load, two
   operators, each the same symbol for every solver: the film (ours; tamaas' PKR with the film's
   symbol registered from Python as a ``tamaas.IntegralOperator`` subclass; ContactMechanics'
   layer) and its half-space limit (ours through ``Film(thickness=1e12)``, whose symbol is
   1/(2|k|) to the last bit; tamaas' own Westergaard operator and, 2.5-3x faster, the same symbol
   registered from Python; ContactMechanics 1D).  tamaas runs on one thread, as ours.  Equal
   accuracy: each solver at the loosest decade of its own tolerance whose pressure is within
   1e-6 max p of ours at rtol 1e-13; medians of interleaved warm runs of the solve call; ours
   also in FFT-pair times of that N.  A target compares us with each peer's fastest
   configuration.  Writes peers_fixed.csv.

E. "surfaces" (issue 25, ``surface_comparison``): the frictionless sphere of the 3D speed
   target (F = 1 N, R = 130 mm on the paper's film: a ~ 1.3 h) on N x N grids (256^2, 1024^2;
   256^2 with --quick) over a 30 mm period, two operators as in D: the film (ours; tamaas'
   PKR on a basic_2d model with the film's symbol registered from Python; ContactMechanics'
   2D layer, nu = 1/2 - 1e-8) and the half-space (ours through ``HALF_SPACE``; tamaas'
   Westergaard and the same symbol from Python; ContactMechanics' 2D half-space).  Equal
   accuracy and timing as D; ours is the core fixed-grid solve (``solve_contact``, cold).
   Writes peers_surface.csv; ``surface_targets`` gives the ">= 5x tamaas at 1024^2" rows.
   ``--surfaces`` runs this case only.

Same scene, same grid (cases A-C): our automatic solve at ``tol`` fixes the period L and the number of
points N (its final level); every solver, ours included (``numerics.contact.solve_contact``,
cold start), then solves on that grid.  Units: ours (lengths h, stresses E h/6R = G h/2R,
displacements h^2/2R, profile x^2): E = 3, nu = 1/2 (E* = 4) for the peers, so that all
compliances are F0/(2|k|) (film) or 1/(2|k|) (half-space).

Convergence: each solver's own test, set to ~1e-10 relative (ours: GMRES/active-set rtol 1e-10;
ContactMechanics: pentol = 1e-10 d, forcetol = 1e-10 p_max dx, thermotol = 1e-10; tamaas:
tolerance 1e-10 on its own error).  Because those tests differ, one common measure is also
reported for every solution: ``residual`` = the largest of the gap on the contact nodes, the
penetration off it (both / the indentation) and the load error, computed with the solver's own
operator (film or half-space symbol) from its pressure.  Time: median of 3 warm runs of the
solve call only; iterations: ours active-set (GMRES matvecs), ContactMechanics CG iterations,
tamaas PKR iterations (read from its log).  Ours starts from its default Hertz guess,
the peers from zero (their defaults).  Compared: half-width from the contact nodes
(N_contact dx / 2, the same rule for all; ours also sub-grid), peak pressure, and
max |p - p_ours| / max p_ours.  Writes peers.csv, peers.png and peers_fixed.csv.
"""
from __future__ import annotations

import math
import os
import re
import sys
import tempfile
import time

import numpy as np

from spectral_contact import Scene, solve
from spectral_contact.numerics.contact import solve_contact
from spectral_contact.numerics.fft import get_rfft
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.film import Film, surface_compliance
from spectral_contact.physics.indenters import Cylinder
from spectral_contact.reference.hertz import hertz_half_width, hertz_pressure

from ._common import parse, progress, table

RTOL = 1e-10
REPEATS = 3
CM_INCOMPRESSIBLE_POISSON = 0.5 - 1e-8
"""ContactMechanics' layer needs nu < 1/2: at 1/2 - 1e-8 its symbol is the incompressible
film's to 7e-7 for k > 0 (pressures agree to ~7e-8 of p_max; at 0.499999, 7e-5 and 1.9e-5); its
k = 0 compliance 2e-8 only shifts the indentation.  Closer to 1/2 (1/2 - 1e-10: k = 0 stiffness
5e9) its constrained CG stopped after one step at a uniform pressure on case B's grid."""


def peers_available() -> dict:
    """name -> version string, or 'absent (reason)'."""
    out = {}
    try:
        import ContactMechanics

        out["ContactMechanics"] = _dist_version("ContactMechanics", ContactMechanics)
    except Exception as exc:  # ImportError or a broken install: report, never fail
        out["ContactMechanics"] = f"absent ({type(exc).__name__}: {exc})"
    try:
        import tamaas

        out["tamaas"] = _dist_version("tamaas", tamaas)
    except Exception as exc:
        out["tamaas"] = f"absent ({type(exc).__name__}: {exc})"
    return out


def _dist_version(dist: str, module) -> str:
    """The installed distribution's version (ContactMechanics' own ``__version__`` can report
    the git state of the current directory instead)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(dist)
    except PackageNotFoundError:
        return getattr(module, "__version__", "?")


def present(versions, name) -> bool:
    return not versions[name].startswith("absent")


def scene_for(s: float, mu: float, base: Scene = Scene()) -> Scene:
    P = 2 * math.pi * s**2
    return base.with_(load=P * base.stress_unit * base.length_unit, mu=mu)


def common_residual(grid: Grid, p: np.ndarray, P: float, symbol: np.ndarray) -> float:
    """The same convergence measure for every solution: gap on the contact nodes and penetration
    off them (relative to the indentation), load error; with the operator ``symbol`` (w^ =
    symbol p^, the sinking).  The profile is |x|^2 (lines: x^2; surfaces: x^2 + y^2)."""
    w = get_rfft(grid.shape).apply(p, symbol)
    f = sum(a**2 for a in np.meshgrid(*grid.axes, indexing="ij"))
    act = p > 0
    if not act.any():
        return float("inf")
    d = float(np.mean((f + w)[act]))
    g = f + w - d
    scale = max(abs(d), 1e-300)
    gap = float(np.max(np.abs(g[act]))) / scale
    pen = float(max(0.0, -g[~act].min(initial=0.0))) / scale
    load = abs(float(np.sum(p)) * grid.cell - P) / P
    return max(gap, pen, load)


def halfspace_symbol(grid: Grid) -> np.ndarray:
    k = grid.k
    s = np.zeros_like(k)
    s[1:] = 1.0 / (2.0 * k[1:])
    return s


def _row(case, solver, version, grid, P, p, t, its, cost, symbol, p_ref, a_sub=float("nan"),
         t_ref=None, p_hertz=None, note=""):
    dx = grid.dx
    return {
        "case": case, "solver": solver, "version": version, "N": grid.n, "L_h": grid.length,
        "time_ms": 1e3 * t, "time_ratio": (t / t_ref) if t_ref else (1.0 if t == t else t),
        "iterations": its, "fft_pairs": cost,
        "a_nodes": float(np.count_nonzero(p > 0) * dx / 2), "a_subgrid": a_sub,
        "p_max": float(p.max()), "dp_rel": float(np.max(np.abs(p - p_ref)) / p_ref.max()),
        "dp_hertz": (float(np.max(np.abs(p - p_hertz)) / p_hertz.max()) if p_hertz is not None
                     else float("nan")),
        "residual": common_residual(grid, p, P, symbol), "note": note,
    }


# --- solvers on a given grid: each a runner doing one cold solve, timing the solve call only ---
def ours_runner(grid: Grid, P: float, nu: float = 0.5):
    ind = [Cylinder(0.0, P)]
    film = None if nu == 0.5 else Film(poisson=nu)

    def run():
        t = time.perf_counter()
        sol = solve_contact(grid, 0.0, ind, rtol=RTOL, film=film)
        dt = time.perf_counter() - t
        return {"p": sol.pressure, "t": dt, "its": f"{sol.iterations} ({sol.krylov_iterations})",
                "cost": sol.fft_pairs, "note": "", "sol": sol}
    return run


def contactmechanics_runner(grid: Grid, P: float, film: bool, d_scale: float, p_scale: float,
                            nu: float = 0.5, tol: float = RTOL):
    from ContactMechanics import PeriodicFFTElasticHalfSpace

    n, L = grid.n, grid.length
    if film:  # layer Green's function exists for 2D grids only: y-invariant strip, ny = 1
        if nu == 0.5:
            sub = PeriodicFFTElasticHalfSpace((n, 1), 3.0, physical_sizes=(L, 1.0), thickness=1.0,
                                              poisson=CM_INCOMPRESSIBLE_POISSON)
        else:  # compressible: E = 2 G (1 + nu) with G = 1, the core's stress unit
            sub = PeriodicFFTElasticHalfSpace((n, 1), 2.0 * (1.0 + nu), physical_sizes=(L, 1.0),
                                              thickness=1.0, poisson=nu)
        heights = (-(grid.x**2))[:, None]
        force = P * 1.0
    else:     # 1D: half-space, young is the contact modulus E* when poisson is not given
        from SurfaceTopography import UniformLineScan

        sub = PeriodicFFTElasticHalfSpace((n,), 4.0, physical_sizes=(L,))
        heights = UniformLineScan(-(grid.x**2), L, periodic=True)
        force = P
    return _cm_run(sub, heights, force, d_scale, p_scale, tol, (n,))


def _cm_run(sub, heights, force, d_scale, p_scale, tol, shape):
    """One cold constrained-CG solve of ContactMechanics on ``sub`` (a runner: the solve call
    timed; its pressure reshaped to ``shape``)."""
    from ContactMechanics.Optimization import constrained_conjugate_gradients

    kw = dict(external_force=force, pentol=tol * d_scale,
              forcetol=tol * p_scale * sub.area_per_pt, thermotol=tol, maxiter=100000)

    def run():
        t = time.perf_counter()
        res = constrained_conjugate_gradients(sub, heights, **kw)
        dt = time.perf_counter() - t
        return {"p": np.asarray(res.jac).reshape(shape) / sub.area_per_pt, "t": dt,
                "its": int(res.nit), "cost": int(res.nfev),
                "note": "" if res.success else "not converged"}
    return run


def _run_capturing_output(fn):
    """Run fn with the process's fds 1 and 2 sent to a temporary file (tamaas logs from C++)."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = {fd: os.dup(fd) for fd in (1, 2)}
    with tempfile.TemporaryFile() as tmp:
        for fd in (1, 2):
            os.dup2(tmp.fileno(), fd)
        try:
            out = fn()
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            for fd, s in saved.items():
                os.dup2(s, fd)
                os.close(s)
        tmp.seek(0)
        text = tmp.read().decode(errors="replace")
    return out, text


def tamaas_operator(model, shape, symbol: np.ndarray):
    """A tamaas integral operator defined in Python (tamaas 2.9: a subclass of
    ``tamaas.IntegralOperator`` put in ``model.operators[name]``, then
    ``PolonskyKeerRey.setIntegralOperator(name)``): displacement^ = symbol * traction^, by the
    same planned pyfftw transform pair as ours (its C++ Westergaard operator uses FFTW too),
    on a basic_1d model (``shape`` one number or (n,)) or basic_2d ((nx, ny)).  ``symbol`` in
    our units with tamaas' E, nu set as below (E* = 4): 1/(2|k|) is Westergaard's."""
    import tamaas as tm

    shape = tuple(np.atleast_1d(shape))
    fft = get_rfft(shape)
    kind = tm.model_type.basic_1d if len(shape) == 1 else tm.model_type.basic_2d

    class SymbolOperator(tm.IntegralOperator):
        def __init__(self, model):
            super().__init__(model)
            self.calls = 0

        def apply(self, inp, out):
            self.calls += 1
            out[...] = fft.apply(np.asarray(inp).reshape(shape), symbol).reshape(out.shape)

        def getKind(self):
            return tm.IntegralOperator.neumann

        def getType(self):
            return kind

        def updateFromModel(self):
            pass

    return SymbolOperator(model)


def tamaas_runner(grid: Grid, P: float, symbol: np.ndarray | None = None, tol: float = RTOL,
                  count: bool = True):
    """tamaas' Polonsky-Keer-Rey solver on a basic_1d model: its Westergaard (half-space)
    operator, or with ``symbol`` an operator registered from Python (``tamaas_operator``)."""
    import tamaas as tm

    n, L = grid.n, grid.length
    heights = -(grid.x**2)

    def solve_once(log: bool):
        """A fresh model and solver (cold start); times the solve call only."""
        tm.set_log_level(tm.LogLevel.info if log else tm.LogLevel.error)
        model = tm.ModelFactory.createModel(tm.model_type.basic_1d, [L], [n])
        model.E, model.nu = 3.0, 0.5  # E* = E/(1-nu^2) = 4: compliance 1/(2|k|)
        solver = tm.PolonskyKeerRey(model, heights, tol)
        op = None
        if symbol is not None:
            op = tamaas_operator(model, n, symbol)
            model.operators["spectral_contact_symbol"] = op
            solver.setIntegralOperator("spectral_contact_symbol")
        solver.max_iter = 100000
        if log:
            solver.dump_freq = 1
        t = time.perf_counter()
        err = solver.solve(P / L)  # mean pressure
        dt = time.perf_counter() - t
        calls = op.calls if op is not None else None
        return np.asarray(model.traction, dtype=float).reshape(n), float(err), dt, calls

    its = None
    if count:
        try:  # the iteration count, from its log (a separate, untimed solve)
            _, text = _run_capturing_output(lambda: solve_once(True))
            nums = [int(m.group(1)) for m in re.finditer(r"^\s*(\d+)\s+\S+\s+\S+\s*$", text, re.M)]
            its = max(nums) if nums else None
        except Exception:  # the count is a nicety; never lose the comparison for it
            its = None
        finally:
            tm.set_log_level(tm.LogLevel.error)

    def run():
        p, err, dt, calls = solve_once(False)
        return {"p": p, "t": dt, "its": its if its is not None else "n/a",
                "cost": calls if calls is not None else "n/a", "note": f"own error {err:.1e}"}
    return run


def time_round_robin(runners: dict, repeats: int = REPEATS, stat: str = "min") -> dict:
    """Warm every runner, then run them in turn ``repeats`` times; keep each one's last result
    with its fastest (``stat`` "min") or median ("median") time (interleaving makes the ratios
    robust to the load of a shared machine)."""
    out = {}
    for name, run in runners.items():
        out[name] = run()
    times = {name: [] for name in runners}
    for _ in range(repeats):
        for name, run in runners.items():
            res = run()
            times[name].append(res["t"])
            out[name] = res
    for name in runners:
        out[name]["t"] = float(min(times[name]) if stat == "min" else np.median(times[name]))
    return out


# --- the cases --------------------------------------------------------------------------------
def run_case(case, scene, tol, versions, halfspace: bool):
    """Our automatic solve fixes (L, N); every solver then runs on that grid.  Case A (film):
    ContactMechanics' layer.  Case B (halfspace=True): also the half-space peers (tamaas,
    ContactMechanics 1D) and the Hertz closed form, with dp_hertz = their distance from it."""
    r = solve(scene, tol=tol)
    grid = Grid(r.grid_points, r.domain_length, float(r.x[0]))
    P = scene.P
    nu = scene.poisson
    film_sym = (surface_compliance(grid.k, 0.0).real if nu == 0.5 else
                Film(poisson=nu).surface_compliance((np.ones_like(grid.k),), grid.k, 0.0).real)
    hs_sym = halfspace_symbol(grid)
    p_hertz = hertz_pressure(grid.x, hertz_half_width(P)) if halfspace else None
    OURS = "spectral_contact (film)"
    first = ours_runner(grid, P, nu)()
    d_scale, p_scale = float(first["sol"].indentations[0]), float(first["p"].max())

    specs = [("ContactMechanics film (2D strip, ny=1)", "ContactMechanics",
              lambda: contactmechanics_runner(grid, P, True, d_scale, p_scale, nu), film_sym)]
    if halfspace:
        specs += [("ContactMechanics half-space (1D)", "ContactMechanics",
                   lambda: contactmechanics_runner(grid, P, False, d_scale, p_scale), hs_sym),
                  ("tamaas half-space (basic_1d, PKR)", "tamaas",
                   lambda: tamaas_runner(grid, P), hs_sym)]
    runners = {OURS: ours_runner(grid, P, nu)}
    symbols = {OURS: film_sym}
    missing = {}
    for name, pkg, make, sym in specs:
        if not present(versions, pkg):
            missing[name] = _absent(case, name, pkg, versions, grid)
            continue
        try:
            run = make()
            run()  # a peer's failure is reported, never fatal
        except Exception as exc:
            missing[name] = _failed(case, name, pkg, versions, grid, exc)
            continue
        runners[name], symbols[name] = run, sym
    res = time_round_robin(runners)
    p0, t0 = res[OURS]["p"], res[OURS]["t"]
    curves = {}
    rows = []
    for name, _, _, _ in [(OURS, None, None, None)] + specs:
        if name in missing:
            rows.append(missing[name])
            continue
        r_ = res[name]
        curves[name] = r_["p"]
        extra = {"a_sub": r.half_width, "note": f"auto solve at tol {tol:g}: a = {r.half_width:.6g}"} \
            if name == OURS else {"t_ref": t0, "note": r_["note"]}
        rows.append(_row(case, name, "this" if name == OURS else versions[
            "tamaas" if name.startswith("tamaas") else "ContactMechanics"], grid, P, r_["p"],
            r_["t"], r_["its"], r_["cost"], symbols[name], p0, p_hertz=p_hertz, **extra))
    if halfspace:
        curves["Hertz closed form (half-space)"] = p_hertz
        rows.append(_row(case, "Hertz closed form (half-space)", "-", grid, P, p_hertz,
                         float("nan"), "-", "-", hs_sym, p0, p_hertz=p_hertz,
                         note="sampled p = 4 sqrt(a^2 - x^2)"))
    return rows, grid, curves


def _blank(case, solver, version, grid, note):
    nan = float("nan")
    return {"case": case, "solver": solver, "version": version, "N": grid.n, "L_h": grid.length,
            "time_ms": nan, "time_ratio": nan, "iterations": "-", "fft_pairs": "-",
            "a_nodes": nan, "a_subgrid": nan, "p_max": nan, "dp_rel": nan, "dp_hertz": nan,
            "residual": nan,
            "note": note}


def _absent(case, name, pkg, versions, grid):
    return _blank(case, name, "absent", grid, versions[pkg])


def _failed(case, name, pkg, versions, grid, exc):
    print(f"  {name} failed: {type(exc).__name__}: {exc}", file=sys.stderr)
    return _blank(case, name, versions[pkg], grid, f"failed: {type(exc).__name__}: {exc}"[:120])


def _plot(cases, path):
    """Top: the pressures of every solver; bottom: their difference from ours."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(cases), figsize=(6 * len(cases), 6.5), squeeze=False)
    for col, (title, grid, curves) in enumerate(cases):
        x = grid.x
        p0 = next(iter(curves.values()))
        sel = p0 > 0
        lo, hi = x[sel].min(), x[sel].max()
        w = hi - lo
        m = (x > lo - 0.3 * w) & (x < hi + 0.3 * w)
        for k, (name, p) in enumerate(curves.items()):
            axes[0, col].plot(x[m], p[m], lw=1.2, ls=("-", "--", ":", "-.")[k % 4], label=name)
            if k:
                axes[1, col].plot(x[m], (p - p0)[m] / p0.max(), lw=1.0, label=name)
        axes[0, col].set_title(f"{title}: N = {grid.n}, L = {grid.length:.3g} h", fontsize=9)
        axes[0, col].set_ylabel("p  [E h / 6R]")
        axes[0, col].legend(fontsize=7)
        axes[1, col].set_xlabel("x / h")
        axes[1, col].set_ylabel("(p - p_ours) / max p_ours")
        if len(curves) > 1:
            axes[1, col].legend(fontsize=7)
        else:
            axes[1, col].text(0.5, 0.5, "peers absent", ha="center", transform=axes[1, col].transAxes)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


# --- fixed grids at equal accuracy: issue 13's peer targets ------------------------------------
FIXED_EXPS = (12, 14, 16)
LEVEL = 1e-6
"""Accuracy every solver must reach: max |p - p_ref| <= LEVEL max p_ref, p_ref ours at REF_RTOL."""
REF_RTOL = 1e-13
TOLERANCES = tuple(10.0**-e for e in range(4, 13))
"""Each solver's own tolerance, loosest first: the first that reaches LEVEL is timed."""
SPEEDUP = 10.0
HALF_SPACE = Film(thickness=1e12)
"""The half-space limit through our own film code: with h = 1e12 every grid mode has K = |k| h
> 1e10, where F0 = 1 to the last bit, so its symbol is 1/(2|k|) (0 at k = 0), Westergaard's:
the same operator as the peers' half-spaces."""
OURS_FIXED = "spectral_contact"


def fft_pair_time(n: int, repeats: int = 21) -> float:
    """Median time [s] of one planned rfft/irfft pair of n points (our matrix-vector product)."""
    from ._common import median_time

    f = get_rfft(n)
    a = np.random.default_rng(0).random(n)
    sym = np.ones(n // 2 + 1, complex)
    return median_time(lambda: f.apply(a, sym), repeats, warm=True)


def _fixed_solvers(operator: str, grid: Grid, P: float, symbol, d_scale, p_scale):
    """name -> (package, make(tol) -> run) for one operator ("film" or "half-space")."""
    film = operator == "film"
    ind = [Cylinder(0.0, P)]

    def ours(tol):
        def run():
            t = time.perf_counter()
            sol = solve_contact(grid, 0.0, ind, rtol=tol, film=None if film else HALF_SPACE)
            dt = time.perf_counter() - t
            its = f"{sol.iterations}+{sol.coarse_iterations} ({sol.krylov_iterations}+" \
                  f"{sol.coarse_krylov_iterations})"
            return {"p": sol.pressure, "t": dt, "its": its, "cost": sol.fft_pairs, "note": ""}
        return run

    out = {OURS_FIXED: ("this", ours)}
    cm = "ContactMechanics layer (2D strip, ny=1)" if film else "ContactMechanics half-space (1D)"
    out[cm] = ("ContactMechanics",
               lambda tol: contactmechanics_runner(grid, P, film, d_scale, p_scale, tol=tol))
    if film:
        out["tamaas PKR (film operator from Python)"] = (
            "tamaas", lambda tol: tamaas_runner(grid, P, symbol, tol=tol, count=False))
    else:  # its own Westergaard operator, and the same symbol from Python (faster: 2.5-3x)
        out["tamaas PKR (Westergaard)"] = (
            "tamaas", lambda tol: tamaas_runner(grid, P, None, tol=tol, count=True))
        out["tamaas PKR (half-space operator from Python)"] = (
            "tamaas", lambda tol: tamaas_runner(grid, P, symbol, tol=tol, count=False))
    return out


def _loosest_meeting(make, p_ref, level):
    """(tol, run, error, last exception) for the loosest tolerance reaching ``level``; tol None
    when none does (error: the best reached)."""
    best, last_exc = float("inf"), None
    for tol in TOLERANCES:
        try:
            run = make(tol)
            p = run()["p"]
        except Exception as exc:  # a loose tolerance may fail to converge: try the next one
            last_exc = exc
            continue
        err = float(np.max(np.abs(p - p_ref)) / p_ref.max())
        best = min(best, err)
        if err <= level:
            return tol, run, err, None
    return None, None, best, last_exc


def fixed_grid_comparison(exps=FIXED_EXPS, level: float = LEVEL, repeats: int = 5,
                          versions: dict | None = None, operators=("film", "half-space"),
                          log=print) -> list[dict]:
    """Frictionless, fixed grids N = 2^e on the period of the paper's scene (our automatic
    solve at mu_d = 0, tol 1e-4), the paper's load; two operators: the film (ours; tamaas' PKR
    with the film's symbol registered from Python; ContactMechanics' layer) and the half-space
    limit (ours with HALF_SPACE; tamaas' Westergaard and the same symbol registered from Python;
    ContactMechanics 1D): the same discrete
    problem for every solver.  Equal accuracy: each solver runs at the loosest of its own
    tolerances (TOLERANCES) whose pressure is within ``level`` max p_ref of p_ref, our solve at
    REF_RTOL; then times are medians of ``repeats`` interleaved warm runs of the solve call only
    (cold starts: ours from its Hertz guess and nested half-resolution solves, the peers from
    zero).  One row per solver: tolerance, dp_ref, the common residual, iterations (ours: final
    + coarser levels, active-set (GMRES)), time, time / ours, time in FFT-pair times of that N
    (measured in the same run)."""
    versions = versions or peers_available()
    if present(versions, "tamaas"):
        import tamaas

        tamaas.initialize(1)  # one thread, as ours (issue 13: one core)
    scene = Scene(mu=0.0)
    r = solve(scene, tol=1e-4)
    L, P = r.domain_length, scene.P
    rows = []
    for operator in operators:
        for e in exps:
            n = 2**e
            grid = Grid.centered(n, L, 0.0)
            film = Film() if operator == "film" else HALF_SPACE
            sym = film.surface_compliance((np.ones_like(grid.k),), grid.k, 0.0).real
            ref = solve_contact(grid, 0.0, [Cylinder(0.0, P)], rtol=REF_RTOL, film=film)
            p_ref = ref.pressure
            solvers = _fixed_solvers(operator, grid, P, sym, float(ref.indentations[0]),
                                     float(p_ref.max()))
            rows += _equal_accuracy(operator, grid, P, sym, solvers, p_ref, level, repeats,
                                    versions, lambda n=n: fft_pair_time(n),
                                    f"  {operator} N = 2^{e}: ", log)
    return rows


def _equal_accuracy(operator, grid: Grid, P: float, sym, solvers: dict, p_ref, level: float,
                    repeats: int, versions: dict, pair_time, label: str, log) -> list[dict]:
    """Cases D and E on one grid: each solver (name -> (package, make(tol) -> run)) at the
    loosest of its tolerances whose pressure is within ``level`` max p_ref of ``p_ref``
    (``_loosest_meeting``), then timed (medians of ``repeats`` interleaved warm runs); one row
    each: tolerance, dp_ref, the common residual, iterations, time, time / ours and time in
    FFT-pair times (``pair_time()``, measured after the runs); "not measured (...)" rows for
    the peers absent or never within ``level``."""
    n, L = grid.shape[0], grid.lengths[0]
    chosen, lines = {}, {}
    for name, (pkg, make) in solvers.items():
        version = "this" if pkg == "this" else versions[pkg]
        if pkg != "this" and not present(versions, pkg):
            lines[name] = {"version": version, "status": "not measured (peer not installed)"}
            continue
        tol, run, err, exc = _loosest_meeting(make, p_ref, level)
        if tol is None:
            why = f"; last failure {type(exc).__name__}: {exc}"[:100] if exc else ""
            lines[name] = {"version": version, "dp_ref": err,
                           "status": f"not measured (best {err:.1e} > {level:g}{why})"}
            continue
        chosen[name] = run
        lines[name] = {"version": version, "tol": tol, "dp_ref": err, "status": "timed"}
    res = time_round_robin(chosen, repeats, stat="median") if chosen else {}
    pair = pair_time()
    t0 = res[OURS_FIXED]["t"] if OURS_FIXED in res else float("nan")
    rows = []
    for name, line in lines.items():
        row = {"operator": operator, "N": n, "L_h": L, "solver": name,
               "version": line["version"], "tol": line.get("tol", float("nan")),
               "dp_ref": line.get("dp_ref", float("nan")), "residual": float("nan"),
               "iterations": "-", "fft_pairs": "-", "time_ms": float("nan"),
               "time_ratio": float("nan"), "time_in_fft_pairs": float("nan"),
               "fft_pair_us": 1e6 * pair, "status": line["status"]}
        if name in res:
            x = res[name]
            row.update(residual=common_residual(grid, x["p"], P, sym), iterations=x["its"],
                       fft_pairs=x["cost"], time_ms=1e3 * x["t"], time_ratio=x["t"] / t0,
                       time_in_fft_pairs=x["t"] / pair)
        rows.append(row)
    if log:
        log(label + "; ".join(f"{r_['solver']} {r_['time_ratio']:.3g}x" for r_ in rows
                              if r_["solver"] != OURS_FIXED))
    return rows


def peer_targets(rows: list[dict], level: float = LEVEL) -> list[dict]:
    """Issue 13's peer targets from ``fixed_grid_comparison`` rows, in the benchmark's target
    format (target, measured, limit, unit, status): for each operator, N and peer, the peer's
    fastest configuration's time / our time >= SPEEDUP, met or not; "not measured (...)" when
    the peer is absent or never reached ``level``."""
    return _targets(rows, SPEEDUP, lambda operator, n, peer: (
        f"vs {peer} {operator} N=2^{int(round(math.log2(n)))} (frictionless, same grid, p to "
        f"{level:g} p_max): peer time / our time"))


def _targets(rows: list[dict], limit: float, title) -> list[dict]:
    """One target row per (operator, N, peer): the peer's fastest timed configuration's time /
    ours >= ``limit``, met or not, or the status of why it was not measured; ``title(operator,
    N, peer)`` names it."""
    groups = {}
    for r_ in rows:
        if r_["solver"] != OURS_FIXED:
            groups.setdefault((r_["operator"], r_["N"], r_["solver"].split()[0]), []).append(r_)
    out = []
    for (operator, n, peer), rs in groups.items():
        timed = [r_ for r_ in rs if r_["status"] == "timed"]
        if timed:
            ratio = min(r_["time_ratio"] for r_ in timed)
            status = "met" if ratio >= limit else "not met"
        else:
            ratio, status = float("nan"), rs[0]["status"]
        out.append({"target": title(operator, n, peer), "measured": ratio, "limit": limit,
                    "unit": "x (>= limit)", "status": status})
    return out


def benchmark_peers(out, quick: bool = False, repeats: int = 11) -> list[dict]:
    """What studies.benchmark calls: the fixed-grid comparison (quick: N = 2^12 only, 3 runs)
    printed and written to benchmark_peers.csv in ``out``, and its target rows."""
    versions = peers_available()
    rows = fixed_grid_comparison((12,) if quick else FIXED_EXPS, repeats=3 if quick else repeats,
                                 versions=versions)
    table(rows, out / "benchmark_peers.csv",
          f"Peers, frictionless, fixed grids, each solver at the loosest of its tolerances giving "
          f"p within {LEVEL:g} p_max of ours at rtol {REF_RTOL:g}; medians of "
          f"{3 if quick else repeats} interleaved warm runs; "
          + ", ".join(f"{k} {v}" for k, v in versions.items()))
    return peer_targets(rows)


# --- E. surfaces (issue 25) --------------------------------------------------------------------
SURFACE_EXPS = (8, 10)    # N x N grids: 256^2, 1024^2
SURFACE_SPEEDUP = 5.0     # issue 25: at least 5x tamaas with the same symbol at 1024^2
SURFACE_PERIOD_M = 0.03   # the 3D speed target's period


def tamaas_surface_runner(grid: Grid, P: float, symbol: np.ndarray | None = None,
                          tol: float = RTOL):
    """tamaas' PKR on a basic_2d model (E* = 4: Westergaard's compliance is 1/(2|k|)), its own
    operator or ``symbol`` registered from Python (as ``tamaas_operator``, in 2D)."""
    import tamaas as tm

    shape, lengths = grid.shape, grid.lengths
    X, Y = np.meshgrid(*grid.axes, indexing="ij")
    heights = -(X**2 + Y**2)

    def run():
        tm.set_log_level(tm.LogLevel.error)
        model = tm.ModelFactory.createModel(tm.model_type.basic_2d, list(lengths), list(shape))
        model.E, model.nu = 3.0, 0.5
        solver = tm.PolonskyKeerRey(model, heights, tol)
        op = None
        if symbol is not None:  # (kept referenced: tamaas holds only its C++ part)
            op = tamaas_operator(model, shape, symbol)
            model.operators["spectral_contact_symbol"] = op
            solver.setIntegralOperator("spectral_contact_symbol")
        solver.max_iter = 100000
        t = time.perf_counter()
        err = solver.solve(P / (lengths[0] * lengths[1]))
        dt = time.perf_counter() - t
        del op
        return {"p": np.asarray(model.traction, dtype=float).reshape(shape), "t": dt,
                "its": "n/a", "cost": "n/a", "note": f"own error {float(err):.1e}"}
    return run


def contactmechanics_surface_runner(grid: Grid, P: float, film: bool, d_scale: float,
                                    p_scale: float, tol: float = RTOL):
    """ContactMechanics' constrained CG on the 2D grid: its layer (film) or half-space."""
    from ContactMechanics import PeriodicFFTElasticHalfSpace

    shape, lengths = grid.shape, grid.lengths
    if film:
        sub = PeriodicFFTElasticHalfSpace(shape, 3.0, physical_sizes=lengths, thickness=1.0,
                                          poisson=CM_INCOMPRESSIBLE_POISSON)
    else:
        sub = PeriodicFFTElasticHalfSpace(shape, 4.0, physical_sizes=lengths)
    X, Y = np.meshgrid(*grid.axes, indexing="ij")
    heights = -(X**2 + Y**2)
    return _cm_run(sub, heights, P, d_scale, p_scale, tol, shape)


def _surface_pair_time(n: int, sym) -> float:
    """Median time [s] of one planned 2D rfft/irfft pair with ``sym`` on n x n."""
    from ._common import median_time

    f2 = get_rfft((n, n))
    a = np.random.default_rng(0).random((n, n))
    return median_time(lambda: f2.apply(a, sym), 11, warm=True)


def surface_comparison(exps=SURFACE_EXPS, level: float = LEVEL, repeats: int = 5,
                       versions: dict | None = None, operators=("film", "half-space"),
                       log=print) -> list[dict]:
    """Case E: the frictionless sphere on N x N grids (see the module's docstring), rows in
    the format of ``fixed_grid_comparison``'s."""
    from spectral_contact.physics.indenters import Sphere
    from spectral_contact.physics.scene import Scene3D

    versions = versions or peers_available()
    if present(versions, "tamaas"):
        import tamaas

        tamaas.initialize(1)
    scene = Scene3D(force=1.0, mu=0.0)
    L, P = SURFACE_PERIOD_M / scene.length_unit, scene.P
    ind = [Sphere(0.0, P)]
    rows = []
    for operator in operators:
        film = Film() if operator == "film" else HALF_SPACE
        for e in exps:
            n = 2**e
            grid = Grid.centered((n, n), (L, L))
            sym = film.surface_compliance(grid.direction, grid.kmag, 0.0).real
            ref = solve_contact(grid, 0.0, ind, rtol=REF_RTOL, film=film)
            p_ref = ref.pressure

            def ours(tol, grid=grid, film=film):
                def run():
                    t = time.perf_counter()
                    sol = solve_contact(grid, 0.0, ind, rtol=tol, film=film)
                    dt = time.perf_counter() - t
                    return {"p": sol.pressure, "t": dt,
                            "its": f"{sol.iterations}+{sol.coarse_iterations} "
                                   f"({sol.krylov_iterations}+{sol.coarse_krylov_iterations})",
                            "cost": sol.fft_pairs, "note": ""}
                return run

            d_scale, p_scale = float(ref.indentations[0]), float(p_ref.max())
            solvers = {OURS_FIXED: ("this", ours)}
            cm = f"ContactMechanics {'layer' if operator == 'film' else 'half-space'} (2D)"
            solvers[cm] = ("ContactMechanics", lambda tol, grid=grid, f=operator == "film":
                           contactmechanics_surface_runner(grid, P, f, d_scale, p_scale, tol))
            if operator == "film":
                solvers["tamaas PKR 2D (film operator from Python)"] = (
                    "tamaas", lambda tol, grid=grid, sym=sym:
                    tamaas_surface_runner(grid, P, sym, tol))
            else:
                solvers["tamaas PKR 2D (Westergaard)"] = (
                    "tamaas", lambda tol, grid=grid: tamaas_surface_runner(grid, P, None, tol))
                solvers["tamaas PKR 2D (half-space operator from Python)"] = (
                    "tamaas", lambda tol, grid=grid, sym=sym:
                    tamaas_surface_runner(grid, P, sym, tol))
            rows += _equal_accuracy(operator, grid, P, sym, solvers, p_ref, level, repeats,
                                    versions, lambda n=n, sym=sym: _surface_pair_time(n, sym),
                                    f"  surface {operator} {n}^2: ", log)
    return rows


def surface_cpu_check(n: int = 1024, tol: float = 1e-9, operator: str = "film") -> dict:
    """Case E's scene on n x n, ours (``solve_contact``, cold) and tamaas' PKR with the same
    symbol at the same rtol, each once warm: CPU and wall seconds (CPU time is less sensitive
    to a shared machine's load than the wall time of the interleaved runs)."""
    import tamaas

    from spectral_contact.physics.indenters import Sphere
    from spectral_contact.physics.scene import Scene3D

    tamaas.initialize(1)
    scene = Scene3D(force=1.0, mu=0.0)
    L, P = SURFACE_PERIOD_M / scene.length_unit, scene.P
    grid = Grid.centered((n, n), (L, L))
    film = Film() if operator == "film" else HALF_SPACE
    sym = film.surface_compliance(grid.direction, grid.kmag, 0.0).real
    ind = [Sphere(0.0, P)]
    out = {}
    for name, run in (("tamaas", tamaas_surface_runner(grid, P, sym, tol)),
                      ("ours", lambda: solve_contact(grid, 0.0, ind, rtol=tol, film=film))):
        run()
        c, t = time.process_time(), time.perf_counter()
        run()
        out[name] = (time.process_time() - c, time.perf_counter() - t)
    out["cpu_ratio"] = out["tamaas"][0] / out["ours"][0]
    out["wall_ratio"] = out["tamaas"][1] / out["ours"][1]
    return out


def surface_targets(rows: list[dict], level: float = LEVEL) -> list[dict]:
    """Issue 25's peer target from ``surface_comparison`` rows: at each N and operator, tamaas'
    fastest configuration's time / ours >= SURFACE_SPEEDUP (ContactMechanics reported too)."""
    return _targets(rows, SURFACE_SPEEDUP, lambda operator, n, peer: (
        f"surface: vs {peer} {operator} {n}^2 (frictionless sphere, same grid, p to {level:g} "
        f"p_max): peer time / our time"))


def _surfaces(args, out, versions) -> int:
    """Case E: peers_surface.csv and the issue-25 target lines."""
    surf = surface_comparison((8,) if args.quick else SURFACE_EXPS,
                              repeats=3 if args.quick else 5, versions=versions)
    table(surf, out / "peers_surface.csv",
          f"E: frictionless sphere (1 N, R 130 mm, film h 2 mm, period 30 mm), N x N grids, each "
          f"solver at the loosest tolerance giving p within {LEVEL:g} max p of ours at rtol "
          f"{REF_RTOL:g}; time_ratio = time / ours")
    for t in surface_targets(surf):
        print(f"{t['target']}: {t['measured']:.3g} (>= {t['limit']:g}: {t['status']})")
    return 0


def main(argv=None) -> int:
    args, out = parse(argv, __doc__.splitlines()[0], "out/peers", extra=lambda p: p.add_argument(
        "--surfaces", action="store_true", help="case E only (the surface peers, issue 25)"))
    versions = peers_available()
    for name, v in versions.items():
        print(f"{name}: {v}")
    absent = [n for n in versions if not present(versions, n)]
    if absent:
        print(f"peers absent: {', '.join(absent)} -- their rows say so; install with "
              f"`pip install contactmechanics tamaas` (or the 'peers' extra)")
    if args.surfaces:
        return _surfaces(args, out, versions)
    tol = 1e-3 if args.quick else 1e-4
    s_thick = 0.05 if args.quick else 0.02
    t0 = time.perf_counter()
    rows, plots = [], []
    specs = [("A film", Scene(mu=0.0), False),
             (f"B thick film a/h={s_thick:g}", scene_for(s_thick, 0.0), True)]
    # compressible films (issue 14): ContactMechanics' layer with poisson = nu
    specs += [(f"C film nu={nu:g}", Scene(mu=0.0, poisson=nu), False)
              for nu in ((0.3,) if args.quick else (0.3, 0.4))]
    for i, (case, scene, halfspace) in enumerate(specs, 1):
        r_rows, grid, curves = run_case(case, scene, tol, versions, halfspace)
        rows += r_rows
        progress(i, len(specs), f"{case}: N = {grid.n}", t0)
        plots.append((case, grid, curves))
    table(rows, out / "peers.csv",
          f"Frictionless contact, same grid per case (our automatic solve at tol {tol:g} sets L, N); "
          f"dp_rel = max|p - p_ours| / max p_ours; residual = common convergence measure")
    for case in dict.fromkeys(r["case"] for r in rows):
        cr = [r for r in rows if r["case"] == case]
        base = cr[0]
        for r in cr[1:]:
            if r["version"] == "-":
                print(f"{case}: Hertz closed form (half-space): a_nodes {r['a_nodes']:.6g}; ours "
                      f"(film) differs from it by {r['dp_rel']:.2e} of p_max (the film's effect)")
            elif r["version"] == "absent":
                print(f"{case}: {r['solver']} absent -- not compared")
            elif r["note"].startswith("failed"):
                print(f"{case}: {r['solver']} {r['note']}")
            else:
                print(f"{case}: {r['solver']} takes {r['time_ratio']:.3g}x our time "
                      f"({r['time_ms']:.3g} ms vs {base['time_ms']:.3g} ms), "
                      f"{r['iterations']} iterations vs our {base['iterations']}; "
                      f"a_nodes {r['a_nodes']:.6g} vs {base['a_nodes']:.6g}; "
                      f"pressures agree to {r['dp_rel']:.2e} of p_max"
                      + (f" (to the Hertz closed form: {r['dp_hertz']:.2e})"
                         if r["dp_hertz"] == r["dp_hertz"] else ""))
    fixed = fixed_grid_comparison((12,) if args.quick else FIXED_EXPS,
                                  repeats=3 if args.quick else 5, versions=versions)
    table(fixed, out / "peers_fixed.csv",
          f"D: frictionless, fixed grids, each solver at the loosest tolerance giving p within "
          f"{LEVEL:g} max p of ours at rtol {REF_RTOL:g}; time_ratio = time / ours")
    for t in peer_targets(fixed):
        print(f"{t['target']}: {t['measured']:.3g} (>= {t['limit']:g}: {t['status']})")
    _surfaces(args, out, versions)
    try:
        _plot(plots, out / "peers.png")
        print(f"(written {out / 'peers.png'})")
    except Exception as exc:  # a plot must never lose the table
        print(f"plot skipped: {exc}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
