"""The one FFT driver (solvers.fft_driver, issue 20): lines and surfaces through the same level
loop, the same progress lines and the same common info."""
from spectral_contact import Scene
from spectral_contact.physics.scene import Scene3D
from spectral_contact.solvers.fft_method import FFTMethod


def test_progress_and_common_info_for_lines_and_surfaces():
    """progress= reaches both drivers (it reached surfaces only), one line per level in the same
    words, and both results carry the driver's common info (the friction law's iterations
    too: surfaces did not report them)."""
    law = dict(friction_law="power", friction_exponent=0.1, friction_pref=1e5)
    for scene in (Scene(**law), Scene3D(force=1.0, **law)):
        lines = []
        r = FFTMethod(tol=1e-2).solve(scene, "exact", progress=lines.append)
        levels = [t for t in lines if "exact model, fft: level" in t]
        assert len(levels) == len(r.info["levels"]) >= 2, lines
        assert levels[0].split(": grid ")[0].endswith("level 1")
        for key in ("levels", "residuals", "domain_margin", "final_level_active_set_iterations",
                    "final_level_krylov_iterations", "friction_law_iterations"):
            assert key in r.info, (scene.dimension, key)
        assert r.info["friction_law_iterations"] > 0


def test_solve_scene_dispatches_on_dimension():
    """``solve_scene`` picks the line or surface rules by ``scene.dimension`` (not by the
    class): a surface refuses model auto, methods other than fft and hertz at poisson < 0.5; a
    line takes model auto and hertz.  No solve beyond closed forms (fast)."""
    import pytest

    from spectral_contact.errors import InputError
    from spectral_contact.solvers.registry import _SOLVE, solve_scene

    assert set(_SOLVE) == {Scene().dimension, Scene3D(force=1.0).dimension} == {"line", "surface"}
    sphere = Scene3D(force=0.2)
    for model, method, poisson in (("auto", "fft", 0.5), ("exact", "abel", 0.5),
                                   ("hertz", "fft", 0.4)):
        with pytest.raises(InputError):
            solve_scene(sphere.with_(poisson=poisson), model, method, 1e-3)
    assert solve_scene(sphere, "hertz", "fft", 1e-3).dimension == "surface"
    assert solve_scene(Scene(), "hertz", "fft", 1e-3).dimension == "line"
