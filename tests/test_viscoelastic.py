"""Viscoelastic (Prony series) film in steady sliding (issue 23): limits, signs, mirror,
equilibrium, --speed 0 bit for bit, CLI refusals, Q_over_P on every film.
(The half-space reference, Hunter's closed form: tests/test_hunter.py.)"""
import json
import math

import numpy as np
import pytest

from spectral_contact import solve
from spectral_contact.cli.main import main
from spectral_contact.errors import InputError
from spectral_contact.numerics.fft import get_rfft
from spectral_contact.physics.film import Film
from spectral_contact.physics.scene import Scene
from spectral_contact.physics.viscoelastic import ViscoelasticFilm, film_of, parse_prony

E_INF = 2.2e6
SLS = ((E_INF, 0.01),)  # E_1 = E_inf (E_0 = 2 E_inf), tau = 10 ms: tau_r = 20 ms
TOL = 1e-3


def _rel(r, q):
    """Relative differences of a, x_c (over a), d, p_max between two results."""
    a = q.half_width
    return np.array([(r.half_width - a) / a, (r.center - q.center) / a,
                     (r.indentation - q.indentation) / q.indentation,
                     (r.max_pressure_Pa - q.max_pressure_Pa) / q.max_pressure_Pa])


def test_material_functions():
    f = ViscoelasticFilm(relaxed_young=3.0, prony=((3.0, 0.5),), speed=1.0)
    assert abs(f.complex_modulus(0.0) - 1.0) < 1e-15  # G_inf = E_inf / 3
    assert abs(f.complex_modulus(1e12) - 2.0) < 1e-9   # G_0
    # SLS: max tan delta = (G0 - Ginf) / (2 sqrt(G0 Ginf)) at w tau = sqrt(Ginf/G0)
    t, w = f.peak_loss_tangent()
    assert t == pytest.approx(1.0 / (2.0 * math.sqrt(2.0)), rel=1e-9)
    assert w * 0.5 == pytest.approx(math.sqrt(0.5), rel=1e-6)
    assert f.retardation_times() == pytest.approx([1.0], rel=1e-12)  # tau E_0/E_inf
    two = ViscoelasticFilm(relaxed_young=1.0, prony=((1.0, 0.1), (2.0, 10.0)), speed=1.0)
    rt = two.retardation_times()
    assert len(rt) == 2 and 0.1 < rt[0] < 10.0 < rt[1] <= 10.0 * 4.0
    for t_ in rt:  # zeros of G*(s / i)
        s = -1.0 / t_
        assert abs(1.0 + sum(e * s * ta / (1 + s * ta) for e, ta in two.prony)) < 1e-9


def test_speed_zero_is_the_elastic_solve_bit_for_bit():
    el = solve(load=200.0, mu=1.0, tol=TOL)
    for scene in (Scene(load=200.0, mu=1.0, speed=0.0, prony=SLS), Scene(load=200.0, mu=1.0, speed=0.0)):
        r = solve(scene, tol=TOL)
        for k in ("x", "pressure", "base_sigma_zz", "base_sigma_xz"):
            assert np.array_equal(getattr(r, k), getattr(el, k)), k
        assert (r.half_width, r.center, r.indentation, r.error_estimate) == \
            (el.half_width, el.center, el.indentation, el.error_estimate)


def test_limits_relaxed_and_glassy():
    slow = solve(load=200.0, mu=1.0, speed=1e-7, prony=SLS, tol=TOL)
    relaxed = solve(load=200.0, mu=1.0, young=E_INF, tol=TOL)
    assert np.max(np.abs(_rel(slow, relaxed))) < slow.error_estimate + relaxed.error_estimate
    fast = solve(load=200.0, mu=1.0, speed=1e5, prony=SLS, tol=TOL)
    glassy = solve(load=200.0, mu=1.0, young=2 * E_INF, tol=TOL)
    assert np.max(np.abs(_rel(fast, glassy))) < fast.error_estimate + glassy.error_estimate
    # and in between it is neither: stiffer than relaxed, softer than glassy
    mid = solve(load=200.0, mu=1.0, speed=0.1, prony=SLS, tol=TOL)
    assert glassy.half_width < mid.half_width < relaxed.half_width


def _sinking(r):
    """The surface's sinking w on the result's grid, from its pressure and shear."""
    film = film_of(r.scene)
    from spectral_contact.numerics.grid import Grid

    g = Grid.centered(r.grid_points, r.domain_length, 0.5 * (r.x[0] + r.x[-1]) + 0.5 * r.domain_length / r.grid_points)
    assert np.allclose(g.x, r.x)
    _, delta = film.surface_displacements(get_rfft(g.shape), g, r.pressure, (r.surface_shear,))
    return delta


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_signs_and_mirror(sign):
    r = solve(load=200.0, mu=0.5 * sign, speed=0.05 * sign, prony=SLS, tol=TOL)
    el = solve(load=200.0, mu=0.5 * sign, young=E_INF, tol=TOL)
    # the pressure moves toward the leading edge (beyond the friction's own shift)
    assert sign * (r.center - el.center) > 0.05 * r.half_width
    assert sign * (r.max_pressure_x - el.max_pressure_x) > 0.05 * r.half_width
    # the deformation friction opposes the motion (signed like mu) and adds to Q/P
    assert sign * r.deformation_friction > 0
    assert r.Q_over_P == pytest.approx(r.mu + r.deformation_friction, rel=1e-12)
    # the trailing side recovers late: half a width behind the contact the surface is sunk
    # deeper (bulges less) than as far ahead of it, by more than on the elastic film
    def asymmetry(res):
        w = _sinking(res)
        lo, hi = res.center - res.half_width, res.center + res.half_width
        s_ = 0.5 * res.half_width
        behind, ahead = (lo - s_, hi + s_) if sign > 0 else (hi + s_, lo - s_)
        return np.interp(behind, res.x, w) - np.interp(ahead, res.x, w)
    r0 = solve(load=200.0, mu=0.0, speed=0.05 * sign, prony=SLS, tol=TOL)
    el0 = solve(load=200.0, mu=0.0, young=E_INF, tol=TOL)
    assert abs(asymmetry(el0)) < 1e-3 * el0.indentation  # frictionless elastic: symmetric
    assert asymmetry(r0) > 0.05 * r0.indentation
    assert asymmetry(r) > asymmetry(el) + 0.05 * r.indentation
    # equilibrium of the base stresses: Int sigma_zz(x, 0) = -P, Int sigma_xz(x, 0) = mu P
    dx = r.x[1] - r.x[0]
    P = r.pressure.sum() * dx
    assert r.base_sigma_zz.sum() * dx == pytest.approx(-P, rel=1e-9)
    assert r.base_sigma_xz.sum() * dx == pytest.approx(r.mu * P, rel=1e-9)
    if sign < 0:  # mirror of the + case
        m = solve(load=200.0, mu=0.5, speed=0.05, prony=SLS, tol=TOL)
        tol = r.error_estimate + m.error_estimate
        assert abs(r.half_width - m.half_width) / m.half_width < tol
        assert abs(r.center + m.center) / m.half_width < tol
        assert abs(r.indentation - m.indentation) / m.indentation < tol
        assert abs(r.deformation_friction + m.deformation_friction) / m.deformation_friction < 1e-2
        assert r.to_dict()["Q_over_P"] == pytest.approx(-m.to_dict()["Q_over_P"], rel=1e-3)


def test_slow_sliding_centroid():
    """Measured law of slow sliding (studies/README, viscoelastic): the pressure's centroid sits
    (E_1/E_inf) V tau ahead of the apex (mu_def = (h/R) that), whatever the contact."""
    for load, w in ((200.0, 1.0), (20.0, 0.25)):
        V = 1e-6  # (measured: ratio 0.997, 0.9997, 0.99997 on 2^12, 2^14, 2^16 points)
        r = solve(load=load, mu=0.0, speed=V, prony=((w * E_INF, 0.01),), tol=TOL,
                  grid_points=2**14)
        assert r.deformation_friction == pytest.approx(w * V * 0.01 / 0.130, rel=2e-3)


def test_json_record():
    r = solve(load=200.0, mu=1.0, speed=0.02, prony=SLS, tol=TOL)
    d = r.to_dict()
    assert d["speed_m_per_s"] == 0.02 and d["prony_terms"] == [[E_INF, 0.01]]
    assert d["deformation_friction"] == r.deformation_friction > 0
    assert d["Q_over_P"] == pytest.approx(1.0 + d["deformation_friction"], rel=1e-12)
    # mu_def = (h/R) x the pressure's centroid, from the profile
    c = np.sum(r.pressure * r.x) / np.sum(r.pressure)
    assert d["deformation_friction"] == pytest.approx(c * 0.002 / 0.130, rel=1e-3)
    assert "speed_m_per_s" not in solve(load=200.0, mu=1.0, tol=TOL).to_dict()


def test_bad_prony_in_python():
    for bad in ("1,2,3", "1,-2", "a,b", "", "1,0"):
        with pytest.raises(InputError, match="--prony"):
            parse_prony(bad)
    with pytest.raises(InputError, match="--poisson 0.5"):
        Scene(poisson=0.4, speed=1.0, prony=SLS)
    with pytest.raises(InputError, match="same sign"):
        Scene(mu=1.0, speed=-1.0, prony=SLS)
    with pytest.raises(InputError, match="--model exact or goodman"):
        solve(load=200.0, speed=1.0, prony=SLS, model="hertz")


def test_model_auto_states_the_viscous_effect():
    slow = solve(load=200.0, mu=1.0, speed=1e-7, prony=SLS, tol=TOL, model="auto")
    fast = solve(load=200.0, mu=1.0, speed=0.05, prony=SLS, tol=TOL, model="auto")
    assert "elastic film is enough" in slow.auto_reason
    assert "elastic film is not enough" in fast.auto_reason
    assert slow.info["auto_viscous_bound"] <= TOL < fast.info["auto_viscous_changes"]["a"]
    # the auto result is the exact viscoelastic solve (at tol/4)
    assert np.array_equal(fast.pressure, solve(load=200.0, mu=1.0, speed=0.05, prony=SLS,
                                               tol=TOL / 4).pressure)


def _cli(capsys, *args):
    code = main(["solve", *args])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli(capsys):
    for args in (["--speed", "1", "--prony", "1,2,3"], ["--speed", "1", "--prony", "1e6,-0.1"],
                 ["--speed", "1", "--prony", "1e6,x"], ["--prony", "1e6,0.1"],
                 ["--speed", "1", "--prony", "1e6,0.1", "--poisson", "0.4"]):
        code, out, err = _cli(capsys, *args, "--tol", "1e-2")
        assert code == 2, args
        assert out == "" and len(err.strip().splitlines()) == 1, err
        assert "--prony" in err or "--speed" in err
    code, out, err = _cli(capsys, "--speed", "0.05", "--prony", "2.2e6,0.01", "--mu", "0.5",
                          "--tol", "1e-3", "--json")
    assert code == 0, err
    rec = json.loads(out)
    assert rec["deformation_friction"] > 0 and rec["speed_m_per_s"] == 0.05
    # --speed 0 (no Prony terms): the elastic record, number for number
    a = json.loads(_cli(capsys, "--speed", "0", "--tol", "1e-3", "--json")[1])
    b = json.loads(_cli(capsys, "--tol", "1e-3", "--json")[1])
    for k in ("wall_time_s", "plan_time_s"):
        a.pop(k), b.pop(k)
    assert a == b


# --- surfaces (3D: the sphere, the symbol at omega = -k_x V) ---------------------------------
def _sphere(**kw):
    return solve(indenter="sphere", force=1.0, tol=1e-2, **kw)


def test_sphere_speed_zero_bit_for_bit_and_limits():
    el = _sphere(mu=0.5)
    r = _sphere(mu=0.5, speed=0.0, prony=SLS)
    for k in ("pressure", "base_sigma_zz", "base_sigma_xz", "base_sigma_yz"):
        assert np.array_equal(getattr(r, k), getattr(el, k)), k
    slow = _sphere(mu=0.5, speed=1e-7, prony=SLS)
    fast = _sphere(mu=0.5, speed=1e5, prony=SLS)
    glassy = _sphere(mu=0.5, young=2 * E_INF)
    for v, e in ((slow, el), (fast, glassy)):
        tol = v.error_estimate + e.error_estimate
        assert abs(v.contact_radius - e.contact_radius) / e.contact_radius < tol
        assert abs(v.indentation - e.indentation) / e.indentation < tol


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_sphere_signs_mirror_equilibrium(sign):
    r = _sphere(mu=0.0, speed=0.1 * sign, prony=SLS)
    d = r.summary()
    q = r.measures
    # the pressure and the contact move toward the leading edge; mu_def opposes the motion
    assert sign * q["xc"] > 0.05 * r.contact_radius
    assert sign * (q["x_max"] + q["x_min"]) > 0
    assert sign * d["deformation_friction"] > 1e-3
    assert d["Q_over_P"] == pytest.approx(d["deformation_friction"], rel=1e-12)
    # mu_def = (h/R) x the centroid for the sphere (f = r^2 / 2R)
    assert d["deformation_friction"] == pytest.approx(q["xc"] * 0.002 / 0.130, rel=1e-9)
    # the base carries the load
    cell = np.prod(np.asarray(r.domain_length) / np.asarray(r.grid_points))
    P = r.pressure.sum() * cell
    assert r.base_sigma_zz.sum() * cell == pytest.approx(-P, rel=1e-9)
    assert abs(r.base_sigma_xz.sum() * cell) < 1e-9 * P
    if sign < 0:
        m = _sphere(mu=0.0, speed=0.1, prony=SLS)
        tol = r.error_estimate + m.error_estimate
        assert abs(r.contact_radius - m.contact_radius) / m.contact_radius < tol
        assert abs(q["xc"] + m.measures["xc"]) / m.contact_radius < tol
        assert d["deformation_friction"] == pytest.approx(-m.summary()["deformation_friction"],
                                                          rel=5e-2)


def test_q_over_p_one_definition_for_every_film():
    """Q_over_P = mu + mu_def on elastic and viscoelastic films, lines and surfaces; mu_def
    = Int p df/dx / P recomputed from the SI profiles (f = x^2/2R: df/dx = x/R), signed like
    mu (the mirror flips it), zero without friction on the elastic film."""
    for mu in (2.0, -2.0, 0.0):
        r = solve(load=200.0, mu=mu, tol=TOL)
        d = r.to_dict()
        p, x = r.pressure_Pa, r.x_m
        mu_def = float(np.sum(p * x) / np.sum(p)) / d["radius_m"]
        assert d["deformation_friction"] == pytest.approx(mu_def, rel=1e-3, abs=1e-9)
        assert d["Q_over_P"] == d["mu"] + d["deformation_friction"]
        if mu == 0.0:
            assert abs(d["deformation_friction"]) < 1e-9
        else:  # the paper's scene: (h/R) x_p = 0.0118 (studies/README, viscoelastic)
            assert math.copysign(1.0, mu) * d["deformation_friction"] == pytest.approx(0.0118, rel=0.02)
    s = solve(indenter="sphere", force=1.0, mu=0.5, tol=1e-2).summary()
    assert s["Q_over_P"] == pytest.approx(0.5 + s["deformation_friction"], rel=1e-12)
    assert s["deformation_friction"] == pytest.approx(
        s["pressure_centroid_x_m"] / s["radius_m"], rel=0.05)
    assert s["deformation_friction"] > 0


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_slow_sliding_first_order_theory(sign):
    """Slow sliding (solvers.visco_slow): the relaxed elastic solve + the first-order
    correction (trailing edge in by |delta|, pressure translated by delta) against the full
    viscoelastic solve on a grid resolving V tau (8 cells), a_H/h = 1, V = 1 mm/s (V tau/h
    = 5e-3, remainder 1e-4): a, x_c, d, p_max, x_p within the two error estimates."""
    from studies.viscoelastic import FILM, load_for

    kw = dict(load=load_for(1.0), mu=0.0, prony=SLS, tol=TOL, **FILM)
    slow = solve(speed=sign * 1e-3, **kw)
    assert slow.info["slow_sliding"]["shift_h"] == pytest.approx(sign * 5e-3)
    full = solve(speed=sign * 1e-3, grid_points=2**15,
                 domain_length=slow.domain_length * FILM["thickness"], **kw)
    assert "slow_sliding" not in full.info
    a = full.half_width
    bound = slow.error_estimate + full.error_estimate
    assert abs(slow.half_width - a) / a < bound
    assert abs(slow.center - full.center) / a < bound
    assert abs(slow.indentation - full.indentation) / full.indentation < bound
    assert abs(slow.max_pressure - full.max_pressure) / full.max_pressure < bound
    assert abs(slow.info["pressure_centroid"] - full.info["pressure_centroid"]) / a < bound
    assert sign * slow.center > 0.4 * 5e-3  # a real shift (delta/2), signed like V
    # equilibrium of the translated base stresses
    dx = slow.x[1] - slow.x[0]
    assert slow.base_sigma_zz.sum() * dx == pytest.approx(-slow.pressure.sum() * dx, rel=1e-9)
    # beyond the theory's range (remainder > tol/4) the full solve runs
    assert "slow_sliding" not in solve(speed=0.05, **kw).info


def test_sphere_period_too_short_for_the_tail_is_refused():
    """3D: a user period that holds the contact and the elastic decay but not a relaxation
    tail shorter than 2.7 h (V tau_r = 1 h here, held by the period: its excess over the
    elastic margin from the kernel's far field, ``_SurfaceSolve.margin_x``, ~1.1 h) is refused
    in one message naming the tail; a longer tail (10 h) has its images summed (tail_terms):
    the same period is accepted."""
    kw = dict(indenter="sphere", force=1.0, mu=0.0, prony=SLS, tol=1e-2)
    with pytest.raises(InputError, match="relaxation tail"):
        solve(**kw, speed=0.1, domain_length=(0.021, 0.04))  # 10.5 h (need 10.9 h)
    # the same period is fine for the elastic film (need 9.8 h), and for the summed tail
    solve(indenter="sphere", force=1.0, mu=0.0, tol=1e-2, domain_length=(0.021, 0.04))
    solve(**kw, speed=1.0, domain_length=(0.021, 0.04))


def test_sphere_period_from_the_far_field():
    """3D, SLS at 0.1 m/s (V tau_r = 1 h, held by the period), tol 1e-2: the period along x is
    the kernel's far-field margin (``_SurfaceSolve.margin_x``, as lines'), 1.4 h beyond the
    elastic one's, not the elastic margin plus the tail's l ln(100 A/tol) (~6 h more: the
    decays do not add); on it the periodic images move the radius, centroid, d and p_max by
    less than tol/1000 (the fixed grid on the period and on twice it along x, same cells)."""
    from spectral_contact.physics.film import Film

    kw = dict(indenter="sphere", force=1.0, mu=0.0, prony=SLS, speed=0.1, tol=1e-2)
    r = solve(**kw)
    (nx, ny), (Lx, Ly) = r.grid_points, r.domain_length
    film = r.scene.core_film()
    elastic, additive = Film.domain_margin(film, 1e-2), film.domain_margin(1e-2, True)
    assert elastic < r.info["domain_margin"] < elastic + 0.5 * (additive - elastic)
    h = 0.002
    a = solve(**kw, grid_points=(nx, ny), domain_length=(Lx * h, Ly * h)).summary()
    b = solve(**kw, grid_points=(2 * nx, ny), domain_length=(2 * Lx * h, Ly * h)).summary()
    rad = b["contact_radius_m"]
    change = max(abs(a["contact_radius_m"] - rad) / rad,
                 abs(a["pressure_centroid_x_m"] - b["pressure_centroid_x_m"]) / rad,
                 abs(a["indentation_m"] / b["indentation_m"] - 1.0),
                 abs(a["max_pressure_Pa"] / b["max_pressure_Pa"] - 1.0))
    assert change < 1e-5


@pytest.mark.parametrize("mu", [0.0, 0.5])
def test_sphere_tail_images_summed(mu, monkeypatch):
    """3D, V tau_r = 10 h: the fixed grid on a 16 h period and on twice it along x (same
    cells) agree to 1e-5 on the radius, centroid, d and p_max (the tail's images summed,
    along x rank one, along y a convolution: numerics.operators.tail_terms); the periodic row
    without the sum differs by more than 1e-3."""
    import spectral_contact.numerics.contact as contact

    kw = dict(indenter="sphere", force=1.0, mu=mu, prony=SLS, speed=1.0, tol=1e-2)

    def change():
        contact.compliance_operator.cache_clear()
        a, b = (solve(**kw, grid_points=(64 * f, 64), domain_length=(0.032 * f, 0.032)).summary()
                for f in (1, 2))
        rad = b["contact_radius_m"]
        return max(abs(a[k] - b[k]) / (abs(b[k]) if k in ("indentation_m", "max_pressure_Pa")
                                        else rad)
                   for k in ("contact_radius_m", "pressure_centroid_x_m", "indentation_m",
                             "max_pressure_Pa"))

    assert change() < 1e-5
    monkeypatch.setattr(contact, "tail_terms", lambda *args: ())  # the plain periodic row
    assert change() > 1e-3
    monkeypatch.undo()
    contact.compliance_operator.cache_clear()


@pytest.mark.parametrize("speed,mu", [(50.0, 2.0), (50.0, 0.0), (-50.0, -1.0), (2.0, 2.0)])
def test_line_tail_images_summed_exactly(speed, mu):
    """Lines: the relaxation tail's periodic images (l = V tau_r = 100 h, or 4 h) are summed
    by the rank-one term (numerics.operators.tail_terms): the compliance on a 32 h period
    equals, near the load, the one on a period 32 times longer (same nodes) to the elastic
    images' e^-17; the plain periodic convolution does not (mu != 0: ~1e-3 of the sinking).
    The contact solved on the short period then matches the long one (d to 1e-9 of itself,
    p to 1e-6 of its peak) where the plain periodic solve is off by ~1e-4."""
    from spectral_contact.numerics.contact import compliance_operator, solve_complementarity, solve_contact
    from spectral_contact.numerics.grid import Grid
    from spectral_contact.numerics.operators import FourierOperator
    from spectral_contact.physics.indenters import Cylinder

    film = ViscoelasticFilm(thickness=1.0, relaxed_young=1.0, prony=((1.0, 1.0),), speed=speed)
    assert len(film.tail_poles(mu)) == 1 and film.tail_poles(mu)[0][0] == pytest.approx(2 * speed)
    n, L, rep = 1024, 32.0, 32
    short, long_ = Grid.centered(n, L), Grid.centered(n * rep, L * rep)
    window = slice((n * rep - n) // 2, (n * rep + n) // 2)
    near = np.abs(short.x) < 3.0
    x = long_.x
    p = np.sqrt(np.maximum(1.0 - (x - 0.3) ** 2, 0.0)) * (1.0 + 0.3 * x)
    u_long = compliance_operator(long_.shape, long_.lengths, mu, film).apply(p)[window]
    op = compliance_operator(short.shape, short.lengths, mu, film)
    u = op.apply(p[window])
    plain = FourierOperator(op.grid, op.symbol_function).apply(p[window])
    scale = np.abs(u_long).max()
    assert np.abs(u - u_long)[near].max() < 1e-7 * scale
    if mu != 0.0:
        assert np.abs(plain - u_long)[near].max() > 1e-4 * scale
    # the contact
    P = 2.0 * np.pi * 0.25
    s = solve_contact(short, mu, [Cylinder(0.0, P)], film=film)
    p0 = np.zeros(n * rep)
    p0[window] = s.pressure
    b = solve_contact(long_, mu, [Cylinder(0.0, P)], film=film, p_init=p0)
    assert not b.pressure[: window.start].any() and not b.pressure[window.stop:].any()
    assert abs(s.indentations[0] - b.indentations[0]) < 1e-9 * b.indentations[0]
    assert np.abs(s.pressure - b.pressure[window]).max() < 1e-6 * b.pressure.max()
    if mu != 0.0:
        pl = solve_complementarity(FourierOperator(op.grid, op.symbol_function),
                                   Cylinder(0.0, P).height(short), np.zeros(n, dtype=np.intp),
                                   [P], p_init=s.pressure)
        assert abs(pl.indentations[0] - b.indentations[0]) > 1e-5 * b.indentations[0]


def test_line_period_without_the_long_tail():
    """The automatic line period no longer holds the tail (V tau_r = 100 h at 10 m/s): it is
    the elastic film's (within the guard), and the result matches a user period 8 times
    longer on the same cells within the error estimates."""
    from studies.viscoelastic import FILM, load_for

    kw = dict(load=load_for(1.0), mu=1.0, prony=SLS, speed=10.0, tol=TOL, **FILM)
    r = solve(**kw)
    el = solve(**{k: v for k, v in kw.items() if k not in ("prony", "speed")})
    assert r.info["tail_length"] == pytest.approx(100.0)
    assert r.domain_length < 1.1 * el.domain_length
    big = solve(grid_points=8 * r.grid_points, domain_length=8 * r.domain_length * FILM["thickness"],
                **kw)
    bound = r.error_estimate + big.error_estimate
    assert np.abs(_rel(r, big)).max() < bound


def test_viscous_gap_is_the_relaxing_films_elastic_edge():
    """The gap behind a viscoelastic trailing edge (numerics.edges.viscous_gap): the elastic
    gap gradient sqrt(s) through the film's memory (r sqrt(s) + sum c_j int_0^s exp(-(s -
    t)/l_j) sqrt(t) dt / l_j), integrated, by quadrature; glassy r (2/3) s^{3/2} within l_j,
    the relaxed edge moved by delta = sum c_j l_j beyond."""
    from scipy.integrate import quad

    from spectral_contact.numerics.edges import viscous_gap
    terms = [(0.3, 0.01), (0.2, 0.2)]  # r = 0.5
    r = 1.0 - sum(c for c, _ in terms)

    def slope(s):
        return r * math.sqrt(s) + sum(c * quad(lambda t: math.exp(-(s - t) / ell) * math.sqrt(t),
                                               0.0, s, limit=200)[0] / ell for c, ell in terms)

    for s in (1e-3, 0.01, 0.05, 0.3, 2.0):
        assert viscous_gap(np.array([s]), terms)[0] == pytest.approx(
            quad(slope, 0.0, s, limit=200)[0], rel=1e-5)
    s = 1e-6
    assert viscous_gap(np.array([s]), terms)[0] == pytest.approx(r * 2 / 3 * s ** 1.5, rel=1e-3)
    delta = sum(c * ell for c, ell in terms)
    s = 1e3
    assert viscous_gap(np.array([s]), terms)[0] == pytest.approx(2 / 3 * (s - delta) ** 1.5,
                                                                 rel=1e-6)


def test_trailing_edge_layer_fitted():
    """Issue 23's cost at tol 1e-4: the edge structure |V| tau (a_H/h 1, V tau/h = 5e-3) needs
    no cells of its own.  On a fixed grid with one cell across V tau the trailing edge fitted
    with its inner layer puts a and x_c within 1.5e-4 of a resolved solve (2^18 points, 64
    cells across V tau; the elastic fit: 4.5e-4 and 4.2e-4 off); the automatic solve stops on
    a grid at most 4 times the elastic one's (it was 8 times: V tau spanned >= 2 cells on the
    third level), and its estimate bounds its error against the resolved solve."""
    from studies.viscoelastic import FILM, load_for
    V, tol = 1e-3, 1e-4
    kw = dict(load=load_for(1.0), mu=0.0, tol=tol, **FILM)
    el = solve(**kw)
    r = solve(prony=SLS, speed=V, **kw)
    assert "slow_sliding" not in r.info
    L = r.domain_length * FILM["thickness"]
    ref = solve(prony=SLS, speed=V, grid_points=2 ** 18, domain_length=L, **kw)
    a = ref.half_width
    n1 = int(2 ** round(math.log2(r.domain_length / (V * SLS[0][1] / FILM["thickness"]))))
    one = solve(prony=SLS, speed=V, grid_points=n1, domain_length=L, **kw)  # ~1 cell across
    assert abs(one.half_width - a) / a < 1.5e-4 and abs(one.center - ref.center) / a < 1.5e-4
    assert r.grid_points <= 4 * el.grid_points
    err = max(abs(r.half_width - a) / a, abs(r.center - ref.center) / a,
              abs(r.indentation - ref.indentation) / ref.indentation,
              abs(r.max_pressure - ref.max_pressure) / ref.max_pressure,
              abs(r.info["pressure_centroid"] - ref.info["pressure_centroid"]) / a)
    assert err <= r.error_estimate <= tol


# --- reliability (issue 23's fourth session) ---------------------------------------------------
@pytest.mark.parametrize("sign", [1, -1])
def test_sphere_trailing_edge_layer_fitted(sign):
    """The sphere's trailing edges fitted with their inner layer (numerics.measure2d: along x
    rows with the lengths |V| tau_r, along y columns with |V| tau_r |dy/dx|): F = 1 N, V tau/h
    = 0.05 (1 cm/s, either way), a fixed 256^2 grid on a 12 x 10 h period (~1 cell across
    V tau) has its contact radius within 5e-4 of 1024^2 on the same period (measured 1.4e-4;
    the elastic fits: 1.7e-3)."""
    from studies.viscoelastic import FILM
    h = FILM["thickness"]
    kw = dict(indenter="sphere", force=1.0, mu=0.0, prony=SLS, speed=0.01 * sign, tol=1e-2,
              domain_length=(12 * h, 10 * h), **FILM)
    coarse = solve(grid_points=256, **kw)
    ref = solve(grid_points=1024, **kw)
    rad = ref.summary()["contact_radius_m"]
    assert abs(coarse.summary()["contact_radius_m"] - rad) / rad < 5e-4


def test_speed_without_prony_is_refused(capsys):
    """An elastic film's steady sliding does not depend on V: --speed V != 0 without --prony was
    silently the elastic solve; now one line, exit 2 (Python: InputError); --speed 0 alone stays
    the elastic solve (test_cli)."""
    for args in (["--speed", "0.1"], ["--speed", "-0.1", "--mu", "-1"],
                 ["--indenter", "sphere", "--speed", "0.1"]):
        code, out, err = _cli(capsys, *args, "--tol", "1e-2")
        assert code == 2, args
        assert out == "" and len(err.strip().splitlines()) == 1, err
        assert "--speed" in err and "needs --prony" in err
    with pytest.raises(InputError, match="needs --prony"):
        Scene(speed=0.1)
    assert Scene(speed=0.0).core_film() == Scene().core_film()


@pytest.mark.parametrize("prony,what", [("0,0.01", "E_i > 0"), ("-2.2e6,0.01", "E_i > 0"),
                                        ("2.2e6,0", "tau_i > 0"), ("2.2e6,-1", "tau_i > 0"),
                                        ("2.2e19,0.01", "E_i / E_inf"),
                                        ("2.2e-7,0.01", "E_i / E_inf"),
                                        ("2.2e6,0.01,0,1", "E_i > 0")])
def test_prony_moduli_out_of_range_refused(capsys, prony, what):
    """Zero or negative moduli and times, and a ratio E_i/E_inf beyond [1e-12, 1e12] (10^13,
    10^-13 here), in any term: one line naming --prony, exit 2."""
    code, out, err = _cli(capsys, "--speed", "0.05", "--prony", prony, "--tol", "1e-2")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert "--prony" in err and what in err


def test_image_factor():
    """``ViscoelasticFilm.image_factor``: 1 for the elastic film; the short and the summed
    tails' bound max |R(+-i kappa)| / r (SLS r = 1/2); None between them (measured)."""
    kappa = 0.7390851332151607
    assert Film().image_factor() == 1.0

    def film(kl):  # one SLS term, E_1 = E_inf: tau_r = 2 tau, l_r = V tau_r
        return ViscoelasticFilm(thickness=1.0, relaxed_young=1.0, prony=((1.0, 1.0),),
                                speed=kl / (2.0 * kappa))
    for kl in (1e-3, 0.3, 0.499):
        assert film(kl).image_factor() == pytest.approx((0.5 + 0.5 / (1 - kl)) / 0.5, rel=1e-9)
    for kl in (0.51, 1.0, 1.99):
        assert film(kl).image_factor() is None
    for kl in (2.01, 10.0):
        assert film(kl).image_factor() == pytest.approx((0.5 + 0.5 / (1 + kl)) / 0.5, rel=1e-9)
    assert film(-0.3).image_factor() == film(0.3).image_factor()


def test_line_images_bounded_without_the_measurement():
    """Where every tail is short or summed and the contact frictionless, the line solve does
    not measure its images on twice the period (domain_difference 0: the elastic cost) and the
    estimate's image term bounds them: the solve's own fixed grid on its period against twice
    it (same cells).  Measured as before: between (0.1 m/s, kappa l_r = 0.74), past tol/4 on
    the margin (a film 31 times stiffer when glassy), and with friction where the bound times
    d_el/d passes tol/4 (E_1 = 10 E_inf, 0.32 m/s, mu 2: d = 0.11 against d_el = 1.67; the
    images' change of d was 1.6 times the plain bound): ``test_line_images_bounded_with_
    friction``."""
    from spectral_contact.solvers.fft import solve_fft
    from studies.viscoelastic import FILM, _line_change, load_for

    for V, measured in ((0.316, False), (0.01, False), (0.1, True)):
        s = Scene(load=load_for(1.0), mu=0.0, speed=V, prony=SLS, **FILM)
        r = solve_fft(s, tol=TOL)
        assert (r.info["domain_difference"] > 0.0) == measured
        N, L = r.grid_points, r.domain_length
        diff = _line_change(solve_fft(s, tol=TOL, grid_points=N, domain_length=L),
                            solve_fft(s, tol=TOL, grid_points=2 * N, domain_length=2 * L))
        assert diff <= r.info["image_error"], V
    # (tau 1e-4 at tol 1e-3 before: that scene's refinement stagnates on 8 of 11 periods in
    # 16.8-18.8 h, whatever the images; this one, at tol 1e-2, converges on 11 of 11 in
    # 15.3-17.3 h)
    stiff = Scene(load=load_for(1.0), mu=0.0, speed=0.01, prony=((30 * E_INF, 1e-3),), **FILM)
    assert stiff.core_film().image_factor() > 30.0
    assert solve_fft(stiff, tol=1e-2).info["domain_difference"] > 0.0
    rubbing = Scene(load=200.0, mu=2.0, speed=0.316, prony=((10 * E_INF, 0.01),), **FILM)
    assert rubbing.core_film().image_factor() < 2.0
    assert solve_fft(rubbing, tol=TOL).info["domain_difference"] > 0.0


def test_line_images_bounded_with_friction():
    """With friction in the contact the images are bounded too (not measured on twice the
    period) where the frictionless bound applies, times max(1, d_el/d) (d relative to itself;
    friction can take it far below the relaxed film's d_el): the paper's scene (mu 2) on the
    SLS at 0.316 m/s (d_ratio 1.9: without it 0.82 of the bound, with it 0.42) and on a film
    11 times stiffer when glassy at 1 m/s (d = 0.22 against 1.67: d_ratio 7.5), and a contact
    of half-width 6.4 h (P_L 2e4 N/m, 0.05 m/s); the solve's own fixed grid on its period
    against twice it within the image term.  The case that
    failed the plain bound (the stiff film at 0.316 m/s, d = 0.11: 1.6 times it) is measured
    (``test_line_images_bounded_without_the_measurement``)."""
    from spectral_contact.solvers.fft import solve_fft
    from studies.viscoelastic import FILM, _line_change

    for load, prony, V, least in ((200.0, SLS, 0.316, 1.5), (200.0, ((10 * E_INF, 0.01),), 1.0, 5.0),
                                  (2e4, SLS, 0.05, 1.0)):  # (the last: a = 6.4 h, 0.64 of it)
        s = Scene(load=load, mu=2.0, speed=V, prony=prony, **FILM)
        r = solve_fft(s, tol=TOL)
        assert r.info["domain_difference"] == 0.0
        assert r.info["friction_images_bound"]["d_ratio"] > least
        N, L = r.grid_points, r.domain_length
        diff = _line_change(solve_fft(s, tol=TOL, grid_points=N, domain_length=L),
                            solve_fft(s, tol=TOL, grid_points=2 * N, domain_length=2 * L))
        assert diff <= r.info["image_error"], V


def test_even_parts_series_meets_closed_form():
    """The in-plane tail symbols' even parts (F2/(2K) - 1)/K^2, (tanh K/K - 1)/K^2: the series
    used at |K^2| < 2e-3 meets the closed forms at the switch (both signs of K^2), and 1/D
    is 1/2 at K = 0."""
    from spectral_contact.physics.viscoelastic import _even_parts

    for K2 in (2e-3, -2e-3):
        inside = np.array(_even_parts(np.array([K2 * (1 - 1e-9)])))
        outside = np.array(_even_parts(np.array([K2 * (1 + 1e-9)])))
        assert np.allclose(inside, outside, rtol=1e-8, atol=0)
    assert _even_parts(np.array([0.0]))[2][0] == pytest.approx(0.5)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_sphere_surface_displacements_tail_images_summed(sign, monkeypatch):
    """3D, V tau_r = 30 h (twice the period): the surface u_x, u_y (and u_z) of the fixed grid
    on twice the period and on four times it (same cells) agree to 1e-5 of their largest
    values (the in-plane tails' images summed like the sinking's:
    ``ViscoelasticFilm.tail_displacement_poles``); without that sum u_x, u_y were off by
    4 % (and by 14 % on the period itself), u_z was not (its tail already summed)."""
    h = 0.002
    kw = dict(indenter="sphere", force=1.0, mu=0.5 * sign, speed=3.0 * sign, prony=SLS,
              tol=1e-2, thickness=h)

    def change():
        res = [solve(**kw, grid_points=(128 * f, 64), domain_length=(0.03 * f, 0.03))
               for f in (2, 4)]
        out = {}
        for name in ("surface_ux", "surface_uy", "surface_uz"):
            f0, f1 = (getattr(q, name) for q in res)
            ix = np.searchsorted(res[1].x, res[0].x - 1e-12)
            out[name] = np.abs(f0 - f1[ix]).max() / np.abs(f1).max()
        return out

    ch = change()
    assert max(ch.values()) < 1e-5, ch
    monkeypatch.setattr(ViscoelasticFilm, "tail_displacement_poles", lambda self, mu=0.0: [])
    ch = change()
    assert ch["surface_ux"] > 1e-2 and ch["surface_uy"] > 1e-2 and ch["surface_uz"] < 1e-5, ch


@pytest.mark.parametrize("tol", [1e-3, 1e-4])
def test_slow_sliding_takes_the_elastic_grids(tol):
    """The slow path's elastic solve runs at tol less the remainder (1e-6 here), not 3 tol/4:
    it takes the elastic solve's own grid (the paper's scene at tol 1e-4: 16384 points at 3
    tol/4 against the elastic 2048, the estimates not being monotone in N), and its estimate,
    the elastic one plus the remainder, stays within tol."""
    from studies.viscoelastic import FILM

    kw = dict(load=200.0, mu=2.0, tol=tol, **FILM)
    slow = solve(speed=1e-4, prony=SLS, **kw)
    el = solve(**kw)
    rem = slow.info["slow_sliding"]["remainder"]
    assert rem <= 1e-2 * tol * (1 + 1e-9)
    assert slow.grid_points == el.grid_points
    assert slow.error_estimate == pytest.approx(
        slow.info["slow_sliding"]["elastic_error_estimate"] + rem, rel=1e-12)
    assert slow.error_estimate <= tol and slow.info["tolerance_met"]


def test_second_order_centroid_energy_identity():
    """The slow-sliding theory's second-order centroid (ViscoelasticFilm
    .slow_centroid_second_order: the energy identity's high wavenumbers, from the relaxed
    solve's edge amplitudes, visco_slow.edge_amplitudes) on a film contact as wide as the film,
    a_H/h = 1 (not Hunter's half-space: its coefficient is -1.34, Hunter's -1, in c2/a^2), at
    V tau/h = 0.016: the resolved solve's centroid is the first-order one (x_p,el + delta) plus
    it, within 10 % of it (measured 0.1 %), and differs from the first-order one by more than
    90 % of it."""
    from spectral_contact.solvers.fft import solve_fft
    from spectral_contact.solvers.visco_slow import edge_amplitudes
    from studies.viscoelastic import FILM, SLS, load_for

    relaxed = Scene(load=load_for(1.0), mu=0.0, **FILM)
    el = solve_fft(relaxed, tol=1e-5)
    s = Scene(load=load_for(1.0), mu=0.0, speed=3.2e-3, prony=SLS, **FILM)
    full = solve_fft(s, tol=1e-4)
    assert "slow_sliding" not in full.info  # resolved: V tau spans >= 2 cells
    film = s.core_film()
    dx = el.x[1] - el.x[0]
    P = float(np.sum(el.pressure)) * dx
    amp = edge_amplitudes(el.x, el.pressure, el.info["edges"][0], 0.3 * el.half_width)
    xp2 = film.slow_centroid_second_order(sum(amp), P)
    first = float(np.dot(el.pressure, el.x)) * dx / P + film.slow_shift
    xp = full.info["pressure_centroid"]
    assert abs(xp - first - xp2) <= 0.1 * abs(xp2)
    assert abs(xp - first) >= 0.9 * abs(xp2)


def test_slow_path_centroid_second_order():
    """The slow path (a_H/h 0.1 at V tau/h = 5e-4, tol 1e-3) adds the second-order centroid
    term: its centroid within 4e-6 a (a tenth of the term) of a resolved solve (2^21 points
    on twice the period; the first-order one is 3.8e-5 a off: studies/README, viscoelastic,
    second order), the term recorded, and the pressure field's centroid the reported one."""
    from spectral_contact.solvers.fft import solve_fft
    from studies.viscoelastic import FILM, SLS, load_for

    s = Scene(load=load_for(0.1), mu=0.0, speed=1e-4, prony=SLS, **FILM)
    r = solve_fft(s, tol=1e-3)
    x2 = r.info["slow_sliding"]["centroid_second_order_h"]
    assert x2 < 0.0
    ref = solve_fft(s, tol=1e-4, grid_points=2**21, domain_length=2 * r.domain_length)
    a = ref.half_width
    assert abs(r.info["pressure_centroid"] - ref.info["pressure_centroid"]) < 4e-6 * a
    assert abs(r.info["pressure_centroid"] - x2 - ref.info["pressure_centroid"]) > 3e-5 * a
    field = float(np.dot(r.pressure, r.x) / np.sum(r.pressure))
    assert field == pytest.approx(r.info["pressure_centroid"], abs=1e-3 * abs(x2))
    # the mirror: V -> -V moves the centroid and its second-order term to the other side
    m = solve_fft(Scene(load=load_for(0.1), mu=0.0, speed=-1e-4, prony=SLS, **FILM), tol=1e-3)
    assert m.info["slow_sliding"]["centroid_second_order_h"] == pytest.approx(-x2, rel=1e-9)
    assert m.info["pressure_centroid"] == pytest.approx(-r.info["pressure_centroid"],
                                                        abs=1e-3 * abs(x2))


def test_cost_study_tolerances(tmp_path, capsys):
    """studies.viscoelastic_cost --tol: comma-separated tolerances in (0, 0.1), one table each;
    anything else one line naming --tol, exit 2."""
    from studies.viscoelastic_cost import _tols
    from studies.viscoelastic_cost import main as cost_main

    assert _tols("1e-3,1e-4") == (1e-3, 1e-4)
    for bad in ("0.5", "abc", "1e-3,", "0"):
        with pytest.raises(SystemExit) as e:
            cost_main(["--tol", bad, "--out", str(tmp_path)])
        assert e.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--tol" in err[0]


def test_cost_study_film(tmp_path, capsys):
    """studies.viscoelastic_cost --film E1=3Einf: the heavier single term's own table (its Prony
    term in the title), beside the SLS's; an unknown film exits 2."""
    import json

    from studies.viscoelastic_cost import main as cost_main

    assert cost_main(["--quick", "--film", "E1=3Einf", "--tol", "1e-3", "--out", str(tmp_path)]) == 0
    rows = np.genfromtxt(tmp_path / "viscoelastic_cost_E1=3Einf.csv", delimiter=",", names=True,
                         dtype=None, encoding="utf-8")
    assert rows.size == 6 and np.all(rows["time_ratio"] > 0)
    title = json.loads((tmp_path / "viscoelastic_cost_E1=3Einf.meta.json").read_text())["title"]
    assert "E_i 6.6e+06 Pa" in title
    assert not (tmp_path / "viscoelastic_cost.csv").exists()
    with pytest.raises(SystemExit) as e:
        cost_main(["--film", "E1=5Einf", "--out", str(tmp_path)])
    assert e.value.code == 2


@pytest.mark.parametrize("kl,mu,sign", [(0.074, 0.0, 1.0), (0.74, 2.0, 1.0), (0.74, 2.0, -1.0),
                                        (1.0, 0.0, 1.0), (1.48, -1.0, 1.0), (4.4, 0.0, 1.0)])
def test_line_far_field_is_the_kernels(kl, mu, sign):
    """``ViscoelasticFilm.line_far_field`` (the residues at the elastic poles times R there and
    at the tails' poles; at kappa l = 1 the double pole) is the line kernel's far field: the
    inverse FFT of H R on 2^18 points over 250 h, 5-10 h behind and ahead of the load, to
    1e-3 (6e-4 at 5 h: the next elastic poles, |Im k| h = 2.49, left out).  The summed tail
    (kappa l = 4.4) without its own pole: behind only the elastic pole's R(-i kappa); the
    kernel behind is that plus the tail's c B exp(-d/l)/l."""
    kappa = 0.7390851332151607
    f = ViscoelasticFilm(thickness=1.0, relaxed_young=1.0, prony=((1.0, 1.0),),
                         speed=sign * kl / (2.0 * kappa))  # tau_r = 2: l = 2 |V|
    n, L = 2**18, 250.0
    k = 2.0 * np.pi * np.fft.fftfreq(n, L / n)
    kernel = np.fft.ifft(f.surface_compliance((np.sign(k), 0.0), np.abs(k), mu)).real * n / L
    idx = np.rint(np.array([5.0, 7.5, 10.0]) * n / L).astype(int)  # s = +d at idx, -d at -idx
    d = idx * (L / n)
    behind, ahead = f.line_far_field(d, mu)
    g0 = (math.sin(2 * kappa) - 2 * kappa) / (2 * kappa)
    norm = (abs(g0) + abs(mu) * kappa) / (2.0 * (math.sin(2 * kappa) + 2 * kappa))
    num_behind = (kernel[-idx] if sign > 0 else kernel[idx]) / norm
    num_ahead = (kernel[idx] if sign > 0 else kernel[-idx]) / norm
    assert np.allclose(num_ahead, ahead, rtol=1e-3, atol=0)
    if kl < 2.0:
        assert np.allclose(num_behind, behind, rtol=1e-3, atol=0)
    else:  # the tail's own pole, c B exp(-d/l)/l, is the difference
        tail = f.tail_poles(mu)[0]
        own = tail[1](np.zeros(1))[0] * np.exp(-d / abs(tail[0])) / abs(tail[0]) / norm
        assert np.allclose(num_behind, behind + own, rtol=1e-3, atol=0)


def test_line_margin():
    """``ViscoelasticFilm.line_margin``: the elastic film's margin at rest; the kernel's far
    field beyond it is below tol/100 of the elastic amplitude (and just above it before the
    margin); the decays do not add: at kappa l_r = 0.74 (0.1 m/s on the study's SLS) it is
    within 1.5 h of the elastic ln(100/tol)/kappa (ln|R(-i kappa)|/kappa = 1.2 h, R = 2.4) where
    the added margin was 13 h longer."""
    kappa = 0.7390851332151607
    rest = ViscoelasticFilm(thickness=1.0, relaxed_young=1.0, prony=((1.0, 1.0),), speed=0.0)
    assert rest.line_margin(1e-4, 2.0) == Film().domain_margin(1e-4)
    for kl in (0.074, 0.3, 0.74, 1.0, 1.5, 3.0):
        for mu in (0.0, 2.0, -2.0):
            f = ViscoelasticFilm(thickness=1.0, relaxed_young=1.0, prony=((1.0, 1.0),),
                                 speed=kl / (2.0 * kappa))
            m = f.line_margin(1e-4, mu)
            d = np.linspace(m, m + 60.0, 3001)
            assert np.abs(f.line_far_field(d, mu)).max() <= 1e-6 * (1.0 + 1e-8)
            assert np.abs(f.line_far_field(np.array([m - 0.05]), mu)).max() > 1e-6
    f = ViscoelasticFilm(thickness=1.0, relaxed_young=1.0, prony=((1.0, 1.0),),
                         speed=0.74 / (2.0 * kappa))
    elastic = math.log(100.0 / 1e-4) / kappa
    assert f.line_margin(1e-4) < elastic + 1.5
    assert f.domain_margin(1e-4, tails_corrected=True) > elastic + 13.0


@pytest.mark.parametrize("load_h,mu,V", [(1.0, 0.0, 0.0316), (1.0, 0.0, 0.1), (None, 2.0, 0.0316),
                                         (None, 2.0, 0.1), (3.0, 0.0, -0.1)])
def test_line_period_near_the_elastic_one(load_h, mu, V):
    """At retardation lengths 0.3-1 h (0.0316 and 0.1 m/s on the study's SLS: kappa l_r 0.23,
    0.74) the automatic line period is within 1.06 of the elastic film's (it was 1.2 and 1.6
    times it: the tail's margin l ln(100 A/tol) added to the elastic one), and the images on
    it stay within the estimate's image term: the solve's own fixed grid on its period against
    2N points on twice it."""
    from spectral_contact.solvers.fft import solve_fft
    from studies.viscoelastic import FILM, _line_change, load_for

    load = 200.0 if load_h is None else load_for(load_h)
    el = solve_fft(Scene(load=load, mu=mu, **FILM), tol=TOL)
    s = Scene(load=load, mu=mu * (1.0 if V > 0 else -1.0), speed=V, prony=SLS, **FILM)
    r = solve_fft(s, tol=TOL)
    assert r.domain_length < 1.12 * el.domain_length, r.domain_length / el.domain_length
    N, L = r.grid_points, r.domain_length
    diff = _line_change(solve_fft(s, tol=TOL, grid_points=N, domain_length=L),
                        solve_fft(s, tol=TOL, grid_points=2 * N, domain_length=2 * L))
    assert diff <= r.info["image_error"]
    assert r.error_estimate <= TOL


def test_full_path_meets_the_slow_sliding_theory():
    """Two independent routes to slow sliding agree: the first-order theory (solvers.visco_slow,
    from Hunter's closed form: the relaxed elastic contact, trailing edge in by delta, pressure
    translated by delta), its elastic solve at tol 1e-5, and the full viscoelastic solve on a
    fixed grid whose cells are 80 times V tau (a_H/h 1 at 1e-5 m/s, 4096 points, the period of
    the tol-1e-4 solve), its trailing edge fitted with the inner layer and corrected by the
    collocation's edge error (``solvers.fft.VISCO_LATTICE``): a, x_c, the centroid within 1e-5
    of a, d and p_max within 1e-5 (measured 2.8e-6 on a; the full path on 2^18 points 3e-7).
    With the elastic edge fit the trailing edge sits delta further out: a 3.1e-5 off.  (Before
    the correction the theory's elastic solve was taken at tol 1e-4 on the same 4096 nodes:
    they agreed within 2e-7 by sharing the nodes' edge error, while both were 4.5e-5 from the
    converged half-width.)"""
    from studies.viscoelastic import FILM, load_for
    kw = dict(load=load_for(1.0), mu=0.0, speed=1e-5, prony=SLS, **FILM)
    period = solve(**kw, tol=1e-4).domain_length * FILM["thickness"]
    slow = solve(**kw, tol=1e-5)
    assert "slow_sliding" in slow.info
    full = solve(**kw, tol=1e-4, grid_points=4096, domain_length=period)
    assert "slow_sliding" not in full.info
    a = slow.half_width
    assert abs(full.half_width - a) / a < 1e-5
    assert abs(full.center - slow.center) / a < 1e-5
    assert abs(full.info["pressure_centroid"] - slow.info["pressure_centroid"]) / a < 1e-5
    assert abs(full.indentation - slow.indentation) / slow.indentation < 1e-5
    assert abs(full.max_pressure - slow.max_pressure) / slow.max_pressure < 1e-5


def test_stagnating_levels_fall_back_to_the_resolved_edge_structure(monkeypatch):
    """A film 11 times stiffer when glassy (E_1 = 10 E_inf), a_H/h 1 at 1e-4 m/s, tol 1e-4.  Its
    term is left to the edge fits (``_LineSolve.LAYER_FITTED_WEIGHT``, seventh session); with
    the fits as they were before that session (the trailing fit's plain iteration, the 3-node
    peak: tests/test_viscoelastic_heavy.py), the levels stagnate and the line solver solves
    again with the structure resolved (``solve_fft``'s fallback: exit 3 without it).  Both say
    so in info; the estimates bound the error against 2^19 points on twice the period."""
    from spectral_contact.numerics import edges
    from spectral_contact.solvers import fft as fft_solver
    from studies.viscoelastic import FILM, load_for
    from tests.test_viscoelastic_heavy import _old_trailing_root
    kw = dict(load=load_for(1.0), mu=0.0, tol=1e-4, speed=1e-4, prony=((10 * E_INF, 0.01),),
              **FILM)
    r = solve(**kw)
    monkeypatch.setattr(fft_solver, "peak_odd_even", edges.peak)
    monkeypatch.setattr(edges, "_trailing_root", _old_trailing_root)
    fallback = solve(**kw)
    ref = solve(**kw, grid_points=2**19, domain_length=2 * r.domain_length * FILM["thickness"])
    assert "edge_structure_resolved" not in r.info
    assert fallback.info.get("edge_structure_resolved") is True
    for res in (r, fallback):
        assert res.info["tolerance_met"]
        assert np.abs(_rel(res, ref)).max() <= res.error_estimate <= 1e-4
    # the fallback's first attempt is counted: more pairs than the direct solve
    assert fallback.counters["transforms"] > r.counters["transforms"]


# --- surfaces without the grid rule (issue 23's sixth session) ------------------------------
def test_surface_peak_pressure_ignores_the_odd_even_mode():
    """A viscoelastic surface's p_max (numerics.edges.peak_odd_even along x): a smooth pressure
    1 - 2 r^2 (peak 1 at x = 0.013, between nodes) plus an odd-even mode of 1 % along x
    (what an unresolved edge structure leaves) has its peak within 1e-4; the 3-node parabola
    (elastic films, and the viscoelastic ones before) is ~1 % off."""
    from spectral_contact.numerics.grid import Grid
    from spectral_contact.numerics.measure2d import measure_contact_2d
    g = Grid.centered((64, 64), (4.0, 4.0))
    x, y = np.meshgrid(*g.axes, indexing="ij")
    smooth = 1.0 - 2.0 * ((x - 0.013) ** 2 + y ** 2)
    active = smooth > 0
    odd = 0.01 * (-1.0) ** np.arange(64)[:, None] * active
    p = np.where(active, smooth + odd, 0.0)
    gap = np.where(active, 0.0, np.maximum(-smooth, 0.0) ** 1.5)
    layered = measure_contact_2d(g, p, gap, active, (-1, [(0.5, 0.01)]))
    plain = measure_contact_2d(g, p, gap, active)
    assert abs(layered["pmax"] - 1.0) < 1e-4
    assert abs(plain["pmax"] - 1.0) > 5e-3


def test_sphere_slow_sliding_edge_structure_fitted_not_gridded():
    """The SLS sphere at 1 mm/s (V tau/h = 5e-3), tol 1e-2: the grid rule (V tau spanned by 2
    cells) asked 8192 x 128 points on the first level and refused the solve
    (ConvergenceError); with the edge fits (layered trailing edges, p_max with the odd-even
    mode) it runs on the elastic sphere's grid and its estimate bounds its error against 4
    times finer cells per axis on the same period (measured 7.9e-5 against 2.0e-3)."""
    from studies.viscoelastic import FILM
    h = FILM["thickness"]
    kw = dict(indenter="sphere", force=1.0, mu=0.0, prony=SLS, speed=1e-3, tol=1e-2, **FILM)
    r = solve(**kw)
    assert max(r.grid_points) <= 512
    (nx, ny), (lx, ly) = r.grid_points, r.domain_length
    ref = solve(grid_points=(4 * nx, 4 * ny), domain_length=(lx * h, ly * h), **kw).summary()
    s = r.summary()
    for k in ("contact_radius_m", "indentation_m", "max_pressure_Pa"):
        assert abs(s[k] - ref[k]) / abs(ref[k]) <= r.error_estimate
    rad = ref["contact_radius_m"]
    assert abs(s["pressure_centroid_x_m"] - ref["pressure_centroid_x_m"]) / rad <= \
        r.error_estimate


def test_resolved_edge_structure_beyond_the_largest_grid_is_refused_before_any_solve(
        monkeypatch):
    """A heavy Prony term (E_i/E_inf > 10 since the seventh session: its edge structure
    resolved; E_i = 2 E_inf before, now fitted) whose |V| tau needs a third level beyond 2^22
    points: refused at once, naming the edge structure (InputError, exit 2).  Before: two
    levels of 2^21 and 2^22 points (~15 s), then exit 3 with the message "error estimate
    4.9e-05 > tol 1.0e-04" (false: the estimate was below tol, one level short of the three
    it needs)."""
    from spectral_contact.solvers import fft
    from studies.viscoelastic import E_INF, FILM, load_for

    def no_levels(*args, **kwargs):
        raise AssertionError("the refinement levels ran")
    monkeypatch.setattr(fft, "refine", no_levels)  # refused before the levels, not after
    prony = tuple((11.0 * E_INF, 10.0 ** k) for k in range(-5, 0))
    with pytest.raises(InputError, match="edge structure"):
        solve(load=load_for(0.3), mu=0.5, speed=1e-5, prony=prony, tol=1e-4, **FILM)
    rc = main(["solve", "--load", f"{load_for(0.3):.6g}", "--mu", "0.5", "--speed", "1e-5",
               "--prony", ",".join(f"{11.0 * E_INF:g},{10.0 ** k:g}" for k in range(-5, 0)),
               "--young", f"{E_INF:g}", "--thickness", f"{FILM['thickness']:g}",
               "--radius", f"{FILM['radius']:g}"])
    assert rc == 2


def test_a_scenes_viscoelastic_film_object_is_the_scenes_own_fields():
    """``solve(film=ViscoelasticFilm(thickness [m], young = E_inf [Pa], prony, speed [m/s]))`` is
    the solve of ``solve(speed=, prony=)`` bit for bit, line and sphere (before: the slow path's
    relaxed scene kept the moving film, RecursionError; the film's speed would have been read in
    h/s).  ``relaxed_young`` defaults to ``young`` (before: 1 Pa, a peak loss tangent of 99.5
    instead of 0.354); both given and different, a film without young, or the speed given twice:
    one-line InputError."""
    f = ViscoelasticFilm(thickness=2e-3, young=2.2e6, prony=((2.2e6, 0.01),), speed=0.05)
    assert f.relaxed_young == 2.2e6
    assert f.peak_loss_tangent()[0] == pytest.approx(0.5 / math.sqrt(2.0), rel=1e-9)
    a, b = solve(film=f, tol=1e-3), solve(speed=0.05, prony=((2.2e6, 0.01),), tol=1e-3)
    assert np.array_equal(a.pressure, b.pressure) and a.half_width == b.half_width
    assert a.to_dict()["speed_m_per_s"] == 0.05
    kw = dict(indenter="sphere", force=1.0, mu=0.3, tol=1e-2)
    a3 = solve(film=f, **kw)
    b3 = solve(speed=0.05, prony=((2.2e6, 0.01),), **kw)
    assert np.array_equal(a3.pressure, b3.pressure)
    for bad in (dict(thickness=2e-3, relaxed_young=2.2e6, prony=((2.2e6, 0.01),), speed=0.05),):
        with pytest.raises(InputError, match="young = E_inf"):
            solve(film=ViscoelasticFilm(**bad))
    with pytest.raises(InputError, match="relaxed modulus"):
        ViscoelasticFilm(thickness=2e-3, young=2.2e6, relaxed_young=1e6)
    with pytest.raises(InputError, match="given both"):
        solve(film=f, speed=0.05)


def test_a_non_converged_solve_beyond_the_verified_prony_range_says_so(capsys):
    """A film 10^6 times stiffer when glassy (E_1/E_inf = 1e6, inside the accepted 1e12) at
    1 mm/s: the active set does not settle (exit 3, nothing written); the message names the
    term's weight against the verified one (before: only the solver's residual)."""
    assert main(["solve", "--speed", "1e-3", "--prony", "2.2e12,0.01"]) == 3
    err = capsys.readouterr().err
    assert "E_i/E_inf = 1e+06, beyond the 10" in err and len(err.strip().splitlines()) == 1


def test_sphere_text_summary_names_the_viscoelastic_film(capsys):
    """The sphere's text summary has the viscoelastic line (V, the terms, mu_def, Q/P) as the
    line's has (before: only its JSON record)."""
    code, out, _ = _cli(capsys, "--indenter", "sphere", "--force", "1", "--mu", "0.3", "--speed",
                        "0.1", "--prony", "2.2e6,0.01", "--tol", "1e-2")
    assert code == 0 and "viscoelastic film        V = 0.1 m/s, 1 Prony term(s); mu_def" in out
    code, out, _ = _cli(capsys, "--indenter", "sphere", "--force", "1", "--tol", "1e-2")
    assert code == 0 and "viscoelastic" not in out


def test_speeds_near_the_shear_wave_speed_are_flagged():
    """The solve is quasi-static: past a tenth of the relaxed film's shear-wave speed
    sqrt(E_inf/(3 rho)) (rho 1000 kg/m^3: 27 m/s for 2.2 MPa) a UserWarning says inertia is
    neglected; below it, no warning (the scene only: nothing is solved)."""
    import warnings

    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        Scene(speed=10.0, prony=SLS)
        Scene(speed=-2.0, mu=-1.0, prony=SLS)
    assert len(seen) == 1 and "0.37 of the film's shear-wave speed" in str(seen[0].message)


def test_film_object_edge_cases_and_the_heavy_note():
    """(Review of the ninth session.)  A ViscoelasticFilm whose Prony moduli all look relative
    to E_inf (below 1e-3 young: E_inf defaulted to 1 before) warns; dataclasses.replace of
    young alone is refused with the way out, relaxed_young=None follows young; the non-
    convergence note counts a line's heaviest term but a surface's sum (its fits are bounded by
    E_0/E_inf); the sphere study's unknown film: exit 2."""
    import dataclasses
    import warnings

    from spectral_contact.physics.scene import Scene3D
    from spectral_contact.solvers.fft_method import _beyond_verified
    from studies.viscoelastic_sphere import main as sphere_main

    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        ViscoelasticFilm(thickness=2e-3, young=2.2e6, prony=((1.0, 0.01),), speed=0.05)
        ViscoelasticFilm(thickness=2e-3, young=2.2e6, prony=((2.2e6, 0.01),), speed=0.05)
    assert len(seen) == 1 and "not relative to E_inf" in str(seen[0].message)
    f = ViscoelasticFilm(thickness=2e-3, young=2.2e6, prony=((2.2e6, 0.01),))
    with pytest.raises(InputError, match="relaxed_young=None"):
        dataclasses.replace(f, young=3e6)
    assert dataclasses.replace(f, young=3e6, relaxed_young=None).relaxed_young == 3e6
    two = ((6 * 2.2e6, 0.01), (6 * 2.2e6, 0.1))
    assert _beyond_verified(Scene(speed=0.01, prony=two)) is None  # each 6 <= 10
    note = _beyond_verified(Scene3D(indenter="sphere", speed=0.01, prony=two))
    assert note is not None and "sum E_0/E_inf - 1 = 12" in note
    assert sphere_main(["--films", "SLS,foo", "--parts", "cost"]) == 2
