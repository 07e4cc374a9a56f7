"""The film: an elastic layer (incompressible by default) of thickness h bonded to a rigid
base, and the one factory of its Fourier symbols (physics.md; physics3d.md; the paper's Eqs. bc3-bc4, Z1-Z6).

Conventions.  Fields are sums of exp(+i k.x) (numpy's), x = (x, y) on the surface, x the sliding
direction.  A wavevector is given as its direction n = k/|k| (a tuple of broadcastable arrays,
one per surface dimension: 1 for plane strain, 2 for 3D) and its magnitude |k|; K = |k| h.
At k = 0 the direction is taken as n = e_x (any choice gives the same symbols there).
Surface tractions at z = h: sigma_zz = -p (p >= 0 in compression) and the shear
tau = (sigma_xz, sigma_yz); base (z = 0) tractions are returned the same way.

Surface compliance, for sliding along the unit vector e with Amontons friction tau = mu p e:
the surface sinks by w = -u_z with

    w^ = H p^,     H = [F0(K) + i mu (e . n) F1(K)] / (2 |k|),     H(k = 0) = 0 (nu = 1/2),

in units of 1/G (G = E/3 at nu = 1/2; G = E/(2(1 + nu)) in general, with F0, F1 of the
compressible film for nu < 1/2 and H(0) = (1 - 2nu) h/(2(1 - nu))); in the paper's
dimensionless units (k in 1/h, stresses in G h/2R, displacements in h^2/2R) exactly the
expression above.  The mu term is odd in k: the operator is not symmetric.  H(0) = 0: a uniform
pressure does not move an incompressible film (a compressible one sinks by H(0) p).

Base stresses, from the surface tractions (by isotropy each mode splits into the sagittal
plane-strain problem along n and an anti-plane one across it, physics3d.md):

    sigma_zz^(0) = A sigma_zz^(h) + i B tau_L^(h),          tau_L = n . tau
    tau_L^(0)    = C tau_L^(h)    + i B' sigma_zz^(h)      (B' = B at nu = 1/2)
    tau_T^(0)    = tau_T^(h) / cosh K                        tau_T = tau - n tau_L

written as tau^(0) = n tau_L^(0) + (tau^(h) - n tau_L^(h)) / cosh K, which in 1D (n = +1 on the
real-FFT half spectrum) is exactly physics.md's sigma_xz^(0) = C sigma_xz^(h) + i B sigma_zz^(h).
At k = 0: sigma_zz^(0) = sigma_zz^(h), tau^(0) = tau^(h) (the base carries the loads).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .options import option
from .transfer import (
    F2,
    compliance_functions,
    compressible_decay_rate,
    compressible_tangential_function,
    compressible_transfer_functions,
    tanh_over,
    transfer_functions,
)

__all__ = ["Film", "DECAY_RATE", "surface_compliance", "base_stresses"]

DECAY_RATE = 0.7390851332151607
"""Slowest exponential decay rate (in 1/h) of the film's kernels in x: the pole of 1/D(k) at
k = i*0.739... (D = cosh 2k + 1 + 2k^2 vanishes where cos y = y).  Periodic images at distance s
perturb the solution by ~exp(-DECAY_RATE * s)."""


def _sech(K: np.ndarray) -> np.ndarray:
    """1/cosh K without overflow."""
    e = np.exp(-np.abs(K))
    return 2.0 * e / (1.0 + e * e)


@dataclass(frozen=True)
class Film:
    """An elastic film bonded to a rigid base (incompressible, nu = 1/2, by default).

    Parameters
    ----------
    thickness : float
        h, in the unit of the wavenumbers' lengths (1 in the dimensionless core, where lengths
        are in h; metres where wavenumbers are in 1/m).

    poisson : float
        nu, Poisson ratio, in [0, 1/2] (default 1/2: incompressible).  For nu < 1/2 the symbols
        are those of the compressible film (physics3d.md; ``transfer.compressible_transfer_
        functions``), still in units of the shear modulus G = E / (2(1 + nu)): H below is the
        sinking per pressure times G.  Then H(k = 0) = (1 - 2nu) h / (2(1 - nu)) (a uniform
        pressure p sinks the film by h (1 - 2nu) p / (2G (1 - nu)): uniaxial strain), and the
        friction couples into the sinking even on a half-space (Dundurs).  nu = 1/2 takes the
        incompressible code path unchanged (bit-identical symbols).

    young : float, optional
        E [Pa], where the film is a scene's (``solve(film=Film(thickness=2e-3, young=2.2e6))``:
        thickness in metres then); None in the core, whose stresses are in units of G.

    The film's parameters live here, so that every symbol of the package comes from one place.

    A film of another kind (another base, a coating, ...) is a subclass that supplies its own
    symbols: ``transfer(K)`` (the plane-strain transfer functions at K = |k| h, in units of the
    shear modulus G), and where they differ ``uniform_compliance`` (its sinking under a uniform
    pressure), ``decay_rate`` (the slowest decay of its kernels: the periodic grids' margin) and
    ``tangential(K)`` (the surface's tangential displacement, for the 3D displacements).  Extra
    fields of the subclass are kept as they are when the solvers take the film to the core's
    units (``core``): give them dimensionless (in h and G).  README, "Adding things", shows one.
    """

    thickness: float = 1.0
    poisson: float = 0.5
    young: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "poisson", option("poisson").check(self.poisson))
        object.__setattr__(self, "thickness", option("thickness").check(self.thickness))
        if self.young is not None:
            object.__setattr__(self, "young", option("young").check(self.young))

    def scene_fields(self) -> dict:
        """The scene fields this film stands for, when it is a kind the scene builds itself
        (``Scene.core_film``; a ``ViscoelasticFilm``: thickness, young, poisson, speed, prony):
        the scene then takes them instead of the object.  {}: the solvers take the film as it
        is (the elastic film, a user's kind)."""
        return {}

    def core(self) -> Film:
        """This film in the dimensionless core's units: thickness 1, stresses in G (the same
        kind, with the same extra fields)."""
        if self.thickness == 1.0 and self.young is None:
            return self
        return replace(self, thickness=1.0, young=None)

    @property
    def incompressible(self) -> bool:
        return self.poisson == 0.5

    def transfer(self, K):
        """(F0, F1, A, B, B', C) at K = |k| h (arrays): the surface sinking per pressure and its
        coupling to the shear (x 2|k|/G), and the base tractions per surface traction
        (``physics.transfer``; B' = B at nu = 1/2).  A film of another kind overrides this."""
        if self.incompressible:
            F0, F1, A, B, C = transfer_functions(K)
            return F0, F1, A, B, B, C
        return compressible_transfer_functions(K, self.poisson)

    def tangential(self, K):
        """F2 at K = |k| h: the surface's displacement along the shear, per shear x 2|k|/G."""
        if self.incompressible:
            return F2(K)
        return compressible_tangential_function(K, self.poisson)

    @property
    def decay_rate(self) -> float:
        """Slowest decay rate of the film's kernels in real space [1/length] (0.7391/h at
        nu = 1/2, 0.9128/h at nu = 0.3: ``transfer.compressible_decay_rate``)."""
        if self.incompressible:
            return DECAY_RATE / self.thickness
        return compressible_decay_rate(self.poisson) / self.thickness

    @property
    def uniform_compliance(self) -> float:
        """H(k = 0) = (1 - 2nu) h / (2(1 - nu)) [length, per G]: the sinking under a uniform
        pressure (0 for the incompressible film)."""
        nu = self.poisson
        return (1.0 - 2.0 * nu) * self.thickness / (2.0 * (1.0 - nu))

    def domain_margin(self, tol: float) -> float:
        """Length [same unit as h] beyond the contact over which the kernels decay to
        ~tol/100 (times an amplitude of order 1): the guard a periodic grid needs."""
        return math.log(100.0 / tol) / self.decay_rate

    def line_margin(self, tol: float, mu: float = 0.0, size: float | None = None) -> float:
        """The margin of a line's period (Amontons ``mu`` in the contact, a contact of
        half-width ``size``): ``domain_margin`` for a film whose kernels decay at
        ``decay_rate`` (a viscoelastic film: its far field against the contact's stiffness,
        ``ViscoelasticFilm.line_margin``)."""
        return self.domain_margin(tol)

    # --- what the solvers' resolution control asks of a film kind: an elastic film's answers.
    # A kind whose symbols depend on the sliding (k_x V: ``physics.viscoelastic``) overrides
    # them; the solvers name no film kind (issue 20: a new kind touches its module, the options
    # and ``Scene.core_film``).
    @property
    def moving(self) -> bool:
        """Whether the symbols depend on the sliding (k_x V): the solvers then measure the
        periodic images and the pressure's centroid, and size the grid by ``edge_scales``."""
        return False

    @property
    def tail_length(self) -> float:
        """Length [h] of the relaxation tail behind the contact (0: none)."""
        return 0.0

    def edge_scales(self) -> list[tuple[float, float]]:
        """(width [h], weight) of each edge structure the grid must resolve ([]: none)."""
        return []

    def trailing_edge_layer(self):
        """(side, [(c_j, l_j)]) of the inner layer behind the contact's trailing edges, whose
        gap the edge fits follow (``numerics.edges.viscous_gap``: side -1 the left edges, +1
        the right ones; lengths l_j > 0 [h]), or None: the elastic edge (gap ~ s^{3/2})."""
        return None

    def image_factor(self) -> float | None:
        """Bound of the line kernels' far field (|s| beyond ``domain_margin``) relative to this
        elastic film's, whose periodic images the solvers' measured amplitude covers: 1.0; None
        when no bound is known (the line solver then measures the images)."""
        return 1.0

    def tail_poles(self, mu: float = 0.0) -> list[tuple[float, float]]:
        """(l, B) of each long one-sided exponential tail of the line compliance kernel,
        K(s) = B exp(s/l)/|l| for s/l < 0 (s = x - x'), whose periodic images a line grid
        sums exactly as a rank-one term (``numerics.operators.tail_terms``) instead of a
        period of several l (Amontons friction ``mu``).  [] for an elastic film (its kernels
        decay at ``decay_rate``)."""
        return []

    def _F0_F1(self, kmag):
        """F0, F1 at K = |k| h (the incompressible ones at nu = 1/2, bit for bit; a kind whose
        ``transfer`` is this class's and incompressible: without A, B, C, the same F0, F1)."""
        K = kmag * self.thickness
        if self.incompressible and type(self).transfer is Film.transfer:
            return compliance_functions(K)
        F0, F1, *_ = self.transfer(K)
        return F0, F1

    def surface_compliance(self, direction, kmag, mu: float = 0.0, slide=(1.0, 0.0)):
        """H(k) = [F0 + i mu (e . n) F1] / (2|k|) (at k = 0: ``uniform_compliance``, 0 at
        nu = 1/2), e = ``slide`` (unit vector,
        the sliding direction: the friction drags the surface along +e for mu > 0)."""
        kmag = np.asarray(kmag, dtype=float)
        F0, F1 = self._F0_F1(kmag)
        e_n = sum(e * n for e, n in zip(slide, direction))
        safe = np.where(kmag > 0, kmag, 1.0)
        H = (F0 + 1j * mu * e_n * F1) / (2.0 * safe)
        return np.where(kmag > 0, H, self.uniform_compliance)  # 0.0 at nu = 1/2

    def shear_compliance(self, direction, kmag, slide=(1.0, 0.0)):
        """The sinking per unit surface shear along e = ``slide``: i (e . n) F1 / (2|k|), 0 at
        k = 0, so that w^ = surface_compliance(mu = 0) p^ + shear_compliance q^ for any shear
        field q along e (Amontons: q = mu p gives back ``surface_compliance(mu)``)."""
        kmag = np.asarray(kmag, dtype=float)
        _, F1 = self._F0_F1(kmag)
        e_n = sum(e * n for e, n in zip(slide, direction))
        safe = np.where(kmag > 0, kmag, 1.0)
        return np.where(kmag > 0, 1j * e_n * F1 / (2.0 * safe), 0.0)

    def shear_compliance_symbol(self, slide=(1.0, 0.0)):
        """``shear_compliance`` as a symbol function (direction, kmag) -> H1."""
        def symbol(direction, kmag):
            return self.shear_compliance(direction, kmag, slide)
        return symbol

    def compliance_symbol(self, mu: float = 0.0, slide=(1.0, 0.0)):
        """The surface compliance as a symbol function (direction, kmag) -> H, for
        ``numerics.operators.FourierOperator``."""
        def symbol(direction, kmag):
            return self.surface_compliance(direction, kmag, mu, slide)
        return symbol

    def base_coefficients(self, kmag):
        """(A, iB, iB', C, sech K) at |k| = kmag: what ``base_transfer`` multiplies by."""
        K = np.asarray(kmag, dtype=float) * self.thickness
        _, _, A, B, Bp, C = self.transfer(K)  # the two couplings differ when nu < 1/2
        return A, 1j * B, 1j * Bp, C, _sech(K)

    def base_transfer(self, direction, kmag, szz_hat, tau_hat, coefficients=None):
        """Base-traction spectra from surface-traction spectra.

        szz_hat : spectrum of sigma_zz(x, h) (= -p^);  tau_hat : tuple of spectra of the surface
        shear components (sigma_xz, [sigma_yz]) at z = h, one per surface dimension (0 allowed).
        coefficients : ``base_coefficients(kmag)`` if already computed.
        Returns (sigma_zz^(x, 0), tuple of the base shear spectra)."""
        A, iB, iBp, C, T = coefficients or self.base_coefficients(kmag)
        tau_L = sum(n * t for n, t in zip(direction, tau_hat))
        szz0 = A * szz_hat + iB * tau_L
        tau_L0 = C * tau_L + iBp * szz_hat
        return szz0, tuple(n * tau_L0 + T * (t - n * tau_L) for n, t in zip(direction, tau_hat))

    def surface_displacement_transfer(self, direction, kmag, p_hat, tau_hat):
        """Surface displacement spectra from surface-traction spectra (physics3d.md):

            delta^ = [F0 p^ + i F1 tau_L] / (2|k|)          (sinking, = -u_z)
            u_L^   = [F2 tau_L - i F1 p^] / (2|k|)
            u_T^   = tanh(K) tau_T / |k|

        p_hat : pressure spectrum (p = -sigma_zz(h) >= 0 in compression); tau_hat : tuple of
        the surface shear spectra (sigma_xz, [sigma_yz]).  Returns (tuple of u_x^, [u_y^],
        delta^).  At k = 0: delta^ = 0 (incompressible; ``uniform_compliance`` p^ for
        nu < 1/2) and u^ = h tau^ (uniform shear of the bonded layer).  Units as
        ``surface_compliance`` (in the core: h^2/2R per G h/2R)."""
        kmag = np.asarray(kmag, dtype=float)
        h = self.thickness
        K = kmag * h
        F0, F1, *_ = self.transfer(K)
        F2_ = self.tangential(K)  # the anti-plane part is the same for every nu
        pos = kmag > 0
        inv2k = np.where(pos, 0.5 / np.where(pos, kmag, 1.0), 0.0)
        tau_L = sum(n * t for n, t in zip(direction, tau_hat))
        delta = (F0 * p_hat + 1j * F1 * tau_L) * inv2k
        if self.uniform_compliance:  # a uniform pressure sinks a compressible film
            delta = delta + np.where(pos, 0.0, self.uniform_compliance) * p_hat
        # F2 / (2|k|) -> h and tanh(K)/|k| -> h as k -> 0
        cL = np.where(pos, F2_ * inv2k, h)
        u_L = cL * tau_L - 1j * F1 * inv2k * p_hat
        cT = h * tanh_over(K)
        u = tuple(n * u_L + cT * (t - n * tau_L) for n, t in zip(direction, tau_hat))
        return u, delta

    def surface_displacements(self, fft, grid, pressure, tau_surface):
        """Surface displacements on ``grid`` (real fields) from the pressure p and the surface
        shear components: returns (tuple of u_x, [u_y], delta = -u_z)."""
        p_hat = fft.forward(pressure)
        tau_hat = tuple(fft.forward(t) for t in tau_surface)
        u, delta = grid.alias_average(
            lambda n: self.surface_displacement_transfer(n, grid.kmag, p_hat, tau_hat))
        return tuple(fft.backward(c) for c in u), fft.backward(delta)

    def base_stresses(self, fft, grid, szz_surface, tau_surface):
        """Base tractions on ``grid`` (real fields) from surface tractions (real fields on the
        same grid): sigma_zz(x, h) and the tuple of shear components at z = h (terms odd in k
        averaged over the two aliases of Nyquist planes: ``Grid.alias_average``).  ``fft`` is the
        grid's planned transform (numerics.fft.get_rfft(grid.shape)).
        Returns (sigma_zz(x, 0), tuple of base shear fields)."""
        szz_hat = fft.forward(szz_surface)
        tau_hat = tuple(fft.forward(t) for t in tau_surface)
        # the coefficients depend only on the film and the grid's wavenumbers: kept for the
        # next call on the same grid (a repeated solve's final grid)
        # (with the first grid of that shape and period: its wavevector directions, which do
        # not depend on the origin, are cached on it)
        # (small grids only: on large ones the solve dwarfs them, and they are large)
        key = (self, grid.shape, grid.lengths)
        entry = _BASE_COEFFICIENTS.get(key)
        if entry is None:
            entry = (self.base_coefficients(grid.kmag), grid)
            if len(_BASE_COEFFICIENTS) >= 8:
                _BASE_COEFFICIENTS.clear()
            if grid.size <= 2**16:
                _BASE_COEFFICIENTS[key] = entry
        coefficients, grid = entry
        szz0, tau0 = grid.alias_average(
            lambda n: self.base_transfer(n, grid.kmag, szz_hat, tau_hat, coefficients))
        return fft.backward(szz0), tuple(fft.backward(t) for t in tau0)


# --- 1D forms (plane strain, k >= 0 of the real FFT), kept for their callers ------------------
_FILM = Film()
_E_X = (1.0,)
_BASE_COEFFICIENTS: dict = {}  # (film, shape, lengths) -> (base_coefficients, a grid of them)


def surface_compliance(k: np.ndarray, mu: float) -> np.ndarray:
    """H(k) on k >= 0 in 1D (dimensionless: displacement h^2/2R per stress E h/6R per 1/h)."""
    return _FILM.surface_compliance(_E_X, np.asarray(k, dtype=float), mu, _E_X)


def base_stresses(fft, k, sigma_zz_surface, sigma_xz_surface):
    """Base stresses sigma_zz(x, 0), sigma_xz(x, 0) of a 1D periodic grid with wavenumbers k
    (>= 0) from the surface tractions, through the planned transform ``fft``."""
    k = np.asarray(k, dtype=float)
    szz0, (sxz0,) = _FILM.base_transfer(_E_X, k, fft.forward(sigma_zz_surface),
                                        (fft.forward(sigma_xz_surface),))
    return fft.backward(szz0), fft.backward(sxz0)
