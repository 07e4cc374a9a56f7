"""The paper's Abel / Fredholm formulation of the sliding contact, as an independent solver.

Dimensionless core (the paper's): lengths in h, displacements in h^2/(2R), stresses in E h/(6R),
load P = scene.P.  Internally coordinates are the paper's, centred on the contact (|x| < a); the
returned ContactResult is in the apex frame (x_apex = x_paper - x0, center = -x0).

Formulation (paper, section "Exact model")
-----------------------------------------
The surface normal stress sigma(x) = sigma_zz(x, 1) = -p(x) is written with the paper's
cosine / sine decomposition  D(x) = Int_0^inf D^c(k) cos kx dk + Int_0^inf D^s(k) sin kx dk  and

    sigma^c(k) = Int_0^a phi(t) J0(kt) dt,      sigma^s(k) = Int_0^a t psi(t) J1(kt) dt,

i.e. in x-space  sigma(x) = Int_|x|^a (phi(t) + x psi(t)) / sqrt(t^2 - x^2) dt  (|x| < a), so
p(x) = -Int_0^S (phi(t) + x psi(t))/t ds with t = sqrt(x^2 + s^2), S = sqrt(a^2 - x^2) (smooth
integrand: phi(t)/t and psi(t)/t are even analytic functions, interpolated from the nodes).
phi, psi solve the coupled second-kind Fredholm equations (paper Eqs. ab1-ab2)

    phi(x) + Int M00 phi + mu Int M10 psi = -4x,     psi(x) + mu Int M01 phi - Int M11 psi = 0,

discretised by Nystrom on n Gauss-Legendre nodes of [0, a] (kernels: abel_kernels.py).  Load:
P = -pi Int_0^a phi dt, matched to scene.P by a safeguarded secant on log a.  A posteriori:

    4 x0  = mu Int phi K_F1J0 - Int psi - Int t psi K_F0m1J1        [Int F0 J1(kt) dk = 1/t + ...]
    1/alpha = x0^2 - Int phi (L_rem + log(2 + sqrt(t^2+4))/2) + (1/2) Int phi log t
              - mu Int t psi K_F1J1_2k

The only singular t-integrand is the log t of Int F0 J0(kt)/(2k) dk ~ -log(t)/2 (t -> 0); it is
split off analytically (Int (1 - e^{-2k}) J0(kt)/k dk = asinh(2/t)) and Int phi log t is done by
Legendre product integration (spectral).  The 1/t of Int F0 J1(kt) dk is removed exactly
(Int J1(kt) dk = 1/t, leaving Int psi).  Base stresses (paper's Z1..Z6 formulas), with the t-sum
done first:  sigma_zz(x,0) = Int [A c - mu B s] cos kx + [A s + mu B c] sin kx dk and
sigma_xz(x,0) = Int [-mu C c + B s] cos kx - [B c + mu C s] sin kx dk, with c = sigma^c(k),
s = sigma^s(k) (this equals Int (Z1 + mu Z3) phi - Int (mu Z2 - Z4) t psi, etc.).

Sign mapping (checked, see tests/test_abel.py)
----------------------------------------------
physics.md: f^(k) = Int f e^{-ikx} dx, so for real f and k > 0, f^(k) = pi (f^c(k) - i f^s(k)).
The paper's Amontons condition sigma_xz(x,1) + mu sigma_zz(x,1) = 0 is ours (sigma_xz = mu p,
friction drags the surface toward +x for mu > 0).  Inserting f^ = pi (f^c - i f^s) into
physics.md's u_z^ = (F0 + i mu sgn(k) F1)/(2|k|) sigma^ gives
u_z^c = (F0 sigma^c + mu F1 sigma^s)/(2k), u_z^s = (F0 sigma^s - mu F1 sigma^c)/(2k): exactly the
paper's Eqs. bc3 / bc4 with u_z(x,1) = -u(x), u(x) = 1/alpha - (x - x0)^2.  Likewise the Z
formulas reproduce physics.md's base transfer sigma_zz^(k,0) = A sigma^ + i sgn(k) B sigma_xz^,
sigma_xz^(k,0) = C sigma_xz^ + i sgn(k) B sigma^.  So the paper's signs are used verbatim, x the
sliding direction, and the paper's x0 (apex relative to contact centre) is -center.  The physics.md
transfer signs were confirmed against an independent single-Fourier-mode solution of the bonded
incompressible layer (stream function, 4x4 linear solve), and the assembled solver against
physics.md's FFT compliance applied to the Abel pressure on a wide periodic grid (the surface
displacement matches -(1/alpha - (x - x0)^2) in the contact) and to its base stresses.  With
mu > 0 the contact centre and the pressure peak move toward +x (leading edge).

Accuracy limits
---------------
The Nystrom matrix's 2-norm condition number (of the sqrt(weight)-symmetrised matrix, i.e. of the
discretised operator in L2) is reported in info["condition_number"]; it grows with a/h and |mu|.
Above COND_WARN an AbelAccuracyWarning is issued; if the error estimate cannot be brought below
``tol`` a ConvergenceError is raised; so is a solution whose pressure turns negative inside the
assumed single contact interval (no longer a valid contact: e.g. mu_d = 96 or 1000 on the
paper's scene).
Measured (tol 1e-4): condition number ~ 0.3 (a/h)^2.7 at mu = 0, up to ~5x more at mu = 10
(2.8 for the paper scene, 4e3 at a = 21 h, 3e5 at a = 64 h); the node count needed grows like
(a/3.2) (digits + log10 cond), so contacts wider than a ~ 100 h (N_MAX nodes) raise
ConvergenceError; within that range the error estimate stays honest and p >= 0 for |mu| <= 10.
"""
from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError, InputError
from ..numerics.abel_kernels import (
    KMAX_M,
    KMAX_Z,
    aposteriori_kernels,
    bessel_on_rule,
    cos_sin_sums,
    film_on_rule,
    gauss_legendre,
    k_rule,
    legendre_log_weights,
    m_kernels,
)
from ..physics.scene import Scene, check_tol
from ..result import ContactResult
from .base import Method, check_grid_points, register

__all__ = ["solve_abel", "AbelMethod", "AbelAccuracyWarning", "COND_WARN", "abel_fields"]

COND_WARN = 1e8        # Nystrom condition number above which results lose > ~1e-8 relative
N_MAX = 400            # largest node count the tolerance loop may use
LOAD_RTOL = 1e-13      # root-finding target on |P(a)/P - 1|
MODELS = ("exact", "goodman")


class AbelAccuracyWarning(UserWarning):
    """The Abel/Nystrom solution may be inaccurate (ill-conditioned system or unphysical field)."""


# -------------------------------------------------------------------------------------------------
@dataclass
class _Abel:
    """One Nystrom solution at fixed a (paper frame)."""

    a: float
    mu: float
    t: np.ndarray
    w: np.ndarray
    phi: np.ndarray
    psi: np.ndarray
    system: np.ndarray  # the Nystrom matrix, sqrt(weight)-symmetrised (for the condition number)
    bessel: tuple       # (J0(k t), J1(k t)) on the kernels' k rule (reused a posteriori)

    @property
    def cond(self) -> float:
        """2-norm condition number of the discretised operator (computed on first use: only
        the accepted solution's is reported)."""
        c = getattr(self, "_cond", None)
        if c is None:
            c = self._cond = float(np.linalg.cond(self.system))
        return c

    @property
    def load(self) -> float:
        return -math.pi * float(self.w @ self.phi)

    # --- interpolation of phi(t)/t and psi(t)/t (even analytic functions) ----------------------
    def _coeffs(self):
        """Legendre coefficients (rows) of phi/t and psi/t on [0, a], shape (2, n)."""
        if not hasattr(self, "_c"):
            n = self.t.size
            s = 2.0 * self.t / self.a - 1.0
            ws = 2.0 * self.w / self.a
            P = np.polynomial.legendre.legvander(s, n - 1)
            proj = (P * ws[:, None]).T * ((2.0 * np.arange(n) + 1.0) / 2.0)[:, None]
            self._c = np.stack([proj @ (self.phi / self.t), proj @ (self.psi / self.t)])
        return self._c

    def _series(self, z):
        """(phi/t, psi/t) at points z of [-1, 1] (t = a (z + 1) / 2), shape (2, z.size): the
        Legendre Vandermonde rows by the three-term recurrence, then one matrix product."""
        n = self.t.size
        V = np.empty((n, z.size))
        V[0] = 1.0
        if n > 1:
            V[1] = z
        for i in range(2, n):
            np.multiply(V[i - 1], z, out=V[i])
            V[i] *= (2.0 * i - 1.0) / i
            V[i] -= ((i - 1.0) / i) * V[i - 2]
        return self._coeffs() @ V

    def interp(self, tq):
        """(phi(tq), psi(tq)) by Legendre interpolation of phi/t, psi/t on [0, a]."""
        tq = np.asarray(tq, dtype=float)
        vals = self._series((2.0 * tq / self.a - 1.0).ravel())
        return tq * vals[0].reshape(tq.shape), tq * vals[1].reshape(tq.shape)

    # --- fields --------------------------------------------------------------------------------
    def pressure(self, xp):
        """p(x) at paper-frame abscissae xp (0 outside |x| < a)."""
        xp = np.atleast_1d(np.asarray(xp, float))
        p = np.zeros_like(xp)
        inside = np.abs(xp) < self.a
        if not np.any(inside):
            return p
        xi = xp[inside]
        m = max(2 * self.t.size, 32)
        u, wu = gauss_legendre(m, 0.0, 1.0)
        S = np.sqrt(np.maximum(self.a**2 - xi**2, 0.0))
        s = S[:, None] * u[None, :]
        tq = np.sqrt(xi[:, None] ** 2 + s**2)
        vals = self._series((2.0 * tq / self.a - 1.0).ravel())
        integrand = vals[0].reshape(xi.size, m) + xi[:, None] * vals[1].reshape(xi.size, m)
        p[inside] = -S * (integrand @ wu)
        return p

    def fine(self):
        """phi, psi on a Gauss grid fine enough to resolve J(kt) up to k ~ KMAX for the Z sums."""
        n = max(self.t.size, int(math.ceil(0.7 * 38.0 * self.a)) + 24)
        if n == self.t.size:
            return self.t, self.w, self.phi, self.psi
        tf, wf = gauss_legendre(n, 0.0, self.a)
        phif, psif = self.interp(tf)
        return tf, wf, phif, psif

    def base_stresses(self, xp, mu_base: float, with_psi: bool = True):
        """sigma_zz(x, 0), sigma_xz(x, 0) at paper-frame xp (paper's Z1..Z6 formulas)."""
        xp = np.atleast_1d(np.asarray(xp, float))
        tf, wf, phif, psif = self.fine()
        rule = k_rule(KMAX_Z, float(np.max(np.abs(xp), initial=0.0)) + self.a)
        k, wk = rule
        _, _, A_, B_, C_ = film_on_rule(rule)
        c, s = bessel_on_rule(tf, rule, wf * phif, wf * tf * psif)
        if not with_psi:
            s = np.zeros_like(k)
        mu = mu_base
        gc_zz, gs_zz = wk * (A_ * c - mu * B_ * s), wk * (A_ * s + mu * B_ * c)
        gc_xz, gs_xz = wk * (-mu * C_ * c + B_ * s), -wk * (B_ * c + mu * C_ * s)
        szz, sxz = cos_sin_sums(xp, rule, [(gc_zz, gs_zz), (gc_xz, gs_xz)])
        return szz, sxz

    def aposteriori(self):
        """(x0, 1/alpha) from the paper's two a-posteriori equations."""
        t, w, phi, psi, mu = self.t, self.w, self.phi, self.psi, self.mu
        K = aposteriori_kernels(t, k_rule(KMAX_M, 2.0 * self.a), self.bessel)
        x0 = 0.25 * (mu * (w @ (phi * K["K_F1J0"])) - w @ psi
                     - w @ (t * psi * K["K_F0m1J1"]))
        W = legendre_log_weights(t.size)
        int_phi_log_t = math.log(self.a) * (w @ phi) + 0.5 * self.a * (W @ phi)
        inv_alpha = (x0 * x0
                     - w @ (phi * (K["L_rem"] + 0.5 * np.log(2.0 + np.sqrt(t * t + 4.0))))
                     + 0.5 * int_phi_log_t
                     - mu * (w @ (t * psi * K["K_F1J1_2k"])))
        return float(x0), float(inv_alpha)

    def _vertex_steps(self, x: float, steps: int = 6):
        """Newton steps on p'(x) = 0 by parabolas through x and x +- 1e-5 a (vertex error
        ~ (p_xxx / p_xx) h^2 / 6 ~ 1e-11 a, about what p's round-off allows); None if p is not
        concave there or a step leaves the contact."""
        h = 1e-5 * self.a
        for _ in range(steps):
            pm_, p0, pp = self.pressure([x - h, x, x + h])
            den = pm_ - 2.0 * p0 + pp
            if not den < 0.0:
                return None
            step = 0.5 * h * (pm_ - pp) / den
            x = x + step
            if not abs(x) < self.a - h:
                return None
            if abs(step) <= 1e-10 * self.a:
                return x
        return x

    def peak(self, near: float | None = None):
        """(max p, its paper-frame abscissa): from ``near`` (where a previous solve found the
        peak), or from the vertex of the parabola through the largest of 255 nodes across the
        contact and its neighbours, Newton steps by parabolas of spacing 1e-5 a: x_max to
        ~1e-10 a (a bracket search alone stops at ~sqrt(eps) a, where p is flat to round-off).
        Falls back to the 255 nodes if the steps from ``near`` fail."""
        xm = None
        if near is not None and abs(near) < self.a:
            xm = self._vertex_steps(float(near))
        if xm is None:
            xs = np.linspace(-self.a, self.a, 257)[1:-1]
            ps = self.pressure(xs)
            i = int(np.argmax(ps))
            xm = float(xs[i])
            if 0 < i < xs.size - 1:
                den = ps[i - 1] - 2.0 * ps[i] + ps[i + 1]
                if den < 0.0:
                    xm += 0.5 * (xs[1] - xs[0]) * (ps[i - 1] - ps[i + 1]) / den
                refined = self._vertex_steps(xm)
                if refined is not None:
                    xm = refined
        return float(self.pressure([xm])[0]), float(xm)


def _nystrom(a: float, mu: float, n: int) -> _Abel:
    t, w = gauss_legendre(n, 0.0, a)
    rule = k_rule(KMAX_M, 2.0 * a)
    bessel = bessel_on_rule(t, rule)
    M00, M01, M10, M11 = m_kernels(t, t, rule, bessel)
    Amat = np.eye(2 * n)
    Amat[:n, :n] += M00 * w
    Amat[:n, n:] += mu * M10 * w
    Amat[n:, :n] += mu * M01 * w
    Amat[n:, n:] -= M11 * w
    rhs = np.concatenate([-4.0 * t, np.zeros(n)])
    sol = np.linalg.solve(Amat, rhs)
    sw = np.sqrt(np.concatenate([w, w]))
    return _Abel(a=a, mu=mu, t=t, w=w, phi=sol[:n], psi=sol[n:],
                 system=Amat * sw[:, None] / sw[None, :], bessel=bessel)


def _solve_load(P: float, mu: float, n, a_guess: float, rtol: float = LOAD_RTOL,
                max_iter: int = 60):
    """Find a with -pi Int phi = P: safeguarded secant on log a.

    ``n`` is the node count, or a callable a -> node count (the scouting pass, where the node
    count follows a so that P(a) stays resolved however far a_guess is).
    Returns (solution, iterations, final relative load residual).
    """
    logP = math.log(P)
    history = []
    n_of = n if callable(n) else (lambda a: n)

    def f(la):
        a = math.exp(la)
        na = n_of(a)
        if na > N_MAX:
            raise ConvergenceError(
                f"Abel solver: a contact of half-width {a:.3g} h needs more than {N_MAX} nodes "
                f"(the Nystrom system's condition number grows like (a/h)^2.7); use the FFT "
                f"method", residuals=history, iterations=len(history))
        sol = _nystrom(a, mu, na)
        Pa = sol.load
        if not (Pa > 0.0 and math.isfinite(Pa)):
            raise ConvergenceError(
                f"Abel solver: load {Pa:.3g} <= 0 at a = {a:.4g} h with {na} nodes "
                f"(Nystrom under-resolved)", residuals=history, iterations=len(history))
        history.append(abs(math.expm1(math.log(Pa) - logP)))
        return math.log(Pa) - logP, sol

    x0 = math.log(a_guess)
    f0, s0 = f(x0)
    if history[-1] <= rtol:
        return s0, 1, history[-1]
    x1 = x0 - min(max(f0 / 2.5, -0.5), 0.5)  # P ~ a^2 (half-space) .. a^5 (thin film)
    f1, s1 = f(x1)
    lo = max([(xx, ff) for xx, ff in ((x0, f0), (x1, f1)) if ff < 0], default=None)
    hi = min([(xx, ff) for xx, ff in ((x0, f0), (x1, f1)) if ff >= 0], default=None)
    while history[-1] > rtol:
        if len(history) >= max_iter:
            raise ConvergenceError(
                f"Abel solver: load not matched to {rtol:g} after {len(history)} iterations",
                residuals=history, iterations=len(history))
        slope = (f1 - f0) / (x1 - x0) if x1 != x0 else 2.5
        x2 = x1 - f1 / (slope if slope > 0 else 2.5)
        if lo is not None and hi is not None:
            if not (lo[0] < x2 < hi[0]):
                x2 = 0.5 * (lo[0] + hi[0])
        else:  # not bracketed yet: at most a factor e^0.5 per step
            x2 = min(max(x2, x1 - 0.5), x1 + 0.5)
        x0, f0 = x1, f1
        x1 = x2
        f1, s1 = f(x1)
        if f1 < 0 and (lo is None or x1 > lo[0]):
            lo = (x1, f1)
        if f1 >= 0 and (hi is None or x1 < hi[0]):
            hi = (x1, f1)
        if lo is not None and hi is not None and hi[0] - lo[0] <= 4e-16 * max(1.0, abs(x1)):
            break  # bracket at machine resolution of log a
    return s1, len(history), history[-1]


def _initial_half_width(P: float) -> float:
    """min(Hertz half-space, thin incompressible film) half-width: P = 2 pi a^2, P = 4 a^5/15."""
    return min(math.sqrt(P / (2.0 * math.pi)), (3.75 * P) ** 0.2)


def _default_nodes(a: float, tol: float) -> int:
    """Node count expected to reach ``tol`` (the caller verifies it).

    Measured: the Nystrom error behaves like cond * 10^(-3.2 n / a) (kernels analytic in a strip
    of half-width 2 around [0, a]), with cond ~ 0.3 (a/h)^2.7 nearly independent of mu.
    """
    digits = max(-math.log10(tol), 1.0)
    log_cond = math.log10(max(1.0, 0.3 * a**2.7))
    return int(math.ceil(8.0 + a / 3.2 * (digits + 1.0 + log_cond)))


@dataclass
class _Solved:
    sol: _Abel
    x0: float
    inv_alpha: float
    pmax: float
    xmax: float
    iterations: int
    residual: float


def _solve_once(P, mu, n, a_guess, tally: list | None = None, near: float | None = None):
    """One load-matched solve; ``near``: where a previous solve found the pressure peak."""
    sol, it, res = _solve_load(P, mu, n, a_guess)
    if tally is not None:
        tally.append(it)
    x0, ia = sol.aposteriori()
    pm, xm = sol.peak(near)
    return _Solved(sol, x0, ia, pm, xm, it, res)


def _change(s1: _Solved, s0: _Solved) -> float:
    a = s1.sol.a
    return max(abs(s1.sol.a - s0.sol.a) / a,
               abs(s1.x0 - s0.x0) / a,
               abs(s1.inv_alpha - s0.inv_alpha) / abs(s1.inv_alpha),
               abs(s1.pmax - s0.pmax) / s1.pmax)


def _smaller(n: int) -> int:
    return max(4, n - max(4, n // 4))


def abel_fields(scene: Scene, mu: float, n: int, a_guess: float | None = None) -> _Solved:
    """Low-level: one load-controlled Nystrom solve with n nodes at friction mu (paper frame)."""
    P = scene.P
    if a_guess is None:
        a_guess = _initial_half_width(P)
    return _solve_once(P, mu, n, a_guess)


def _unloaded(scene: Scene, model: str, x, t_start: float) -> ContactResult:
    """P = 0: no contact, zero fields on ``x`` (default: 401 points over +- 8 h)."""
    xx = np.linspace(-8.0, 8.0, 401) if x is None else x.copy()
    z = np.zeros_like(xx)
    return ContactResult(
        scene=scene, model=model, method="abel", x=xx, pressure=z, base_sigma_zz=z.copy(),
        base_sigma_xz=z.copy(), half_width=0.0, center=0.0, indentation=0.0,
        max_pressure=0.0, max_pressure_x=0.0, grid_points=0,
        domain_length=float(xx[-1] - xx[0]) if xx.size > 1 else 0.0, iterations=0,
        residual=0.0, error_estimate=0.0, wall_time_s=time.perf_counter() - t_start,
        info={"condition_number": 1.0, "n_nodes": 0, "no_contact": True})


def _node_levels(P: float, mu: float, tol: float, n_nodes, a_start: float, root_iterations):
    """The tolerance loop: the node count raised by 1.5x from ``_default_nodes`` until the
    change against the previous count is below tol (a fixed ``n_nodes``: against
    ``_smaller(n_nodes)``).  (fine, n, n_small, err); ConvergenceError at N_MAX."""
    if n_nodes is not None:
        n = n_nodes
        n_small = _smaller(n)
        fine = _solve_once(P, mu, n, a_start, root_iterations)
        coarse = _solve_once(P, mu, n_small, fine.sol.a, root_iterations, fine.xmax)
        return fine, n, n_small, _change(fine, coarse)
    n = _default_nodes(a_start, tol)
    n_small = _smaller(n)
    coarse = _solve_once(P, mu, n_small, a_start, root_iterations)
    while True:
        fine = _solve_once(P, mu, n, coarse.sol.a, root_iterations, coarse.xmax)
        err = _change(fine, coarse)
        if err <= tol or n >= N_MAX:
            break
        coarse, n_small = fine, n
        n = min(N_MAX, int(math.ceil(1.5 * n)))
    if err > tol:
        raise ConvergenceError(
            f"Abel solver: error estimate {err:.2e} > tol {tol:g} at {n} nodes "
            f"(a = {fine.sol.a:.3g} h, mu = {mu:g}, condition number "
            f"{fine.sol.cond:.2e}); the Abel method degrades at large a/h",
            residuals=[err], iterations=fine.iterations)
    return fine, n, n_small, err


def _profile_x(a: float, x0: float) -> np.ndarray:
    """The default profile abscissae (apex frame): the contact +- 8 h, the base stresses'
    peaks sampled to ~1e-5 (cells min(0.02, a/50), 400 ... 4000 points, odd)."""
    span = a + 8.0
    dx = min(0.02, a / 50.0)
    npts = int(min(max(math.ceil(2.0 * span / dx), 400), 4000)) | 1
    return np.linspace(-x0 - span, -x0 + span, npts)


# -------------------------------------------------------------------------------------------------
def solve_abel(scene: Scene, model: str = "exact", tol: float = 1e-4, n_nodes: int | None = None,
               x: np.ndarray | None = None) -> ContactResult:
    """Solve one scene with the paper's Abel formulation (Nystrom on Gauss-Legendre nodes).

    Parameters
    ----------
    scene : Scene
    model : {"exact", "goodman"}
        "goodman": the frictionless window and pressure, friction only loads the base.
    tol : float in [1e-14, 0.1)
        Relative accuracy target of a, contact centre (relative to a), indentation and peak
        pressure; the node count is increased until the change against a smaller node count is
        below it (unless ``n_nodes`` is given).
    n_nodes : int, optional
        Fix the number of Nystrom nodes (>= 6).
    x : array, optional
        Profile abscissae in h, apex frame; default: uniform grid over the contact +- 8 h.

    Returns
    -------
    ContactResult (method "abel").  info: condition_number, n_nodes, n_nodes_compared,
    kernel_quadrature_points, x0_paper, load_history...

    Warns
    -----
    AbelAccuracyWarning : ill-conditioned Nystrom system.

    Raises
    ------
    InputError
    ConvergenceError : no convergence in the node count, or negative pressure inside the
        contact (the single-interval formulation does not hold).
    """
    t_start = time.perf_counter()
    if not isinstance(scene, Scene):
        raise InputError(f"scene must be a Scene; got {type(scene).__name__}")
    if model not in MODELS:
        raise InputError(f"model must be one of {', '.join(MODELS)}; got {model!r}")
    tol = check_tol(tol)
    n_nodes = check_grid_points(n_nodes, 6, 2000, "Abel Nystrom nodes")
    if x is not None:
        x = np.asarray(x, dtype=float)
        if x.ndim != 1 or x.size == 0 or not np.all(np.isfinite(x)):
            raise InputError("x must be a non-empty 1-D array of finite abscissae (in h)")

    P = scene.P
    mu = scene.mu
    mu_solve = 0.0 if model == "goodman" else mu

    if P == 0.0:
        return _unloaded(scene, model, x, t_start)

    # --- scouting pass: node count following a, load to 1e-4 -------------------------------
    scout, scout_it, _ = _solve_load(P, mu_solve, lambda a: _default_nodes(a, 1e-6),
                                     _initial_half_width(P), rtol=1e-4)
    root_iterations = [scout_it]  # every root-finding step is one Nystrom solve
    fine, n, n_small, err = _node_levels(P, mu_solve, tol, n_nodes, scout.a, root_iterations)

    sol = fine.sol
    if sol.cond > COND_WARN or sol.cond * 1e-15 > tol:
        warnings.warn(
            f"Abel solver: Nystrom condition number {sol.cond:.2e} (roundoff may exceed tol) "
            f"(a = {sol.a:.3g} h, mu = {mu_solve:g}); results may be inaccurate",
            AbelAccuracyWarning, stacklevel=2)

    x0, inv_alpha = fine.x0, fine.inv_alpha
    xx = _profile_x(sol.a, x0) if x is None else x.copy()
    xp = xx + x0  # paper frame
    p = sol.pressure(xp)
    pmin = float(np.min(sol.pressure(np.linspace(-sol.a, sol.a, 203)[1:-1])))
    if pmin < -1e-6 * fine.pmax:
        # the one-interval formulation no longer describes a contact: no answer rather than
        # a wrong one (the FFT method has no such assumption)
        raise ConvergenceError(
            f"Abel solver: pressure {pmin:.3g} < 0 inside the contact (peak {fine.pmax:.3g}): "
            f"the single-interval contact is not valid here (a = {sol.a:.3g} h, mu = "
            f"{mu_solve:g}); use method fft", residuals=[pmin / fine.pmax],
            iterations=fine.iterations)
    szz, sxz = sol.base_stresses(xp, mu, with_psi=(model == "exact"))

    tf = sol.fine()[0]
    info = {
        "condition_number": sol.cond,
        "n_nodes": int(n),
        "n_nodes_compared": int(n_small),
        "kernel_quadrature_points": int(k_rule(KMAX_M, 2.0 * sol.a)[0].size),
        "base_quadrature_t_points": int(tf.size),
        "x0_paper": x0,
        "mu_in_contact": mu_solve,
        "root_finding_iterations": fine.iterations,
        "scouting_iterations": scout_it,
        "tolerance_met": bool(err <= tol),
    }
    return ContactResult(
        scene=scene, model=model, method="abel", x=xx, pressure=p, base_sigma_zz=szz,
        base_sigma_xz=sxz, half_width=float(sol.a), center=float(-x0), indentation=float(inv_alpha),
        max_pressure=fine.pmax, max_pressure_x=float(fine.xmax - x0), grid_points=int(n),
        domain_length=float(xx[-1] - xx[0]) if xx.size > 1 else 0.0,
        iterations=int(fine.iterations), residual=float(fine.residual), error_estimate=float(err),
        wall_time_s=time.perf_counter() - t_start, info=info,
        counters={"transforms": 0, "iterations": int(sum(root_iterations)),
                  "linear_iterations": int(sum(root_iterations))})


@register
class AbelMethod(Method):
    """The paper's Abel formulation (Nystrom on Gauss-Legendre nodes): an independent check.

    Option: ``grid_points``, the number of Nystrom nodes (6 ... 2000), fixed instead of chosen
    from ``tol``.  It needs no domain: ``domain_length`` is refused."""

    name = "abel"

    def __init__(self, tol: float = 1e-4, grid_points=None, domain_length=None):
        super().__init__(tol)
        self.grid_points = check_grid_points(grid_points, 6, 2000, "Abel Nystrom nodes")
        if domain_length is not None:
            raise InputError("domain_length applies to method fft only (method abel needs no domain)")

    def solve(self, scene: Scene, model: str) -> ContactResult:
        if scene.poisson != 0.5:
            raise InputError(f"method abel is for the incompressible film (poisson 0.5) only; got "
                             f"poisson {scene.poisson:.10g}: use method fft")
        if not scene.friction.is_amontons:
            raise InputError(f"method abel solves Amontons friction only; got friction law "
                             f"{scene.friction_law}: use method fft")
        if scene.interface_compliance != 0.0 or scene.interface_law != "linear":
            raise InputError("method abel has a rigid interface only (interface compliance 0, "
                             f"law linear); got {scene.interface_compliance:g} m/Pa, law "
                             f"{scene.interface_law}: use method fft")
        return solve_abel(scene, self.check_model(model), self.tol, self.grid_points)
