"""Scene objects a user composes (issue 20): a film of the user's own kind (its symbols), any
indenter shape (a height function of x for a line, of x and y for a surface), an interface;
``solve(film=..., indenter=..., interface=..., load=...)`` and the keyword shorthands."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from spectral_contact import Film, FrictionLaw, InputError, Interface, Scene, Shape, solve
from spectral_contact.physics.transfer import transfer_functions

R = 0.13  # the paper's radius [m]


@dataclass(frozen=True)
class FilmOnSoftBed(Film):
    """README's example: a film whose base rests on a thin soft bed that yields like a Winkler
    foundation, ``bed`` = C_b G / h (C_b [m/Pa] the bed's compliance).  To first order in bed
    the surface sinks by what the base's normal stress A p - i B tau compresses the bed."""

    bed: float = 0.0

    def transfer(self, K):
        F0, F1, A, B, Bp, C = super().transfer(K)
        return F0 + 2.0 * K * self.bed * A, F1 - 2.0 * K * self.bed * B, A, B, Bp, C

    @property
    def uniform_compliance(self):
        return super().uniform_compliance + self.bed * self.thickness


@dataclass(frozen=True)
class OwnSymbols(Film):
    """A user's film with the default film's symbols, written out from physics.transfer."""

    def transfer(self, K):
        F0, F1, A, B, C = transfer_functions(K)
        return F0, F1, A, B, B, C


def _rel(a, b):
    return abs(a - b) / abs(b)


def test_a_user_parabola_is_the_cylinder_on_a_line():
    """A height function of one argument is a line indenter: the parabola x^2/2R equals the
    built-in cylinder to the solver's tolerance (their error estimates added)."""
    ref = solve(load=200.0, mu=2.0, tol=1e-4)
    r = solve(indenter=lambda x: x**2 / (2 * R), load=200.0, mu=2.0, tol=1e-4)
    assert r.scene.height is not None and r.tolerance_met
    bound = ref.error_estimate + r.error_estimate
    assert _rel(r.half_width_m, ref.half_width_m) <= bound
    assert abs(r.contact_center_m - ref.contact_center_m) <= bound * ref.half_width_m
    assert _rel(r.indentation_m, ref.indentation_m) <= bound
    assert _rel(r.max_pressure_Pa, ref.max_pressure_Pa) <= bound
    dx = r.x[1] - r.x[0]
    assert -np.sum(r.base_sigma_zz) * dx == pytest.approx(r.scene.P, rel=1e-10)


def test_a_user_parabola_through_the_exponential_interface():
    """The exponential interface law starts its Newton iteration from the indenter's first
    pressure: a user's line shape gives the cylinder's answer, without overflow on the way."""
    import warnings

    kw = dict(load=200.0, interface_law="exponential", interface_pressure=1e5,
              interface_length=1e-6, tol=1e-3)
    ref = solve(**kw)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        r = solve(indenter=lambda x: x**2 / (2 * R), **kw)
    bound = ref.error_estimate + r.error_estimate
    assert _rel(r.half_width_m, ref.half_width_m) <= bound
    assert _rel(r.indentation_m, ref.indentation_m) <= bound


def test_a_user_shape_beyond_the_cylinder_is_solved_on_a_line():
    """A flat-bottomed punch with rounded edges (not a parabola): its contact covers the flat
    and is wider, its peak pressure lower, than that of the cylinder of its edges' radius (the
    punch without its flat) at the same load; equilibrium holds."""
    w = 1e-3  # flat half-width [m]

    def punch(x):
        return np.where(np.abs(x) <= w, 0.0, (np.abs(x) - w) ** 2 / (2 * 0.01))

    r = solve(indenter=punch, extent=3e-3, load=200.0, mu=0.0, tol=1e-3)
    edge = solve(indenter=lambda x: x**2 / (2 * 0.01), extent=3e-3, load=200.0, mu=0.0,
                 tol=1e-3)
    assert r.half_width_m > w and abs(r.contact_center_m) < 1e-3 * w  # symmetric
    assert r.half_width_m > edge.half_width_m and r.max_pressure_Pa < edge.max_pressure_Pa
    dx = r.x[1] - r.x[0]
    assert -np.sum(r.base_sigma_zz) * dx == pytest.approx(r.scene.P, rel=1e-10)


def test_a_user_paraboloid_is_the_sphere_on_a_surface():
    """A height function of two arguments is a surface indenter loaded by a force."""
    ref = solve(indenter="sphere", force=0.5, mu=0.0, tol=1e-2)
    r = solve(indenter=lambda x, y: (x**2 + y**2) / (2 * R), force=0.5, mu=0.0, tol=1e-2)
    bound = ref.error_estimate + r.error_estimate
    assert _rel(r.contact_radius, ref.contact_radius) <= bound
    assert _rel(r.indentation, ref.indentation) <= bound


@pytest.mark.parametrize("indenter, load", [("line", {"load": 100.0}),
                                            ("sphere", {"force": 0.5})])
def test_a_user_film_with_the_default_symbols_is_the_default_film(indenter, load):
    ref = solve(indenter=indenter, mu=1.0, tol=1e-2, **load)
    film = OwnSymbols(thickness=0.002, young=2.2e6, poisson=0.5)
    r = solve(film=film, indenter=indenter, mu=1.0, tol=1e-2, **load)
    assert type(r.scene.film) is OwnSymbols
    np.testing.assert_allclose(r.pressure, ref.pressure, rtol=0, atol=1e-12 * ref.pressure.max())
    np.testing.assert_allclose(r.base_sigma_xz, ref.base_sigma_xz, rtol=0,
                               atol=1e-12 * np.abs(ref.base_sigma_xz).max())


@pytest.mark.parametrize("indenter, load", [("line", {"load": 100.0}),
                                            ("sphere", {"force": 0.5})])
def test_a_user_film_with_other_symbols_works_for_lines_and_surfaces(indenter, load):
    """A film on a soft bed: bed = 0 is the default film bit for bit; a soft bed sinks the
    indenter deeper and widens the contact; the base still carries the load and the friction."""
    ref = solve(indenter=indenter, mu=1.0, tol=1e-2, **load)
    same = solve(film=FilmOnSoftBed(thickness=0.002, young=2.2e6, bed=0.0), indenter=indenter,
                 mu=1.0, tol=1e-2, **load)
    np.testing.assert_array_equal(same.pressure, ref.pressure)
    soft = solve(film=FilmOnSoftBed(thickness=0.002, young=2.2e6, bed=0.5), indenter=indenter,
                 mu=1.0, tol=1e-2, **load)
    assert soft.indentation_m > 1.05 * ref.indentation_m
    assert soft.max_pressure_Pa < ref.max_pressure_Pa
    cell = np.prod([ax[1] - ax[0] for ax in ((soft.x,) if indenter == "line" else (soft.x, soft.y))])
    assert -np.sum(soft.base_sigma_zz) * cell == pytest.approx(soft.scene.P, rel=1e-8)
    assert np.sum(soft.base_sigma_xz) * cell == pytest.approx(soft.scene.P, rel=1e-8)


def test_user_shapes_and_films_need_the_fft_method():
    bed = FilmOnSoftBed(thickness=0.002, young=2.2e6, bed=0.5)
    for kw in ({"film": bed}, {"indenter": lambda x: x**2 / (2 * R)}):
        with pytest.raises(InputError, match="method fft"):
            solve(method="abel", **kw)
        with pytest.raises(InputError, match="method fft"):
            solve(model="hertz", **kw)
    r = solve(film=bed, model="auto", tol=1e-3)
    assert r.info["auto"] == "exact" and "user-defined film" in r.info["auto_reason"]


def test_the_interface_object_is_the_keyword_shorthand():
    a = solve(interface=Interface(mu=0.5, compliance=1e-9), load=200.0, tol=1e-3)
    b = solve(load=200.0, mu=0.5, interface_compliance=1e-9, tol=1e-3)
    np.testing.assert_array_equal(a.pressure, b.pressure)
    law = FrictionLaw("power", exponent=0.1, pref=2e4)
    a = solve(interface=Interface(mu=2.0, friction=law), tol=1e-3)
    b = solve(mu=2.0, friction_law="power", friction_exponent=0.1, friction_pref=2e4, tol=1e-3)
    np.testing.assert_array_equal(a.pressure, b.pressure)
    assert a.scene == b.scene


def test_the_shape_object_is_the_keyword_shorthand():
    a = solve(indenter=Shape.sphere(radius=0.05), force=0.2, tol=1e-2)
    b = solve(indenter="sphere", radius=0.05, force=0.2, tol=1e-2)
    np.testing.assert_array_equal(a.pressure, b.pressure)
    a = solve(indenter=Shape.line(radius=0.1), tol=1e-3)
    b = solve(radius=0.1, tol=1e-3)
    np.testing.assert_array_equal(a.pressure, b.pressure)
    s = solve(indenter=Shape.cylinder(radius=0.1292, length=0.008), force=1.0, tol=2e-2).scene
    assert (s.indenter, s.radius, s.length) == ("cylinder", 0.1292, 0.008)
    with pytest.raises(InputError, match="radius"):
        solve(indenter=Shape.sphere(radius=0.05), radius=0.1)


def test_the_film_object_is_the_keyword_shorthand():
    a = solve(film=Film(thickness=0.003, young=1e6, poisson=0.5), load=100.0, tol=1e-3)
    b = solve(thickness=0.003, young=1e6, load=100.0, tol=1e-3)
    assert a.scene.with_(film=None) == b.scene
    np.testing.assert_array_equal(a.pressure, b.pressure)


@pytest.mark.parametrize("kwargs, words", [
    ({"film": Film(thickness=0.002, young=2.2e6), "thickness": 0.003}, "thickness"),
    ({"film": Film(thickness=0.002)}, "young"),
    ({"film": "pdms"}, "film"),
    ({"interface": Interface(mu=1.0), "mu": 2.0}, "mu"),
    ({"indenter": lambda: 0.0}, "height function"),
    ({"indenter": lambda x, y, z: 0.0}, "height function"),
    ({"indenter": lambda x: np.full_like(x, np.nan)}, "NaN"),
    ({"indenter": lambda x: ["a"] * len(x)}, "numbers"),
    ({"indenter": lambda x: x**2, "force": 1.0}, "force"),
    ({"indenter": lambda x, y: x**2 + y**2, "load": 1.0}, "load"),
    ({"extent": 1e-3}, "extent"),
])
def test_composition_errors_are_one_line_input_errors(kwargs, words):
    with pytest.raises(InputError, match=words) as exc:
        solve(tol=1e-2, **kwargs)
    assert "\n" not in str(exc.value)


def test_scene_with_film_takes_the_films_numbers():
    film = Film(thickness=0.003, young=1e6, poisson=0.4)
    s = Scene(film=film)
    assert (s.thickness, s.young, s.poisson) == (0.003, 1e6, 0.4)
    assert s.core_film() == Film(poisson=0.4)  # the core's film: thickness 1, stresses in G
    with pytest.raises(InputError, match="thickness"):
        Scene(film=film, thickness=0.005)
