import csv
import math

import pytest

from spectral_contact import Scene, solve


@pytest.fixture(scope="session")
def paper():
    return Scene()


def scene_for(a_over_h_hertz: float, mu: float, base: Scene = Scene()) -> Scene:
    """A scene whose Hertz half-space half-width is a_over_h_hertz film thicknesses."""
    P = 2 * math.pi * a_over_h_hertz**2
    return base.with_(load=P * base.stress_unit * base.length_unit, mu=mu)


@pytest.fixture(scope="session")
def paper_exact(paper):
    return solve(paper, tol=1e-4)


def read_rows(path):
    """The rows of a CSV file as dicts (studies' outputs), after checking that the file opens
    with numpy's and pandas' plain readers (``assert_opens_plainly``)."""
    assert_opens_plainly(path)
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def assert_opens_plainly(path):
    """The CSV opens with numpy.genfromtxt(path, delimiter=',', names=True) and (if pandas is
    installed) pandas.read_csv(path), no other argument: one header row, no comment lines, the
    same columns and rows both ways."""
    import numpy as np

    with open(path, encoding="utf-8") as fh:
        lines = fh.read().splitlines()
    header = lines[0].split(",")
    assert not lines[0].startswith("#") and all(not ln.startswith("#") for ln in lines)
    rows = [ln for ln in lines[1:] if ln.strip()]
    a = np.genfromtxt(path, delimiter=",", names=True)
    assert a.dtype.names is not None and len(a.dtype.names) == len(header)
    assert a.size == len(rows)
    try:
        import pandas as pd
    except ImportError:
        return
    df = pd.read_csv(path)
    assert list(df.columns) == header and len(df) == len(rows)
