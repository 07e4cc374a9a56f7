"""numerics.blas_threads: the inverses and the line FFT solver hold OpenBLAS at one thread and give
the count back."""
import numpy as np
import pytest

from spectral_contact.numerics import blas_threads
from spectral_contact.numerics.blas_threads import blas_thread_counts, single_blas_thread


def _libs_or_skip():
    if not blas_threads._libraries():
        pytest.skip("no OpenBLAS library found in this process (another BLAS or no /proc)")


def test_block_sets_one_thread_and_restores_nested():
    _libs_or_skip()
    libs = blas_threads._libraries()
    before = blas_thread_counts()
    libs[0][1](2)  # as a 2-core machine's default
    try:
        with single_blas_thread():
            assert blas_thread_counts() == [1] * len(libs)
            with single_blas_thread():
                assert blas_thread_counts() == [1] * len(libs)
            assert blas_thread_counts() == [1] * len(libs)  # the outer block still holds it
        assert blas_thread_counts()[0] == 2
    finally:
        for (_, s), n in zip(libs, before):
            s(n)
    assert blas_thread_counts() == before


def _runs_under_one_thread(monkeypatch, module, checker, call):
    """``call()`` (refused by its input check ``module.checker``) sees one BLAS thread in every
    library, and the count found before (2 here) is given back."""
    _libs_or_skip()
    from spectral_contact.errors import InputError

    libs = blas_threads._libraries()
    before = blas_thread_counts()
    libs[0][1](2)
    seen = []
    real = getattr(module, checker)

    def spy(*a, **k):
        seen.append(blas_thread_counts())
        return real(*a, **k)

    monkeypatch.setattr(module, checker, spy)
    try:
        with pytest.raises(InputError):
            call()
        assert seen == [[1] * len(libs)]
        assert blas_thread_counts()[0] == 2
    finally:
        for (_, s), n in zip(libs, before):
            s(n)


def test_inverse_runs_under_one_thread_and_restores_on_error(monkeypatch):
    from spectral_contact.instruments import inverse

    x = np.linspace(-0.01, 0.01, 4)  # too few samples: refused inside the block
    _runs_under_one_thread(monkeypatch, inverse, "_prepare",
                           lambda: inverse.invert_line(x, x, x, prior="contact"))


def test_maps_inverse_runs_under_one_thread(monkeypatch):
    from spectral_contact.instruments import inverse_maps

    x = np.linspace(-0.01, 0.01, 3)  # too few points: refused inside the block
    z = np.zeros((3, 3))
    _runs_under_one_thread(monkeypatch, inverse_maps, "_check_maps",
                           lambda: inverse_maps.invert_maps(x, x, z, z, z))


def test_line_fft_solve_runs_under_one_thread():
    """The line FFT solver (its GMRES bases' products, a viscoelastic solve's centroid dot) holds
    one BLAS thread: with OpenBLAS's default of one per core, a viscoelastic line took 2-4
    times the CPU of the same solve on one thread (studies/README, viscoelastic, cost)."""
    _libs_or_skip()
    from spectral_contact.physics.scene import Scene
    from spectral_contact.solvers.fft import solve_fft

    libs = blas_threads._libraries()
    before = blas_thread_counts()
    libs[0][1](2)
    seen = []
    try:
        scene = Scene(load=200.0, mu=2.0, speed=1e-2, prony=((2.2e6, 0.01),), young=2.2e6,
                      thickness=0.002, radius=0.13)
        r = solve_fft(scene, tol=1e-3, progress=lambda line: seen.append(blas_thread_counts()))
        assert r.half_width > 0 and seen
        assert all(c == [1] * len(libs) for c in seen)
        assert blas_thread_counts()[0] == 2
    finally:
        for (_, s), n in zip(libs, before):
            s(n)


def test_line_fft_solve_holds_numpys_build_without_importing_scipy_linalg():
    """In a process that has not imported scipy.linalg, the line solve holds numpy's OpenBLAS
    at one thread without importing scipy.linalg for its build (~60 ms once per process: the
    CLI's single solves), and gives the count back."""
    import subprocess
    import sys

    code = """
import sys
from spectral_contact.numerics import blas_threads
from spectral_contact.physics.scene import Scene
from spectral_contact.solvers.fft import solve_fft
libs = blas_threads._openblas_libraries()  # the builds loaded now (numpy's)
if not libs or "scipy.linalg" in sys.modules:
    print("skip"); raise SystemExit
libs[0][1](2)
seen = []
solve_fft(Scene(load=200.0, mu=2.0), tol=1e-3,
          progress=lambda line: seen.append(int(libs[0][0]())))
print(seen and all(n == 1 for n in seen), int(libs[0][0]()), "scipy.linalg" in sys.modules)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split()
    if out == ["skip"]:
        pytest.skip("no OpenBLAS library found, or scipy.linalg imported at startup")
    assert out == ["True", "2", "False"]
