"""One result type that knows its dimension (issue 20): ``Result`` carries what lines and
surfaces share; the SI views come from one table (``result.SI_VIEWS``), with the same attribute
names where they apply; ``summary()`` is the JSON record (a dict) for both; the old names work."""
from __future__ import annotations

import numpy as np
import pytest

from spectral_contact import solve
from spectral_contact.result import SI_VIEWS, ContactResult, ContactResult3D, Result

SHARED = ("mu", "poisson", "young_Pa", "radius_m", "thickness_m", "friction_law",
          "interface_compliance_m_per_Pa", "x_m", "pressure_Pa", "surface_shear_Pa",
          "base_sigma_zz_Pa", "base_sigma_xz_Pa", "indentation_m", "max_pressure_Pa",
          "max_pressure_x_m", "domain_length_m", "indentation", "max_pressure", "max_pressure_x",
          "surface_shear", "friction_ratio", "deformation_friction", "Q_over_P", "tolerance_met",
          "speed_m_per_s", "prony_terms", "auto_reason", "grid_points", "error_estimate",
          "iterations", "residual", "wall_time_s", "plan_time_s", "counters", "info")


@pytest.fixture(scope="module")
def results():
    line = solve(load=100.0, mu=0.5, tol=1e-3)
    surf = solve(indenter="paraboloid", radius_x=0.1, radius_y=0.05, force=0.2, mu=0.5,
                 tol=1e-2)
    return line, surf


def test_one_type_that_knows_its_dimension(results):
    line, surf = results
    assert isinstance(line, Result) and isinstance(surf, Result)
    assert isinstance(line, ContactResult) and isinstance(surf, ContactResult3D)
    assert (line.dimension, line.ndim) == ("line", 1) and (surf.dimension, surf.ndim) == ("surface", 2)
    for name in SHARED:  # the same names where they apply
        assert hasattr(line, name) and hasattr(surf, name), name
    assert line.pressure_Pa.ndim == 1 and surf.pressure_Pa.ndim == 2


def test_every_json_key_is_an_attribute_of_the_same_name(results):
    for r in results:
        rec = r.summary()
        assert isinstance(rec, dict) and rec == r.to_dict()
        for key, value in rec.items():
            if key in ("friction_exponent", "friction_pref_Pa", "shear_strength_Pa",
                       "shear_slope"):  # the law's parameters: the scene's
                continue
            got = getattr(r, key)
            got = [int(n) for n in got] if key == "grid_points" and r.ndim == 2 else got
            assert got == value, key


def test_the_si_views_come_from_one_table(results):
    """Each row of SI_VIEWS on each result that has it: the dimensionless source times the
    scene's units (or the scene's field); a row's name is a view of both where both have it."""
    for r in results:
        for name, source, units, _doc, dims, form in SI_VIEWS:
            if r.dimension not in dims:
                assert name in {n for n, *_, d, _f in SI_VIEWS if r.dimension in d} or \
                    not hasattr(r, name), name
                continue
            if units is None:
                assert getattr(r, name) == getattr(r.scene, source), name
                continue
            def si(v):  # times each unit in turn
                for u in units:
                    v = v * getattr(r.scene, u)
                return v

            v = getattr(r, source)
            if form == "pair":
                assert getattr(r, name) == [float(si(d)) for d in v], name
            else:
                assert np.array_equal(getattr(r, name), si(v)), name


def test_the_old_names_still_work(results):
    line, surf = results
    assert line.half_width_m > 0 and line.x0_m == -line.contact_center_m
    assert surf.contact_radius_m > 0 and surf.contact_area_m2 == pytest.approx(
        np.pi * surf.contact_radius_m**2, rel=1e-12)
    assert set(surf.maps()) >= {"x_m", "pressure_Pa", "surface_uz_m"}
    assert surf.maps()["pressure_Pa"].shape == surf.pressure.shape
    assert surf.radius_x_m == 0.1 and surf.radius_y_m == 0.05 and surf.indenter == "paraboloid"
    assert list(line.profiles()) == list(surf.profiles())  # the same profile columns
    with pytest.raises(AttributeError):
        surf.half_width_m  # noqa: B018 (a line's measure, not a surface's)
    with pytest.raises(AttributeError):
        line.contact_radius_m  # noqa: B018
