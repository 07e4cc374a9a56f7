"""A viscoelastic (Prony series) incompressible film in steady sliding at speed V (issue 23).

Material.  The film's Young's relaxation modulus is the Prony series

    E(t) = E_inf + sum_i E_i exp(-t / tau_i),       E_inf > 0, E_i > 0, tau_i > 0,

(the shear modulus G(t) = E(t)/3: nu = 1/2 at all times).  With the time convention exp(+i w t)
of a harmonic strain, sigma = G*(w) eps with the complex modulus

    G*(w) = G_inf + sum_i G_i (i w tau_i) / (1 + i w tau_i),   G_i = E_i / 3,

relaxed G*(0) = G_inf, glassy G*(inf) = G_0 = G_inf + sum G_i; loss tangent Im G*/Re G* > 0
for w > 0.

Steady sliding: the frequency a material point sees.  The indenter slides toward +x at speed V
(V < 0: toward -x) over a film fixed to its base; the package's frame moves with the indenter,
x = X - V t (X the material coordinate).  A steady field of the indenter's frame is a sum of
modes exp(+i k.x) (the package's Fourier convention: numpy's, ``physics.film``); at a fixed
material point X a mode reads exp(i k.X) exp(-i k_x V t): the point sees the frequency

    w(k) = -k_x V.

Correspondence.  For an incompressible film bonded to a rigid base, a given surface traction
field produces a stress field independent of G (the incompressible elasticity equations with
traction and zero-displacement conditions are G-free in terms of stresses and G u), and the
displacement field scales as 1/G.  For linear viscoelasticity each Fourier mode is harmonic in
time at a material point, so its displacement is the elastic one with G replaced by G*(w(k)):
in units of 1/G_inf every compliance symbol of ``Film`` is multiplied by

    R(k) = G_inf / G*(-k_x V),

and the base-traction transfer (stresses from tractions) is unchanged.  On the real-FFT half
spectrum R(-k) = conj R(k), as a real operator needs.

Sign check (one SLS term, G_inf/G* = (1 - i k_x l)/(1 - i k_x l_r), l = V tau, l_r = V tau_r,
tau_r = tau G_0/G_inf the retardation time): the factor 1/(1 - i k l_r) is the Fourier transform
of exp(x/l_r)/l_r for x < 0 only, so a load at x' sinks the surface behind it (x < x'), decaying
over l_r: for V > 0 the trailing side (-x) recovers late, the material entering at the leading
edge (+x) is stiffer (glassy), the pressure moves toward +x, and the pressure's horizontal force
on the indenter (Int p df/dx) opposes the motion.  Tests check all three signs.

Compressible films (nu < 1/2) with a Prony series are refused (``Scene``): with an elastic bulk
modulus the symbol is not a scaling of the elastic one (the layer's transfer functions depend on
nu(w)), which this film does not model.

Units: ``speed`` in lengths of ``thickness`` per second (the core: h/s), ``tau`` in seconds;
moduli in any one unit (``relaxed_young`` and the Prony moduli together).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..errors import InputError
from .film import Film
from .options import check_prony
from .transfer import F2, tanh_over, transfer_functions

__all__ = ["ViscoelasticFilm", "film_of", "parse_prony", "check_prony"]


def parse_prony(text: str, option: str = "--prony") -> tuple:
    """'E1,tau1[,E2,tau2,...]' -> ((E1, tau1), ...); InputError naming ``option`` otherwise."""
    return check_prony(str(text), option)


@lru_cache(maxsize=64)
def _retardation_times(relaxed_young: float, prony: tuple) -> tuple:
    """``ViscoelasticFilm.retardation_times`` of E_inf ``relaxed_young`` and ``prony`` (bisection
    between the poles, sorted)."""
    taus = sorted({t for _, t in prony})
    poles = [-1.0 / t for t in taus]  # increasing: most negative first

    def f(s):
        return relaxed_young + sum(e * s * t / (1.0 + s * t) for e, t in prony)

    out = []
    bounds = list(zip(poles[:-1], poles[1:])) + [(poles[-1], 0.0)] if poles else []
    for lo, hi in bounds:
        a, b = lo + 1e-15 * abs(lo), hi - (1e-15 * abs(hi) if hi else 0.0)
        if hi == 0.0:
            b = 0.0
        for _ in range(200):  # f -> -inf at a pole's right, f(0) > 0; increasing between
            m = 0.5 * (a + b)
            if f(m) > 0.0:
                b = m
            else:
                a = m
            if b - a <= 1e-15 * abs(b):
                break
        out.append(-1.0 / (0.5 * (a + b)))
    return tuple(sorted(out))


MERGE_FACTOR = 4.0  # (``ViscoelasticFilm.MERGE_FACTOR``: why this factor)


def merged_weights(prony, relaxed_young: float) -> list[float]:
    """Per Prony term (E_i [Pa], tau_i [s]), the summed E_j/E_inf of the terms whose tau_j is
    within MERGE_FACTOR of tau_i, itself included (``ViscoelasticFilm.merged_weights``)."""
    f = MERGE_FACTOR * (1.0 + 1e-12)
    return [sum(e / relaxed_young for e, t in prony if t_i / f <= t <= t_i * f)
            for _, t_i in prony]


@dataclass(frozen=True)
class ViscoelasticFilm(Film):
    """An incompressible Prony-series film in steady sliding (module docstring).

    Parameters
    ----------
    thickness : float
        h (the length unit of ``speed`` and of the wavenumbers' inverse).
    relaxed_young : float, optional
        E_inf, the relaxed Young's modulus (the unit of the compliances is 1/G_inf, G_inf =
        E_inf/3: the elastic film's unit for E = E_inf).  Default: ``young`` (a scene's film:
        ``young`` is E_inf, as the command line's --young), else 1 (the core).  Both given and
        different: InputError.
    prony : tuple of (E_i, tau_i)
        Prony moduli (same unit as ``relaxed_young``) and relaxation times [s].
    speed : float
        V [thickness's unit / s], signed: > 0 the indenter slides toward +x.  A scene's film
        (``solve(film=ViscoelasticFilm(thickness=2e-3, young=2.2e6, prony=((2.2e6, 0.01),),
        speed=0.05))``: thickness [m], young = E_inf and E_i [Pa], speed [m/s]) becomes the
        scene's own young, prony and speed (``Scene(young=, prony=, speed=)``, the same solve
        bit for bit); in the core (thickness 1) V is in h/s.

    ``speed == 0`` or no terms: the symbols are those of the elastic film of modulus E_inf
    (R = 1 exactly; the solvers then use ``Film`` itself, bit for bit).

    Periodic grids sample the symbols as they are (R(0) = 1 at k_x = 0: the periodic row of
    contacts).  Its images along x are those of the isolated contact once the period holds the
    relaxation tails (``domain_margin``) or once their images are summed (``tail_poles``: the
    tails longer than 2.7 h, lines and surfaces).  (Replaced: a band average of R over |k_x| <
    pi/L_x on the k_x = 0 modes of surfaces, which stood in for the tails' images beyond a
    period shorter than them but moved the sphere by ~1e-3 at V tau_r = 1-3 h, where the
    period held the tail: the period effect beyond the estimate in studies/README.)
    """

    relaxed_young: float | None = None
    prony: tuple = ()
    speed: float = 0.0

    def __post_init__(self):
        super().__post_init__()
        if self.relaxed_young is None:  # E_inf is the film's Young modulus (1 in the core)
            object.__setattr__(self, "relaxed_young", 1.0 if self.young is None else self.young)
            if self.young is not None and self.prony and \
                    max(e for e, _ in check_prony(self.prony)) < 1e-3 * self.young:
                # (before the ninth session E_inf defaulted to 1 here: moduli relative to it)
                import warnings

                warnings.warn(f"ViscoelasticFilm: every Prony modulus is below 1e-3 of young = "
                              f"E_inf = {self.young:g}; they are in young's unit (Pa), not "
                              f"relative to E_inf", UserWarning, stacklevel=3)
        elif self.young is not None and self.relaxed_young != self.young:
            raise InputError(f"ViscoelasticFilm: young is the relaxed modulus E_inf (as --young); "
                             f"got young {self.young:g} and relaxed_young {self.relaxed_young:g}: "
                             f"give one of them (dataclasses.replace: both, or relaxed_young="
                             f"None to follow young)")
        if not (self.relaxed_young > 0.0 and math.isfinite(self.relaxed_young)):
            raise InputError(f"ViscoelasticFilm: relaxed_young (E_inf) must be > 0 and finite; "
                             f"got {self.relaxed_young!r}")
        if not self.incompressible:
            raise InputError(f"--prony needs --poisson 0.5 (an incompressible film); got "
                             f"poisson {self.poisson:.10g}")
        object.__setattr__(self, "prony", check_prony(self.prony))

    def scene_fields(self) -> dict:
        """A scene's film (``solve(film=...)``): its thickness [m], E_inf [Pa] (``young``),
        poisson, speed [m/s] and Prony terms, as the scene's own fields (``Film.scene_fields``:
        the scene builds the same film, ``Scene.core_film``)."""
        if self.young is None:
            raise InputError("film: a scene's viscoelastic film needs young = E_inf [Pa] (the "
                             "relaxed modulus): ViscoelasticFilm(thickness=h [m], young=E_inf "
                             "[Pa], prony=((E_1 [Pa], tau_1 [s]), ...), speed=V [m/s])")
        return {"thickness": self.thickness, "young": self.young, "poisson": self.poisson,
                "speed": self.speed, "prony": self.prony}

    # --- the material ---------------------------------------------------------------------------
    @property
    def glassy_young(self) -> float:
        """E_0 = E_inf + sum E_i."""
        return self.relaxed_young + sum(e for e, _ in self.prony)

    def complex_modulus(self, omega):
        """G*(omega) = [E_inf + sum E_i i w tau_i/(1 + i w tau_i)] / 3 (time factor exp(+i w t)),
        in the unit of ``relaxed_young``."""
        w = np.asarray(omega, dtype=float)
        E = np.full(w.shape, self.relaxed_young, dtype=complex)
        for e, tau in self.prony:
            iwt = 1j * w * tau
            E = E + e * iwt / (1.0 + iwt)
        return E / 3.0

    def loss_tangent(self, omega):
        """tan delta = Im G* / Re G* at omega [rad/s]."""
        G = self.complex_modulus(omega)
        return G.imag / G.real

    def peak_loss_tangent(self) -> tuple[float, float]:
        """(max tan delta, its omega [rad/s]) over omega > 0 (a dense log scan refined by a
        golden-section search)."""
        taus = [t for _, t in self.prony] or [1.0]
        w = np.logspace(math.log10(0.01 / max(taus)), math.log10(100.0 / min(taus)), 2001)
        t = self.loss_tangent(w)
        j = int(np.argmax(t))
        lo, hi = math.log(w[max(j - 1, 0)]), math.log(w[min(j + 1, w.size - 1)])
        g = 0.5 * (math.sqrt(5.0) - 1.0)
        for _ in range(80):
            a, b = hi - g * (hi - lo), lo + g * (hi - lo)
            if self.loss_tangent(math.exp(a)) > self.loss_tangent(math.exp(b)):
                hi = b
            else:
                lo = a
        wm = math.exp(0.5 * (lo + hi))
        return float(self.loss_tangent(wm)), wm

    def retardation_times(self) -> list[float]:
        """The retardation times: -1/s at the zeros s < 0 of G*(s/i) = G_inf + sum G_i s tau_i /
        (1 + s tau_i), one between each pair of consecutive poles -1/tau_i and one in
        (-1/tau_max, 0): the decay lengths of the film's memory are V times them.  The largest
        is at most tau_max E_0/E_inf (equal for one term).  (Cached per Prony series: a line
        solve asked for them 7 times, 40 us each, ~4 % of a viscoelastic solve's CPU.)"""
        return list(_retardation_times(float(self.relaxed_young),
                                       tuple((float(e), float(t)) for e, t in self.prony)))

    # --- the symbols --------------------------------------------------------------------------
    @property
    def moving(self) -> bool:
        """Whether the symbols differ from the elastic film's (V != 0 and terms present)."""
        return self.speed != 0.0 and bool(self.prony)

    def partial_fractions(self) -> tuple[float, list[tuple[float, float]]]:
        """R(z) = G_inf/G*(z/i) = r + sum_j c_j / (1 + z tau_r,j): (r, [(c_j, tau_r,j)]), r =
        E_inf/E_0, c_j = tau_r,j / (d/dz G*/G_inf at z = -1/tau_r,j), sum c_j = 1 - r."""
        out = []
        for tr in self.retardation_times():
            z = -1.0 / tr
            deriv = sum(e / self.relaxed_young * t / (1.0 + z * t) ** 2 for e, t in self.prony)
            out.append((tr / deriv, tr))
        return self.relaxed_young / self.glassy_young, out

    def modulus_ratio(self, direction, kmag):
        """R(k) = G_inf / G*(-k_x V) (1 where V = 0)."""
        kx = np.asarray(kmag, dtype=float) * direction[0]
        if not self.moving:
            return np.ones_like(kx, dtype=complex)
        return (self.relaxed_young / 3.0) / self.complex_modulus(-kx * self.speed)

    def surface_compliance(self, direction, kmag, mu: float = 0.0, slide=(1.0, 0.0)):
        """The elastic film's H times R(k) (in units of 1/G_inf)."""
        H = super().surface_compliance(direction, kmag, mu, slide)
        return H * self.modulus_ratio(direction, kmag) if self.moving else H

    def shear_compliance(self, direction, kmag, slide=(1.0, 0.0)):
        H1 = super().shear_compliance(direction, kmag, slide)
        return H1 * self.modulus_ratio(direction, kmag) if self.moving else H1

    def surface_displacement_transfer(self, direction, kmag, p_hat, tau_hat):
        """Every displacement scales with 1/G: the elastic transfer times R(k)."""
        u, delta = super().surface_displacement_transfer(direction, kmag, p_hat, tau_hat)
        if not self.moving:
            return u, delta
        R = self.modulus_ratio(direction, kmag)
        return tuple(R * c for c in u), R * delta

    # --- the new length scales ----------------------------------------------------------------
    # decay_rate stays the elastic film's (the images' formula of solvers.fft): the tail's
    # images are summed (tail_poles) or covered by domain_margin, and bounded (image_factor)
    # or measured (solvers.fft, step 4)

    @property
    def tail_length(self) -> float:
        """|V| times the largest retardation time: the decay length of the relaxation tail
        behind the contact (0 when not moving)."""
        return abs(self.speed) * max(self.retardation_times()) if self.moving else 0.0

    def _long_tails(self) -> list[tuple[float, float]]:
        """[(c_j, l_j)]: the retardation terms whose tail l_j = V tau_r,j is long enough to have
        its periodic images summed (|l_j| decay_rate >= TAIL_CORRECTED); none at rest."""
        if not self.moving:
            return []
        _, terms = self.partial_fractions()
        return [(c, self.speed * tr) for c, tr in terms
                if abs(self.speed * tr) * self.decay_rate >= TAIL_CORRECTED]

    def tail_poles(self, mu: float = 0.0) -> list[tuple[float, object]]:
        """(l_j, B_j) of the relaxation tails that the FFT solvers sum exactly: l_j = V tau_r,j
        (signed like V) with |l_j| >= ``TAIL_CORRECTED`` / ``decay_rate``, and B_j(k_y) = c_j
        H(-i/l_j, k_y) (a function of k_y [1/length], array in, array out; lines: k_y = 0),
        H the elastic symbol continued to k_x = -i/l (``partial_fractions``: R = r + sum c_j /
        (1 - i k_x l_j)).

        The kernel of c_j H(k)/(1 - i k_x l_j) has, besides the elastic film's poles, one at
        k_x = -i/l_j: K_j(s_x, .) = exp(s_x/l_j)/|l_j| F_y^-1[B_j](.) for s_x/l_j < 0 (behind
        the load) plus terms that decay at the elastic rate (checked against a 2^22-point line
        kernel at l = 10 h and 100 h, mu 0 and 2: 1e-4 relative, the reference's own noise).
        With y = h/l, K_y = k_y h, kappa^2 = K_y^2 - y^2 (H = [F0(K) + i mu (k_x/|k|) F1(K)] /
        (2|k|) is a function of kappa^2 and k_x; F1 = 2K^2/D):

            B = c h [F0(kappa)/(2 kappa) + mu y / D(kappa)],   D = cosh 2kappa + 1 + 2kappa^2,

        with kappa = i t, t^2 = y^2 - K_y^2 > 0: F0/(2 kappa) = (sin 2t - 2t)/(2t D), D = cos 2t +
        1 - 2t^2.  Lines (K_y = 0): B = c h [(sin 2y - 2y)/(2y) + mu y]/(cos 2y + 1 - 2y^2),
        -y^2 h/3 + mu y h/2 for y -> 0: a long line tail weighs ~ (h/l)^2 without friction,
        ~ mu h/l with it; on a surface B(k_y) -> c H(k_y) for k_y >> 1/l: the tail of a
        contact of width w << l carries its elastic sinking, not (h/l)^2 of it.  (Amontons
        friction along x only: a Prony film takes no other law.)  Terms with |l| <
        TAIL_CORRECTED / decay_rate decay within a few elastic decay lengths (their pole is
        near D's zero at y = 0.739, where B diverges and the elastic poles' residues with
        it): they stay in ``domain_margin``."""
        h = self.thickness
        return [(length, _tail_symbol(c, h, h / length, mu)) for c, length in self._long_tails()]

    def image_factor(self) -> float | None:
        """Bound of the periodic images' effect on a line contact relative to the elastic
        film's (``Film``: 1), or None (the line solver then measures the images on twice the
        period, as for every viscoelastic line before).

        The kernel of H(k) R(k) far from the load is a sum of residues at the symbol's poles in
        the half-plane of the side (R = r + sum c_j / (1 - i k_x l_j), ``partial_fractions``):
        the elastic film's, the zeros of D = cosh 2K + 1 + 2K^2, each times R there, and the
        tails' k_x = -i/l_j (behind the load only).  The nearest elastic ones, k_x = +-i kappa
        (kappa = ``decay_rate`` = 0.7391/h: cos t = t at t = kappa h), carry R(+-i kappa) = r
        + sum c_j / (1 +- kappa l_j) (real); the next are at |Im k_x| h = 2.487 (K = 1.809 +
        2.487 i), whose share at the period's margin (kappa s >= ln(100/tol)) is below
        exp(-1.75 s/h) < 1e-10 of the nearest's.  A bound is known when every tail is either

        - summed (kappa |l_j| >= TAIL_CORRECTED = 2, ``tail_poles``: its own pole's images are
          exact): its share at the elastic pole is |c_j / (1 -+ kappa |l_j|)| <= c_j / 1; or
        - short (kappa |l_j| <= 1/2): its share is at most c_j / (1 - kappa |l_j|) <= 2 c_j,
          and its own pole decays at 1/|l_j| >= 2 kappa: its images are below the square of
          the elastic ones at the margin;

        between (1/2 < kappa |l_j| < 2) the tail's pole meets the elastic one (a double pole at
        kappa |l_j| = 1, a far field ~ s exp(-kappa s)): None.  The images' far field is then
        at most max |R(+-i kappa)| times the elastic one, and the contact it acts on is at
        least as stiff as the relaxed film and at most as the glassy one (|G*(w)| <= G_0:
        |R(k)| >= r = E_inf/E_0 on every real k), so their relative effect is at most

            factor = max(|R(i kappa)|, |R(-i kappa)|) / r      (>= 1),

        times the elastic film's (the line solver's measured amplitude, in its estimate, on
        frictionless contacts; where that passes tol/4 on the period's margin, factor > ~12.5,
        or with friction it measures them).  Checked on `python -m studies.viscoelastic
        --parts images` (the fixed grid on its period against twice it, 54 frictionless
        full-path solves: 0.02-0.24 of the bound).  Without the 1/r the paper's scene (mu 2)
        at 0.32 m/s (kappa l_r = 2.3, a glassy contact under a far field R(i kappa) = 0.65)
        was 1.07 times the bound; with it, on a film 11 times stiffer when glassy, 1.6 times:
        friction can bring the indentation d (relative to itself in the estimate) far below
        the elastic film's, which the 1/r does not bound (``solvers.fft``)."""
        if not self.moving:
            return 1.0
        r, terms = self.partial_fractions()
        kappa = self.decay_rate
        ahead = behind = r
        for c, tr in terms:
            kl = kappa * abs(self.speed) * tr
            if 0.5 < kl < TAIL_CORRECTED:
                return None
            ahead += c / (1.0 + kl)
            behind += c / (1.0 - kl)
        return max(1.0, abs(ahead) / r, abs(behind) / r)

    def tail_displacement_poles(self, mu: float = 0.0) -> list[tuple[float, object, object]]:
        """(l_j, Bx_j, By_j) of the same summed tails (``tail_poles``) for the surface's
        in-plane displacements u_x, u_y of a surface under the pressure p and the shear mu p
        along x: Bx_j(k_y), By_j(k_y) = c_j U_x, U_y at k_x = -i/l_j (arrays of k_y
        [1/length], complex; surfaces' output fields).  U = the elastic transfer
        (``Film.surface_displacement_transfer``) with tau = (mu p, 0): in h units, K_x = k_x h,
        K_y = k_y h, K^2 = K_x^2 + K_y^2,

            U_x / h = mu [K_x^2 F2/(2K) + K_y^2 tanh(K)/K] / K^2 - i K_x / D,
            U_y / h = mu K_x K_y [F2/(2K) - tanh(K)/K] / K^2 - i K_y / D,

        even functions of K (the 1/K^2 removable: F2/(2K), tanh(K)/K -> 1); at K_x = -i y
        (y = h/l), K^2 = K_y^2 - y^2.  A long tail carries the uniform shear's u = mu h p (U_x
        -> h (mu - y/2) on a line): without its images summed the periodic u_x, u_y near the
        contact were off by ~ the tail's weight times the contact's size over the period (the
        sphere at V tau_r = 30 h, mu 0.5, on the 15 h period: 14 % of max |u_x| against four
        times the period; tests/test_viscoelastic.py)."""
        h = self.thickness
        return [(length, *_tail_displacement_symbols(c, h, h / length, mu))
                for c, length in self._long_tails()]

    def tail_amplitude(self, length: float | None = None) -> float:
        """Relative amplitude of the relaxation tail behind the contact: c min(1, (2h/l)^2), c =
        1 - E_inf/E_0 the relaxing part's weight, l = ``length`` (default ``tail_length``).  A
        tail much longer than the film is thick carries the elastic sinking smeared over l,
        whose first two moments
        vanish on an incompressible film (H ~ k^2/3 at small k): its amplitude falls as
        (h/l)^2 (for l >> h, the tail's residue H(-i/l)/l ~ 1/(3 l^3) over the contact's
        1/l).  Used for the period's margin only; the images' effect is then measured
        (``solvers.fft``)."""
        if not self.moving:
            return 0.0
        c = 1.0 - self.relaxed_young / self.glassy_young
        return c * min(1.0, (2.0 * self.thickness / (length or self.tail_length)) ** 2)

    def domain_margin(self, tol: float, tails_corrected: bool = False) -> float:
        """The locator's margin and a first bound (lines and, since the tenth session, surfaces
        along x take ``line_margin`` once the contact is located: from the far field, where the
        decays do not add): the elastic margin plus the tail's: l ln(100 A/tol), A =
        ``tail_amplitude(l)`` (the two decays added, the tail being the elastic sinking smeared
        behind the load over l),
        l = ``tail_length``; ``tails_corrected`` (lines: the tails of ``tail_poles`` have their
        images summed exactly by the solver): l the longest retardation length left, < 2.7 h,
        or the elastic margin alone.  The images are then measured (``solvers.fft``).
        (Tried and reverted before the exact sum: a shorter line margin, ln(A/tol), with the
        images measured on twice the period: the paper's scene (mu 2) at 10 m/s kept changing
        by 6.4e-4 > tol/4 at tol 1e-3 over three doublings: the images of a tail l >> L fall
        only as l/L, not exponentially (``numerics.operators.tail_terms``).  For surfaces a 20
        times larger amplitude: the sphere's changes on twice the period did not fall with it
        (0.3 m/s: 1.7e-3 -> 9.7e-4, 1 m/s: 5.2e-4 -> 7.8e-4), so they are not the tail's
        images alone; studies/README, viscoelastic.)"""
        m = super().domain_margin(tol)
        if not self.moving:
            return m
        tail = self.tail_length
        if tails_corrected:  # the line solver sums the long tails' images (``tail_poles``)
            tail = max([abs(self.speed) * t for t in self.retardation_times()
                        if abs(self.speed) * t * self.decay_rate < TAIL_CORRECTED], default=0.0)
            if tail == 0.0:
                return m
        return m + tail * max(math.log(100.0 * self.tail_amplitude(tail) / tol), 0.0)

    def line_far_field(self, d, mu: float = 0.0):
        """The line kernel's far field at distances ``d`` (array, >= 0, lengths of
        ``thickness``) from the load, behind it and ahead of it, without the summed tails'
        own poles (their images are exact, ``tail_poles``), relative to the elastic film's
        largest far-field amplitude (max(|A_b|, |A_a|) below): (behind, ahead), signed.

        The kernel of H(k) R(k) (Amontons ``mu`` in the contact, signed as the scene's; R = r
        + sum c_j / (1 - i k_x l_j), ``partial_fractions``) is, beyond a few thicknesses, the
        sum of the residues at the poles nearest the real axis: the elastic film's k_x =
        -+i kappa (kappa = ``decay_rate``, t0 = kappa h: cos t0 = t0), each times R there, and
        behind the load the tails' k_x = -i/l_j (``tail_poles``: B_j exp(-d/l_j)/l_j).  In the
        mirrored frame of V > 0 (V < 0: s -> -s, mu -> -mu; m = mu sign V), with y_j = h/l_j,

            behind:  A_b [r + sum_summed c_j/(1 - kappa l_j)] exp(-kappa d)
                     + sum_others c_j [A_b exp(-kappa d)/(1 - kappa l_j) + y_j phi(y_j) exp(-d/l_j)],
            ahead:   A_a R(i kappa) exp(-kappa d),      R(i kappa) = r + sum c_j/(1 + kappa l_j),

        A_b, A_a = (g0 +- m t0) / (2 S), g0 = (sin 2t0 - 2t0)/(2t0), S = sin 2t0 + 2t0 (the
        residues of H = h [(sinh 2K - 2K)/(2K D) + i m K/D], K = k_x h, D = cosh 2K + 1 + 2K^2,
        at K = -+i t0), phi(y) = [(sin 2y - 2y)/(2y) + m y] / (cos 2y + 1 - 2y^2) (= B_j/(c_j h),
        ``tail_poles``).  Checked against the kernel of a 2^20-point line (period 4000 h) at
        kappa l = 0, 0.074, 0.74, 1.48, mu 0 and +-2, V +-: to the reference's noise (1e-8).
        At kappa l_j = 1 the two poles meet (a double pole): the term is evaluated as
        c_j A_b (exp(-kappa d) - exp(-d/l_j))/(1 - kappa l_j) (-> c_j A_b (d/l_j) exp(-kappa d))
        plus c_j beta_j exp(-d/l_j), beta_j = y_j phi(y_j) + A_b/(1 - kappa l_j) regular (within
        1e-3 of the double pole: the mean of beta at y = t0 (1 +- 2e-3))."""
        return self._far_field(np.asarray(d, dtype=float), self._far_parts(mu))

    def _far_parts(self, mu: float):
        """(A_b, A_a, norm, r_b, r_a, [(c_j, l_j, beta_j)]) of ``line_far_field`` (computed
        once per margin: the retardation times are a bisection)."""
        h, kappa = self.thickness, self.decay_rate
        t0 = kappa * h
        S = math.sin(2.0 * t0) + 2.0 * t0
        g0 = (math.sin(2.0 * t0) - 2.0 * t0) / (2.0 * t0)
        m = mu * (1.0 if self.speed >= 0.0 else -1.0)
        Ab, Aa = (g0 + m * t0) / (2.0 * S), (g0 - m * t0) / (2.0 * S)
        r, terms = self.partial_fractions() if self.moving else (1.0, [])
        r_b = r_a = r
        tails = []
        for c, tr in terms:
            length = abs(self.speed) * tr
            kl = kappa * length
            r_a += c / (1.0 + kl)
            if kl >= TAIL_CORRECTED:  # its own pole's images are summed: only R(-i kappa)
                r_b += c / (1.0 - kl)
                continue
            y = h / length
            beta = (0.5 * sum(_tail_beta(t0 * (1.0 + e), t0, m, Ab) for e in (2e-3, -2e-3))
                    if abs(y / t0 - 1.0) < 1e-3 else _tail_beta(y, t0, m, Ab))
            tails.append((c, length, beta))
        return Ab, Aa, max(abs(Ab), abs(Aa)), r_b, r_a, tails

    def _far_field(self, d, parts):
        """``line_far_field`` at the array ``d`` from ``_far_parts``."""
        Ab, Aa, norm, r_b, r_a, tails = parts
        kappa = self.decay_rate
        el = np.exp(-kappa * d)
        behind = r_b * Ab * el
        for c, length, beta in tails:
            x = (1.0 - kappa * length) * d / length  # (exp(-kappa d) - exp(-d/l))/(1 - kappa l)
            xs = np.where(np.abs(x) > 1e-12, x, 1.0)
            meet = el * (d / length) * np.where(np.abs(x) > 1e-12, -np.expm1(-xs) / xs, 1.0)
            # (the exponent capped at 700: exp underflows slowly, to 0 beyond 745)
            behind = behind + c * (Ab * meet + beta * np.exp(-np.minimum(d / length, 700.0)))
        return behind / norm, r_a * Aa * el / norm

    def line_margin(self, tol: float, mu: float = 0.0, size: float | None = None) -> float:
        """The period's margin of a line (lengths of ``thickness``; Amontons ``mu`` in the
        contact; the long tails' images summed, ``tail_poles``): the shortest free length d
        beyond which the kernel's far field (``line_far_field``: both sides, relative to the
        elastic film's largest amplitude) stays below tol/100 times |R(1/size)| (1 without a
        ``size``), as the elastic film's exp(-kappa d) does beyond ``Film.domain_margin``.

        The images displace the surface over the contact smoothly (the far field varies over
        1/kappa = 1.35 h); a, x_c, d and p_max change by that over the contact's own
        compliance, ~ H(k) R(k) at k ~ 1/a: the far field is taken relative to |R(1/a)| (r =
        E_inf/E_0 <= |R| <= 1; a glassy contact, |R| -> r, is r times stiffer and its far field
        r times smaller: the elastic margin; without the |R| such margins were ln(1/r)/kappa
        shorter, and the paper's scene on a film 11 times stiffer when glassy (0.1 m/s)
        failed the measured images' tol/4 and doubled its period).  The decays do not add:
        for kappa l < 1 the tail's exp(-d/l) decays faster than the elastic exp(-kappa d) and
        the margin is the elastic one plus ln(|R(-i kappa)|/|R(1/a)|)/kappa; for kappa l > 1
        the tail's decay sets it (l ln(amplitude/tol)); near kappa l = 1 the double pole's
        d exp(-kappa d).  (Was ``domain_margin``: the elastic margin plus l ln(100 A/tol),
        the two decays added: periods 1.2-1.7 times the elastic one at kappa l 0.2-0.8;
        studies/README, viscoelastic, images.)  The last crossing of the target on a grid of
        h/20 (up to where a monotone bound of the far field, each term's modulus, the double
        pole's bounded by d/l exp(-min(kappa, 1/l) d), is below it), then within that step
        log-linearly (checked: the step's end where it falls short), so that the period moves
        with the physics only (rounded to h/20, a slow film's period moved by up to 0.05 h
        from the elastic one, and the final grids with it: studies/README).  The images are
        then bounded (``image_factor``) or measured as before (``solvers.fft``)."""
        if not self.moving:
            return self.domain_margin(tol)
        h = self.thickness
        stiff = 1.0 if size is None else float(abs(
            self.modulus_ratio((1.0, 0.0), np.array([1.0 / max(size, 1e-12)]))[0]))
        target = 1e-2 * tol * stiff
        step = h / 20.0
        # the monotone bound's end: double the trial length until it is below the target
        parts = self._far_parts(mu)
        d_hi = max(Film.domain_margin(self, tol), 2.0 * h)  # the elastic margin
        for _ in range(60):
            if self._far_bound(d_hi, parts) <= target:
                break
            d_hi *= 2.0
        d = np.arange(0.0, d_hi + step, step)
        behind, ahead = self._far_field(d, parts)
        far = np.maximum(np.abs(behind), np.abs(ahead))
        above = np.nonzero(far > target)[0]
        if not above.size:
            return 0.0
        # the last crossing within its step, log-linear (the far field is exponential there):
        # no h/20 rounding; the grid's point beyond it should the interpolation fall short
        k = above[-1]
        f0, f1 = math.log(far[k]), math.log(max(far[k + 1], 1e-300))
        m = float(d[k] + step * (f0 - math.log(target)) / (f0 - f1))
        b, a = self._far_field(np.array([m]), parts)
        return m if max(abs(b[0]), abs(a[0])) <= target * (1.0 + 1e-9) else float(d[k + 1])

    def _far_bound(self, d: float, parts) -> float:
        """An upper bound of |``line_far_field``| at every distance >= d >= the longest
        unsummed tail and 1/kappa (each term's modulus, decreasing there; ``_far_parts``)."""
        Ab, Aa, norm, r_b, r_a, tails = parts
        kappa = self.decay_rate
        el = math.exp(-kappa * d)
        rest = 0.0
        for c, length, beta in tails:
            if d < length or d < 1.0 / kappa:
                return math.inf
            rest += abs(c) * (abs(Ab) * (d / length) * math.exp(-min(kappa, 1.0 / length) * d)
                              + abs(beta) * math.exp(-d / length))
        return max(abs(r_b * Ab) * el + rest, abs(r_a * Aa) * el) / norm

    def trailing_edge_layer(self):
        """(side, [(c_j, |V| tau_r,j)]): behind the trailing edge (the left one for V > 0,
        side -1; the right one for V < 0) the gap opens through the film's memory, glassy
        within |V| tau_r,j of the edge, relaxed and delayed beyond (``partial_fractions``:
        R = r + sum c_j / (1 - i k_x V tau_r,j); ``numerics.edges.viscous_gap``).  None at
        rest."""
        if not self.moving:
            return None
        _, terms = self.partial_fractions()
        return (-1 if self.speed > 0 else 1), [(c, abs(self.speed) * tr) for c, tr in terms]

    def edge_scales(self) -> list[tuple[float, float]]:
        """(|V| tau_i, E_i/E_inf) per term: the widths of the edge structure each term makes
        and its weight."""
        if not self.moving:
            return []
        return [(abs(self.speed) * t, e / self.relaxed_young) for e, t in self.prony]

    # (``merged_weights``, module level) terms whose relaxation times lie within this factor
    # of each other are one heavy term for the edge fits: three terms of 10 E_inf at tau/c,
    # tau, c tau (a_H/h 0.3, mu 0, 0.17 mm/s, tol 1e-2) were not carried by the fits at c = 1,
    # 1.5, 2, 3.16 (c = 1, the same film as one 30 E_inf term, stopped 23 % off in p_max under
    # an estimate of 8.8e-3; from 1.5 the levels stagnated and the resolved retry solved it)
    # and were at c = 5, 10 (the audit, at c = 4.5 and 5, a_H/h 0.3 and 1, 7 speeds: 28 of 28
    # bounded; studies/README, viscoelastic, an audit of the estimates, tenth session)
    MERGE_FACTOR = MERGE_FACTOR

    def merged_weights(self) -> list[float]:
        """Per term, the summed E_j/E_inf of the terms whose tau_j is within MERGE_FACTOR of its
        tau_i (itself included): the weight that decides whether the edge fits carry its
        structure (the fitted range, the leading-edge peak); the bounds keep ``edge_scales``'
        own weights.  Equal to ``edge_scales``' weights for terms more than a factor 4 apart.  A
        verified 10 E_inf term with any neighbour within the factor, however light, is then
        beyond the fitted range and resolved: the range's edge is a cliff (as a single term of
        10.01 E_inf is), safe, not smooth (10 E_inf + 0.01 E_inf at 2 tau: 2048 -> 32768
        points at 0.3 mm/s, the same p_max and a within 1e-5)."""
        return merged_weights(self.prony, self.relaxed_young) if self.moving else []


    # --- slow sliding: the first-order theory ---------------------------------------------------
    @property
    def slow_shift(self) -> float:
        """delta = V sum (E_i/E_inf) tau_i (signed like V, lengths of ``thickness``): the first
        moment of the symbol, R(k) = 1 + i k delta + O(k^2 delta l_r) (module docstring).

        Slow sliding (every V tau_r,i << a, h): the pressure is the relaxed elastic one
        translated by delta (the sinking delayed: s = s_e + delta s_e'), and the edge layers of
        width ~V tau_i set the edges: the leading edge stays where the relaxed elastic one is,
        the trailing edge moves toward the centre by |delta|; so a = a_el - |delta|/2, x_c =
        x_c,el + delta/2, the pressure's centroid x_p = x_p,el + delta, d and p_max unchanged,
        to first order.  Found in Hunter's closed form (``reference.hunter``: for r = E_inf/E_0
        = 0.05 ... 0.8 the remainders of a, x_c and x_p are below (1 + r)/2 (delta/a)(l_r/a))
        and confirmed on the film (a_H/h 0.3, V tau/h = 1.6e-4 against a 2^20-point resolved
        solve: a, x_c, d, p_max within 8e-6, below that solve's own estimate)."""
        if not self.moving:
            return 0.0
        return self.speed * sum(e * t for e, t in self.prony) / self.relaxed_young

    @property
    def slow_second_moment(self) -> float:
        """m2 = sum c_j l_j^2 (l_j = |V| tau_r,j, ``partial_fractions``; lengths^2 of
        ``thickness``): R(k) = 1 + i k delta + (i k)^2 m2 + O(k^3) (delta l_r for one term)."""
        if not self.moving:
            return 0.0
        return sum(c * (self.speed * tr) ** 2 for c, tr in self.partial_fractions()[1])

    def slow_centroid_second_order(self, edge_amplitudes_sq: float, load: float) -> float:
        """The second-order shift [h] of the pressure's centroid in slow sliding of a
        frictionless cylinder (f = x^2 in the core's units, f'' = 2) on this film:
        -(pi/16) (A_1^2 + A_2^2) (m2 - delta^2/2) / (f'' P), A_e the relaxed elastic pressure's
        edge amplitudes (p = A_e sqrt(eps) at distance eps inside edge e), P the load.

        Derivation (energy identity, exact for any pressure of a frictionless contact, H the
        film's real even symbol): F_def = Int p f' dx = -<p, D K_R p> = sum_j c_j l_j Int
        |p_hat|^2 H k^2 / (1 + k^2 l_j^2) dk/2pi.  Its first order, delta Int |p_hat|^2 H k^2 =
        delta <p, -s_e''> = delta f'' P, is x_p = delta; the departure of 1/(1 + k^2 l_j^2)
        from 1 acts at k ~ 1/l_j >> 1/a, where the two square-root edges give |p_hat|^2 =
        (pi/4)(A_1^2 + A_2^2)|k|^-3 and H = 1/(2|k|) (the film is a half-space there): -(pi/16)
        (A_1^2 + A_2^2) m2.  The first-order pressure change at the leading edge adds +(pi/16)
        (A_1^2 + A_2^2) delta^2/2: taken from Hunter's closed form (r = 0.2-0.8: the sum is
        -(1 + r)/2 delta l_r / a, A^2 = 32 a; tests/test_hunter.py), m2 - delta^2/2 being the
        (ik)^2 coefficient of R exp(-ik delta).  For V > 0; V < 0 the mirror (the sign flips:
        the high-wavenumber integral is c_j l_j |l_j|).  Checked on the film (studies.viscoelastic
        --parts second): a_H/h 0.1, 1, 3 at V tau/h 1.6e-4 ... 1.6e-2, the first-order
        centroid's error 2e-6 ... 8e-4 of a left at <= 7e-7 of a with this term (and a
        two-term series: 8.1e-5 -> 6e-9)."""
        if not self.moving:
            return 0.0
        delta = self.slow_shift
        c2 = self.slow_second_moment - 0.5 * delta * delta
        # odd in V (the mirror): c_j l_j |l_j| in the identity, l_j = V tau_r,j
        return -math.copysign(1.0, self.speed) * (math.pi / 16.0) * edge_amplitudes_sq * c2 \
            / (2.0 * load)

    def slow_remainder(self, a: float) -> float:
        """Bound of the second-order remainder of the slow-sliding theory on a contact of
        half-width ``a`` (relative to a for a, x_c and x_p, to themselves for d and p_max):
        2 |delta| l_r / min(a, h)^2, l_r = ``tail_length`` (the symbol's second-order term is
        delta l_r k^2, k ~ 1/min(a, h); twice the half-space's largest coefficient, 0.9)."""
        if not self.moving:
            return 0.0
        s = min(a, self.thickness)
        return 2.0 * abs(self.slow_shift) * self.tail_length / (s * s)


TAIL_CORRECTED = 2.0
"""|l| x decay_rate from which a relaxation tail's periodic images are summed exactly on line
grids (``ViscoelasticFilm.tail_poles``): l >= 2.7 h on the incompressible film."""


def _tail_symbol(c: float, h: float, y: float, mu: float):
    """k_y -> c H(-i y/h, k_y) (``ViscoelasticFilm.tail_poles``), |y| < 0.37."""
    def coefficient(ky):
        K2 = (np.asarray(ky, dtype=float) * h) ** 2 - y * y  # kappa^2
        out = np.empty(K2.shape)
        im = K2 < 0.0
        t = np.sqrt(-K2[im])
        D = np.cos(2.0 * t) + 1.0 - 2.0 * t * t
        tt = np.maximum(t, 1e-300)
        g0 = np.where(t > 1e-4, (np.sin(2.0 * tt) - 2.0 * tt) / (2.0 * tt * D), -t * t / (3.0 * D))
        out[im] = g0 + mu * y / D
        if im.all():  # (every line's: k_y = 0; the real branch below would assign nothing)
            return c * h * out
        K = np.sqrt(K2[~im])
        F0, F1, *_ = transfer_functions(K)
        Ks = np.maximum(K, 1e-300)
        # F0/(2K) (-> K^2/3 at 0) and 1/D = F1/(2K^2) (-> 1/2)
        out[~im] = (np.where(K > 1e-4, F0 / (2.0 * Ks), K * K / 3.0)
                    + mu * y * np.where(K > 1e-4, F1 / (2.0 * Ks * Ks), 0.5))
        return c * h * out
    return coefficient


def _tail_beta(y: float, t0: float, m: float, Ab: float) -> float:
    """y phi(y) + A_b y/(y - t0) (``ViscoelasticFilm.line_far_field``): the tail's residue
    (B/(c l)) less the part that cancels the elastic pole's c A_b/(1 - kappa l) at y = t0."""
    D = math.cos(2.0 * y) + 1.0 - 2.0 * y * y
    phi = ((math.sin(2.0 * y) - 2.0 * y) / (2.0 * y) + m * y) / D
    return y * phi + Ab * y / (y - t0)


def _even_parts(K2):
    """(F2/(2K) - 1)/K^2, (tanh(K)/K - 1)/K^2 and 1/D at real K^2 (arrays; K = i t for K^2 <
    0, |K^2| < 0.5: below the first zero of D, t = 0.739): even functions of K, so real; their
    series at |K^2| < 2e-3 (sympy: -5/3 + 46 K^2/15 - 1769 K^4/315 + 29146 K^6/2835 and -1/3
    + 2 K^2/15 - 17 K^4/315 + 62 K^6/2835; the rest below 1e-8 there, 2e-7 at 1e-2)."""
    K2 = np.asarray(K2, dtype=float)
    f2 = np.empty(K2.shape)  # F2/(2K)
    tT = np.empty(K2.shape)  # tanh(K)/K
    iD = np.empty(K2.shape)  # 1/D
    neg = K2 < 0.0
    t = np.sqrt(-K2[neg])
    ts = np.maximum(t, 1e-300)
    D = np.cos(2.0 * t) + 1.0 - 2.0 * t * t
    f2[neg] = (np.sin(2.0 * ts) + 2.0 * ts) / (2.0 * ts * D)
    tT[neg] = np.tan(ts) / ts
    iD[neg] = 1.0 / D
    K = np.sqrt(K2[~neg])
    Ks = np.where(K > 1e-4, K, 1.0)  # (below: the limits; f2 is then used through its series)
    _, F1, *_ = transfer_functions(K)
    f2[~neg] = np.where(K > 1e-4, F2(Ks) / (2.0 * Ks), 1.0)
    tT[~neg] = tanh_over(K)
    iD[~neg] = np.where(K > 1e-4, F1 / (2.0 * Ks * Ks), 0.5)  # 1/D = F1/(2K^2)
    small = np.abs(K2) < 2e-3
    safe = np.where(small, 1.0, K2)
    x = K2
    pf = np.where(small, -5.0 / 3.0 + x * (46.0 / 15.0 + x * (-1769.0 / 315.0 + x * 29146.0 / 2835.0)),
                  (f2 - 1.0) / safe)
    pg = np.where(small, -1.0 / 3.0 + x * (2.0 / 15.0 + x * (-17.0 / 315.0 + x * 62.0 / 2835.0)),
                  (tT - 1.0) / safe)
    return pf, pg, iD


def _tail_displacement_symbols(c: float, h: float, y: float, mu: float):
    """k_y -> c U_x(-i y/h, k_y), c U_y(-i y/h, k_y) (``ViscoelasticFilm.tail_displacement_poles``):
    with K_x = -i y, U_x/h = mu [1 - y^2 pf + K_y^2 pg] - y/D, U_y/h = -i K_y [mu y (pf - pg)
    + 1/D] (pf, pg, 1/D: ``_even_parts`` at K^2 = K_y^2 - y^2)."""
    def parts(ky):
        Ky = np.asarray(ky, dtype=float) * h
        return Ky, _even_parts(Ky * Ky - y * y)

    def bx(ky):
        Ky, (pf, pg, iD) = parts(ky)
        return (c * h * (mu * (1.0 - y * y * pf + Ky * Ky * pg) - y * iD)).astype(complex)

    def by(ky):
        Ky, (pf, pg, iD) = parts(ky)
        return c * h * (-1j * Ky * (mu * y * (pf - pg) + iD))
    return bx, by


def film_of(scene) -> Film:
    """The film of a ``Scene``/``Scene3D`` in the core's units: ``scene.core_film()`` (kept for
    callers of the earlier name)."""
    return scene.core_film()
