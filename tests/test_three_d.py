"""3D: indenters of finite size on the film (issue 10): limits, symmetries, equilibrium, the
2D solver as the long-cylinder limit, the error estimate, the command line."""
import json
import math

import numpy as np
import pytest

from spectral_contact import InputError, solve
from spectral_contact.cli.main import main
from spectral_contact.numerics.contact import solve_contact
from spectral_contact.numerics.edges import fit_edges
from spectral_contact.numerics.grid import Grid
from spectral_contact.physics.indenters import Cylinder, FiniteCylinder, Sphere
from spectral_contact.physics.scene import Scene3D
from spectral_contact.result import JSON_KEYS_3D, MAP_KEYS
from spectral_contact.solvers.fft3d import solve_fft3d


@pytest.fixture(scope="module")
def sliding():
    """The sliding sphere of the speed target (a/h ~ 1.3, mu = 1) at a modest tolerance."""
    return solve(indenter="sphere", force=1.0, mu=1.0, tol=3e-3)


def _cell(r):
    return (r.x[1] - r.x[0]) * (r.y[1] - r.y[0])


def test_equilibrium_and_complementarity(sliding):
    r, P = sliding, sliding.scene.P
    c = _cell(r)
    assert r.base_sigma_zz.sum() * c == pytest.approx(-P, rel=1e-8)
    assert r.base_sigma_xz.sum() * c == pytest.approx(r.scene.mu * P, rel=1e-8)
    assert abs(r.base_sigma_yz.sum() * c) < 1e-8 * P
    assert r.pressure.sum() * c == pytest.approx(P, rel=1e-8)
    assert r.pressure.min() >= 0.0
    s = r.summary()
    assert set(JSON_KEYS_3D) <= set(s)
    # friction pushes the contact and the peak forward (toward +x) and tilts sigma_zz
    assert s["pressure_centroid_x_m"] > 0 and s["max_pressure_x_m"] > 0
    assert s["contact_x_max_m"] > -s["contact_x_min_m"]


def test_mirror_and_y_symmetry():
    g = Grid.centered((128, 128), (14.0, 14.0))
    plus = solve_contact(g, 1.5, [Sphere(0.0, 30.0)])
    minus = solve_contact(g, -1.5, [Sphere(0.0, 30.0)])
    flip = (-np.arange(128)) % 128
    np.testing.assert_allclose(minus.pressure, plus.pressure[flip, :], atol=1e-9 * plus.pressure.max())
    np.testing.assert_allclose(plus.pressure, plus.pressure[:, flip], atol=1e-9 * plus.pressure.max())
    assert np.all(plus.gap[~plus.active] >= -1e-9 * np.abs(plus.sinking).max())


def test_infinite_cylinder_is_the_plane_strain_solution():
    """Height independent of y: every row is the 1D solution (mu = 0 and 2)."""
    for mu in (0.0, 2.0):
        g1 = Grid.centered(512, 20.0, 0.5)
        s1 = solve_contact(g1, mu, [Cylinder(0.0, 40.0)])
        g2 = Grid.centered((512, 8), (20.0, 2.0), (0.5, 0.0))
        s2 = solve_contact(g2, mu, [Cylinder(0.0, 40.0 * 2.0)])
        np.testing.assert_allclose(s2.pressure, np.repeat(s1.pressure[:, None], 8, axis=1),
                                   atol=1e-9 * s1.pressure.max())
        assert s2.indentations[0] == pytest.approx(s1.indentations[0], rel=1e-9)


@pytest.mark.parametrize("mu", [0.0, 2.0])
def test_long_finite_cylinder_matches_2d_at_its_line_load(mu):
    """A cylinder 40 h long: at y = 0 the half-width and centre are the plane-strain ones at
    the line load carried there (within 1 % of a: the grid has 16 cells across the contact)."""
    P_line = 40.0
    g = Grid.centered((256, 512), (24.0, 48.0), (0.4 if mu else 0.0, 0.0))
    s = solve_contact(g, mu, [FiniteCylinder(0.0, P_line * 40.0, 1.0, 20.0)])
    x, y = g.axes
    j0 = int(np.argmin(np.abs(y)))
    line = s.pressure[:, j0].sum() * g.dx
    assert line == pytest.approx(P_line, rel=0.05)  # ends carry more: a little less mid-way
    (left, right), = fit_edges(x, g.dx, s.gap[:, j0], s.pressure[:, j0], s.active[:, j0])
    ref = solve(load=line * s_unit_load(), mu=mu, tol=1e-6)
    assert 0.5 * (right - left) == pytest.approx(ref.half_width, rel=1e-2)
    assert 0.5 * (right + left) == pytest.approx(ref.center, abs=1e-2 * ref.half_width)


def s_unit_load():
    """N/m per unit of dimensionless line load for the default scene."""
    from spectral_contact import PAPER_SCENE

    return PAPER_SCENE.stress_unit * PAPER_SCENE.length_unit


def test_small_sphere_approaches_hertz():
    """Frictionless sphere with a_H = 0.2 h: Hertz (incompressible half-space) within the layer
    correction, bounded here by 2 (a/h)^2 = 8 % (the film stiffens the contact: a < a_H)."""
    a_h = 0.2
    P = 32.0 * a_h**3 / 3.0
    g = Grid.centered((512, 512), (10.0, 10.0))
    s = solve_contact(g, 0.0, [Sphere(0.0, P)])
    area = s.active.sum() * g.cell
    a = math.sqrt(area / math.pi)
    assert a < a_h * 1.02
    assert a == pytest.approx(a_h, rel=2 * a_h**2)
    assert s.pressure.max() == pytest.approx(16 * a_h / math.pi, rel=2 * a_h**2 + 0.02)


def test_goodman_window_is_frictionless_and_exact_differs(sliding):
    s = sliding.scene
    good = solve(s, model="goodman", tol=3e-3)
    frictionless = solve(s.with_(mu=0.0), tol=3e-3)
    assert good.contact_radius == pytest.approx(frictionless.contact_radius, rel=1e-12)
    np.testing.assert_array_equal(good.pressure, frictionless.pressure)
    assert abs(sliding.measures["xc"] - good.measures["xc"]) > 0.1
    # but Goodman's base shear still carries the friction
    assert good.base_sigma_xz.sum() * _cell(good) == pytest.approx(s.mu * s.P, rel=1e-8)


def test_error_estimate_bounds_the_error_against_a_finer_solve():
    scene = Scene3D(force=0.5, mu=1.0)
    coarse = solve_fft3d(scene, tol=1e-2)
    fine = solve_fft3d(scene, tol=1e-2, grid_points=2 * coarse.grid_points[0] * 2,
                       domain_length=coarse.domain_length)
    for key in ("indentation", "pmax"):
        err = abs(coarse.measures[key] - fine.measures[key]) / abs(fine.measures[key])
        assert err <= max(coarse.error_estimate, 1e-12)
    err_r = abs(coarse.contact_radius - fine.contact_radius) / fine.contact_radius
    assert err_r <= coarse.error_estimate
    assert coarse.error_estimate <= 1e-2


def test_hertz_model_for_the_sphere_only():
    r = solve(indenter="sphere", force=1.0, model="hertz")
    a = (3 * r.scene.P / 32) ** (1 / 3)
    assert r.contact_radius == pytest.approx(a, rel=1e-12)
    assert r.base_sigma_zz.sum() * _cell(r) == pytest.approx(-r.scene.P, rel=1e-6)
    with pytest.raises(InputError, match="sphere"):
        solve(indenter="cylinder", force=1.0, model="hertz")


def test_front_function_validates_the_scene():
    with pytest.raises(InputError, match="force"):
        solve(load=100.0, force=1.0)
    with pytest.raises(InputError, match="load"):
        solve(indenter="sphere", load=100.0)
    with pytest.raises(InputError, match="indenter"):
        solve(indenter="cone", force=1.0)
    with pytest.raises(InputError, match="method"):
        solve(indenter="sphere", force=1.0, method="abel")


def test_height_function_indenter_equals_the_sphere():
    R = 0.13
    r_fn = solve(indenter=lambda x, y: (x**2 + y**2) / (2 * R), force=0.5, mu=0.0, radius=R,
                 tol=1e-2, grid_points=128, domain_length=0.03)
    r_sp = solve(indenter="sphere", force=0.5, mu=0.0, radius=R, tol=1e-2, grid_points=128,
                 domain_length=0.03)
    np.testing.assert_allclose(r_fn.pressure, r_sp.pressure, atol=1e-8 * r_sp.pressure.max())


@pytest.mark.parametrize("indenter, extra", [
    ("sphere", []), ("cylinder", ["--length", "0.008"]),
    ("paraboloid", ["--radius-x", "0.2", "--radius-y", "0.1"])])
def test_cli_each_indenter_json_maps_profiles(tmp_path, capsys, indenter, extra):
    maps = tmp_path / "m.npz"
    prof = tmp_path / "p.csv"
    argv = ["solve", "--indenter", indenter, "--force", "0.5", "--mu", "1", "--tol", "2e-2",
            "--json", "--sensor", "--maps", str(maps), "--profiles", str(prof), *extra]
    assert main(argv) == 0
    s = json.loads(capsys.readouterr().out)
    assert set(JSON_KEYS_3D) <= set(s)
    assert s["indenter"] == indenter and s["force_N"] == 0.5
    with np.load(maps) as z:
        assert set(MAP_KEYS) | {"S_zz_Pa", "S_xz_Pa", "S_yz_Pa"} <= set(z.files)
        nx, ny = s["grid_points"]
        assert z["pressure_Pa"].shape == (nx, ny) and z["x_m"].shape == (nx,)
    data = np.genfromtxt(prof, delimiter=",", names=True)
    assert data["x_m"].size == s["grid_points"][0]


@pytest.mark.parametrize("argv", [
    ["solve", "--indenter", "sphere", "--load", "100"],
    ["solve", "--force", "1"],
    ["solve", "--indenter", "sphere", "--force", "-1"],
    ["solve", "--indenter", "sphere", "--method", "abel"],
    ["solve", "--indenter", "sphere", "--length", "0.01"],
    ["solve", "--indenter", "sphere", "--model", "auto"],
    ["solve", "--maps", "x.npz"],
    ["solve", "--indenter", "sphere", "--thickness", "1e308"],
    ["solve", "--indenter", "sphere", "--force", "1e-300"],
    ["solve", "--indenter", "sphere", "--young", "1e-300"],
    ["solve", "--indenter", "sphere", "--domain-length", "0.01"],
    ["solve", "--indenter", "sphere", "--grid-points", "31"],
    ["solve", "--indenter", "sphere", "--maps", "/proc/x.npz"],
    ["solve", "--indenter", "sphere", "--plot", "p.png", "--maps", "p.png"],
])
def test_cli_bad_3d_input_exits_2(argv, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert list(tmp_path.iterdir()) == []


def test_surface_displacements_close_the_gap_and_shear_the_layer(sliding):
    """Inside the contact the surface follows the indenter: u_z = f - d; the mean tangential
    displacement is the uniform shear of the bonded layer, h * mean(q) (h = 1 here)."""
    r = sliding
    g = Grid(r.pressure.shape, r.domain_length, (r.x[0], r.y[0]))
    f = Sphere(0.0, r.scene.P).height(g)
    inside = r.pressure > 0
    np.testing.assert_allclose(r.surface_uz[inside], (f - r.indentation)[inside],
                               atol=1e-7 * r.indentation)
    assert r.surface_ux.mean() == pytest.approx(r.scene.mu * r.pressure.mean(), rel=1e-10)
    assert abs(r.surface_uy.mean()) < 1e-12


@pytest.mark.parametrize("a_over_h", [0.3, 1.0, 3.0])
def test_frictionless_sphere_against_the_axisymmetric_reference(a_over_h):
    """The independent check in 3D (as Abel in 2D): the Fredholm formulation of the sphere on
    the layer (reference.axisym_layer, ~1e-12) against the FFT solver at tol 1e-2: contact
    radius, indentation, peak pressure and the base sigma_zz(r) within tol, and each error
    below the solver's own estimate."""
    from spectral_contact.reference.axisym_layer import sphere_on_layer

    tol = 1e-2
    P = 32.0 * a_over_h**3 / 3.0  # Hertz radius a_over_h
    ref = sphere_on_layer(P)
    base = Scene3D(mu=0.0)
    F = P * base.stress_unit * base.length_unit**2
    r = solve_fft3d(base.with_(force=F), tol=tol)
    errors = [abs(r.contact_radius / ref.a - 1), abs(r.indentation / ref.indentation - 1),
              abs(r.measures["pmax"] / ref.max_pressure - 1)]
    assert max(errors) <= tol
    assert max(errors) <= r.error_estimate
    j = int(np.argmin(np.abs(r.y)))
    sel = np.abs(r.x) < ref.a + 4.0
    bz = ref.base_sigma_zz(np.abs(r.x[sel]))
    assert np.max(np.abs(r.base_sigma_zz[sel, j] - bz)) <= tol * np.max(np.abs(bz))
