"""One declaration of the options (physics/options.py): the command line, the sweep and the
Python API take every option with the same default and the same bounds, and their messages name
it as the caller typed it (issue 20; issue 24's "Messages")."""
from __future__ import annotations

import argparse
import dataclasses
import functools
import inspect
import math

import pytest

from spectral_contact.api import METHODS, MODELS, make_scene, solve
from spectral_contact.cli.main import build_parser, main
from spectral_contact.cli.scene_options import scene_from_args
from spectral_contact.errors import InputError
from spectral_contact.physics.options import OPTIONS, option
from spectral_contact.physics.scene import Scene, Scene3D

try:  # the sweep's table needs no pandas until it runs
    from spectral_contact import sweep as _sweep
except ImportError:  # pragma: no cover
    _sweep = None

SCENE_OPTIONS = [o for o in OPTIONS if o.scenes != "solve"]
SOLVE_OPTIONS = [o for o in OPTIONS if o.scenes == "solve"]

# what an option needs beside it to be taken at all (its indenter, its law)
CONTEXT = {
    "force": {"indenter": "sphere"}, "length": {"indenter": "cylinder"},
    "radius_x": {"indenter": "paraboloid"}, "radius_y": {"indenter": "paraboloid"},
    "friction_exponent": {"friction_law": "power", "friction_pref": 1e4},
    "friction_pref": {"friction_law": "power"},
    "shear_strength": {"friction_law": "linear"}, "shear_slope": {"friction_law": "linear"},
    "interface_pressure": {"interface_law": "exponential", "interface_length": 1e-6},
    "interface_length": {"interface_law": "exponential", "interface_pressure": 1e5},
    "interface_law": {"interface_pressure": 1e5, "interface_length": 1e-6},
    "friction_law": {"shear_slope": 0.5},  # the linear law needs its parameters (issue 24)
}


@functools.lru_cache(maxsize=1)
def _solve_parser() -> argparse.ArgumentParser:
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices["solve"]


def _argv(values: dict) -> list[str]:
    return ["solve"] + [f"{option(k).flag}={v}" for k, v in values.items()]


def _cases(o):
    """(value, accepted) pairs at and beyond the option's bounds."""
    if o.kind is str:
        return [(o.choices[-1], True), ("bogus", False)]
    out = [(math.inf, False), (math.nan, False)]
    if o.lo is not None:
        out += [(o.lo, not o.lo_open), (o.lo - max(1e-6 * abs(o.lo), 1e-9), False)]
    if o.hi is not None:
        out += [(o.hi, not o.hi_open), (o.hi + max(1e-6 * abs(o.hi), 1e-9), False)]
    return out


def _python(values):
    try:
        make_scene(**values)
        return None
    except InputError as exc:
        return str(exc)


def _command_line(values, capsys):
    """None if the command line builds the scene, else its one-line error (exit 2)."""
    try:
        args = _solve_parser().parse_args(_argv(values)[1:])
    except InputError:
        args = None
    if args is not None:
        try:
            scene_from_args(args)
            return None
        except InputError:
            pass
    capsys.readouterr()
    assert main(_argv(values) + ["--json"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    return err


def _sweep_row(values):
    try:
        (params,) = _sweep.scenes({k: [v] if not isinstance(v, str) else v
                                   for k, v in values.items()})
        _sweep.scene_of(params)
        return None
    except InputError as exc:
        return str(exc)


@pytest.mark.parametrize("o", [o for o in SCENE_OPTIONS if o.lo is not None or o.hi is not None
                               or o.choices is not None or o.kind is float],
                         ids=lambda o: o.name)
def test_bounds_agree_between_the_command_line_the_sweep_and_python(o, capsys):
    """Every scene option, at and beyond its bounds: the Python API, the command line and (for
    the sweep's options) the sweep accept and refuse the same values; Python's message names
    ``name``, the command line's ``--name``."""
    for value, accepted in _cases(o):
        values = {**CONTEXT.get(o.name, {}), o.name: value}
        if o.name == "extent":
            values["indenter"] = lambda x: x * x
        py = _python(values)
        assert (py is None) == accepted, (o.name, value, py)
        if not accepted:
            assert o.name in py and o.flag not in py, py
        if o.cli:
            cli = _command_line(values, capsys)
            assert (cli is None) == accepted, (o.name, value, cli)
            if not accepted and o.choices is None:
                assert o.flag in cli, cli
        if o.sweep and _sweep is not None and not (o.kind is str and not accepted):
            assert (_sweep_row(values) is None) == accepted, (o.name, value)


def test_defaults_agree_between_the_command_line_the_sweep_and_python():
    """With nothing given, the three entry points build the same scenes (line and sphere),
    whose fields are the declared defaults; the solve options' defaults agree too."""
    parser = _solve_parser()
    for argv, scene in (([], Scene()), (["--indenter", "sphere"], Scene3D())):
        assert scene_from_args(parser.parse_args(argv)) == scene
        assert make_scene(**({"indenter": "sphere"} if argv else {})) == scene
        if _sweep is not None:
            (params,) = _sweep.scenes({"indenter": "sphere"} if argv else {})
            assert _sweep.scene_of(params) == scene
    fields = {f.name: f.default for cls in (Scene, Scene3D) for f in dataclasses.fields(cls)
              if f.name != "indenter"}
    for o in SCENE_OPTIONS:
        if o.name != "indenter":
            assert fields[o.name] == o.default, o.name
    args = parser.parse_args([])
    sig = inspect.signature(solve).parameters
    for o in SOLVE_OPTIONS:
        assert getattr(args, o.name) == o.default == sig[o.name].default, o.name
        if _sweep is not None:
            assert _sweep.OPTIONS[o.name][1] == o.default, o.name


def test_every_option_is_on_each_entry_point_with_its_choices_and_help():
    """Each declared option is a flag of ``solve`` (where ``cli``) whose help says its default,
    a field of the scene that takes it, a keyword of ``solve``; the sweep's options are the
    declared ``sweep`` ones in the declared order; the model and method choices are the
    registry's."""
    actions = {a.dest: a for a in _solve_parser()._actions}
    for o in OPTIONS:
        if o.cli:
            a = actions[o.name]
            assert a.option_strings == [o.flag] and o.default_said() in a.help, o.name
            if o.choices is not None and o.scenes != "solve":
                assert tuple(a.choices) == o.choices, o.name
    assert tuple(actions["model"].choices) == MODELS == option("model").choices
    assert set(actions["method"].choices) == set(METHODS) == set(option("method").choices)
    scene_fields = {f.name for cls in (Scene, Scene3D) for f in dataclasses.fields(cls)}
    assert {o.name for o in SCENE_OPTIONS} <= scene_fields
    assert {o.name for o in SOLVE_OPTIONS} <= set(inspect.signature(solve).parameters)
    if _sweep is not None:
        assert list(_sweep.OPTIONS) == [o.name for o in OPTIONS if o.sweep]
        for o in OPTIONS:
            if o.sweep:
                kind, _, unit, text = _sweep.OPTIONS[o.name]
                assert kind is o.kind and text == o.cli_help(), o.name
                assert unit == (o.choices if o.kind is str else o.unit), o.name


# --- issue 24, "Messages" -----------------------------------------------------------------------

@pytest.mark.parametrize("argv, flag", [
    (["--poisson", "0.7"], "--poisson"),
    (["--friction-law", "power", "--friction-pref", "1e4", "--friction-exponent", "2"],
     "--friction-exponent"),
    (["--interface-law", "exponential", "--interface-pressure", "1e5"], "--interface-length"),
    (["--interface-pressure", "1e5"], "--interface-pressure"),
    (["--indenter", "cylinder", "--length", "0"], "--length"),
    (["--indenter", "sphere", "--force=-1"], "--force"),
    (["--indenter", "paraboloid", "--radius-x", "0"], "--radius-x"),
    (["--indenter", "sphere", "--mu", "2e3"], "--mu"),
    (["--indenter", "sphere", "--radius-y", "0.1"], "--radius-y"),
])
def test_the_command_line_names_the_option_as_typed(argv, flag, capsys):
    assert main(["solve", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and flag in err
    bare = flag[2:].replace("-", "_")
    rest = f" {err} ".replace(flag, "--")
    for after in (" (", " must", " applies", " is ", " = ", " and "):  # not the Python name
        assert f" {bare}{after}" not in rest, err


def test_surfaces_take_the_line_bounds():
    """|mu| <= 1e3 for a sphere too (any finite value was accepted before)."""
    with pytest.raises(InputError, match=r"mu .*\[-1000, 1000\]"):
        Scene3D(mu=2e3)
    with pytest.raises(InputError, match=r"mu .*\[-1000, 1000\]"):
        Scene(mu=2e3)


def test_grid_points_range_says_two_to_the_22(capsys):
    assert main(["solve", "--grid-points", "99999999999999999999"]) == 2
    err = capsys.readouterr().err
    assert "--grid-points" in err and "4194304" in err and "4611686018427387904" not in err


def test_calibrate_on_a_fine_scan_blames_the_scan_not_a_negative_thickness(tmp_path, capsys):
    r = [i * 1e-7 for i in range(12000)]  # r_max 1.2 mm in 0.1 um steps: > 4096 cells at any h
    (tmp_path / "u.csv").write_text("r_m,U_zz_mV\n" + "\n".join(
        f"{x:.17g},{math.exp(-(x / 3e-4) ** 2):.17g}" for x in r) + "\n")
    assert main(["calibrate", "--measured", str(tmp_path / "u.csv"), "--punch-load", "1",
                 "--punch-radius", "1e-4"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "<= -" not in err and "step" in err and "u.csv" in err


@pytest.mark.skipif(_sweep is None, reason="the sweep's module")
def test_a_sweep_row_mixing_a_sphere_and_load_says_so_in_the_options_words():
    row = _sweep.solve_row({"indenter": "sphere", "load": 100.0})
    assert row["status"] == "input_error"
    msg = row["message"]
    assert "load" in msg and "force" in msg and "height" not in msg and "extent" not in msg


def test_sweep_help_says_each_default_once(capsys):
    with pytest.raises(SystemExit):
        main(["sweep", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "(default 200)" in text and "(default 200) [N/m] (default" not in text
    assert text.count("(default chosen from --tol)") <= 2  # grid points and period only


def test_solve_refuses_a_scene_and_its_parameters_together():
    """``solve(Scene(load=100), load=200)`` used 200 silently: the ambiguity is refused."""
    with pytest.raises(InputError, match="load"):
        solve(Scene(load=100.0), load=200.0)
    with pytest.raises(InputError, match="force"):
        solve(Scene3D(), force=2.0)


def test_the_json_keys_are_the_declared_ones():
    """Each option's declared JSON key is a key of the results' records (lines, surfaces, the
    laws' parameters); the laws' and the exponential interface's keys come from the table."""
    from spectral_contact.physics.friction import FrictionLaw
    from spectral_contact.result import JSON_KEYS, JSON_KEYS_3D

    keys = set(JSON_KEYS) | set(JSON_KEYS_3D) | {"length_m", "radius_x_m", "radius_y_m",
                                                  "interface_pressure_Pa", "interface_length_m"}
    keys |= set(FrictionLaw("power", exponent=0.1, pref=1e4).describe())
    keys |= set(FrictionLaw("linear", shear_strength=1.0, shear_slope=1.0).describe())
    keys |= set(solve(load=200.0, mu=0.5, speed=0.05, prony="2.2e6,0.01", tol=1e-2).to_dict())
    assert {o.json for o in OPTIONS if o.json} <= keys
    assert FrictionLaw("power", exponent=0.1, pref=1e4).describe() == {
        "friction_law": "power", "friction_exponent": 0.1, "friction_pref_Pa": 1e4}
    assert FrictionLaw("linear", shear_strength=5.0, shear_slope=2.0).describe() == {
        "friction_law": "linear", "shear_strength_Pa": 5.0, "shear_slope": 2.0}


# --- issue 20/23: the viscoelastic film's options are rows of the one declaration -----------------

@pytest.mark.parametrize("prony, accepted", [
    ("2.2e6,0.01", True), ("1e6,0.1,5e5,1", True), ("1,2,3", False), ("1e6,-0.1", False),
    ("1e6,x", False), ("1e6,0", False), ("inf,1", False)])
def test_prony_is_parsed_in_one_place_for_every_entry_point(prony, accepted, capsys):
    """--prony: the command line, the sweep and Python accept and refuse the same series, each
    message naming the option as typed (``--prony`` / ``prony``)."""
    values = {"speed": 0.05, "mu": 0.5, "prony": prony}
    py = _python(values)
    assert (py is None) == accepted, py
    cli = _command_line(values, capsys)
    assert (cli is None) == accepted, cli
    sw = _sweep_row(values) if _sweep is not None else py
    assert (sw is None) == accepted, sw
    if not accepted:
        assert "--prony" in cli and "prony" in py and "--prony" not in py, (cli, py)
        assert "prony" in sw
    else:
        (params,) = _sweep.scenes(values)
        assert _sweep.scene_of(params) == make_scene(**values) == scene_from_args(
            _solve_parser().parse_args(_argv(values)[1:]))


def test_prony_needs_speed_on_the_command_line_and_in_a_sweep(capsys):
    assert main(["solve", "--prony", "2.2e6,0.01"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--prony needs --speed" in err
    if _sweep is not None:
        with pytest.raises(InputError, match="prony needs speed"):
            _sweep.scenes({"prony": "2.2e6,0.01"})
    # Python keeps the field's default (speed 0: the relaxed film)
    assert make_scene(prony="2.2e6,0.01").speed == 0.0


def test_speed_and_prony_are_solve_options_only():
    """onset does not take a viscoelastic film: its parser has no --speed/--prony."""
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    onset = {a.dest for a in sub.choices["onset"]._actions}
    assert "speed" not in onset and "prony" not in onset and "mu" in onset


def test_a_sweep_over_speed_runs(tmp_path, capsys):
    """--speed is a sweep option: the rows are the solves of their scenes (the deformation
    friction grows from the relaxed film's with the speed), several Prony series by ';'."""
    pytest.importorskip("pandas")
    assert main(["sweep", "--speed", "0,0.02,0.05", "--prony", "2.2e6,0.01;1e6,0.1", "--mu",
                 "0.5", "--tol", "1e-2", "--serial", "--out", str(tmp_path / "o")]) == 0
    import pandas as pd

    df = pd.read_csv(tmp_path / "o" / "summary.csv")
    assert len(df) == 6 and set(df["status"]) == {"ok"}
    first = df[df["prony_terms"] == "[[2200000.0;0.01]]"]
    assert first["speed_m_per_s"].tolist() == [0.0, 0.02, 0.05]
    r = solve(load=200.0, mu=0.5, speed=0.05, prony="2.2e6,0.01", tol=1e-2).summary()
    assert first["deformation_friction"].iloc[2] == pytest.approx(r["deformation_friction"], rel=1e-12)
    assert first["deformation_friction"].iloc[0] < first["deformation_friction"].iloc[2]


def test_the_thickness_is_checked_once_from_calibrate_to_the_base_stresses(monkeypatch, tmp_path,
                                                                          capsys):
    """issue 20: calibrate --punch-load checked --thickness three times (the command, the
    axisymmetric instrument, the film); the film is made once, where the value enters."""
    from pathlib import Path

    from spectral_contact.instruments import axisym
    from spectral_contact.physics.options import Option

    seen = []
    real = Option.check

    def counting(self, value):
        if self.name == "thickness":
            seen.append(value)
        return real(self, value)

    monkeypatch.setattr(Option, "check", counting)
    axisym.flat_punch_base_stresses(1.0, 250e-6, 2e-3, dx_m=1e-4, r_max_m=4e-3)
    assert seen == [2e-3]  # Python: at the instrument's entry
    seen.clear()
    scan = Path(__file__).resolve().parents[1] / "examples" / "synthetic_punch_scan.csv"
    assert main(["calibrate", "--measured", str(scan), "--punch-load", "0.1", "--n-boot", "0",
                 "--out", str(tmp_path / "g.csv")]) == 0, capsys.readouterr().err
    assert seen == [option("thickness").default]  # the command line: once, by the command
    assert main(["calibrate", "--measured", str(scan), "--punch-load", "0.1",
                 "--thickness=-1"]) == 2
    assert "--thickness" in capsys.readouterr().err


def test_a_film_kind_is_named_by_its_module_and_the_scene_only():
    """issue 20: a new film kind touches at most 3 package files -- its module, its option rows
    and ``Scene.core_film`` (the one place that builds the solvers' film).  The viscoelastic
    film: the solvers and every other module use it through ``Film``'s interface only."""
    import ast
    from pathlib import Path

    root = Path(__file__).resolve().parents[1] / "spectral_contact"
    naming = set()
    for path in root.rglob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Name) and node.id == "ViscoelasticFilm" or \
                    isinstance(node, ast.alias) and node.name == "ViscoelasticFilm":
                naming.add(path.relative_to(root).as_posix())
    # (its own module may name it or not: the class is defined there)
    assert naming - {"physics/viscoelastic.py"} == {"physics/scene.py"}, naming
    opts = [o.name for o in OPTIONS if o.name in ("speed", "prony")]
    assert opts == ["speed", "prony"]  # its parameters: rows of the one declaration
    scene = make_scene(speed=0.05, prony="2.2e6,0.01", mu=0.5)
    film = scene.core_film()
    assert film.moving and film.thickness == 1.0 and film.speed == 0.05 / scene.thickness
    assert not make_scene(speed=0.0, prony="2.2e6,0.01").core_film().moving  # relaxed: Film
