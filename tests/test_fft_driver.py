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
