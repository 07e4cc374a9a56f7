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
    """The rows of a CSV file as dicts (studies' outputs)."""
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))
