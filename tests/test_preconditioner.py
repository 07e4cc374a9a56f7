"""The cut-off preconditioner of FourierOperator (numerics/operators.py)."""
import numpy as np
import pytest


@pytest.mark.parametrize("shape,lengths,mu", [((256,), (20.0,), 2.0), ((64, 48), (12.0, 9.0), 1.0),
                                              ((33,), (5.0,), 0.0)])
def test_preconditioner_equals_the_symbol_evaluated_mode_by_mode(shape, lengths, mu):
    """The clipped part is evaluated with |k| = k_c as one broadcast value: same numbers as
    evaluating the film's symbol at every mode with |k| replaced by k_c."""
    from spectral_contact.numerics.grid import Grid
    from spectral_contact.numerics.operators import FourierOperator
    from spectral_contact.physics.film import Film

    grid = Grid(shape, lengths)
    op = FourierOperator(grid, Film().compliance_symbol(mu, (1.0, 0.0)[: len(shape)]))
    k_cut = 0.37 * float(grid.kmag.max())
    P = op.preconditioner(k_cut)
    full = np.broadcast_to(op._evaluate(np.full(grid.kshape, k_cut)), grid.kshape)
    ref = np.where(grid.kmag < k_cut, 1.0 / full, 1.0 / np.where(op.symbol == 0, 1.0, op.symbol))
    assert np.array_equal(P, ref)
    assert op.preconditioner(k_cut) is P  # cached per cut-off


@pytest.mark.parametrize("speed,mu,constant", [(10.0, 2.0, 0.0), (0.3, -1.0, 0.0), (3e-3, 0.0, 0.0),
                                               (1.0, 0.5, 0.2 + 0.1j)])
def test_line_preconditioner_of_a_viscoelastic_film_equals_the_mode_by_mode_one(speed, mu, constant):
    """On a line the clipped symbol is one value, evaluated once (``_line_preconditioner``):
    bitwise the mode-by-mode evaluation, for the complex symbol of a viscoelastic film (a long
    tail at 10 h/s, a short one at 0.3, a stiff edge layer at 3e-3) and with a constant added."""
    from spectral_contact.numerics.grid import Grid
    from spectral_contact.numerics.operators import FourierOperator
    from spectral_contact.physics.viscoelastic import ViscoelasticFilm

    film = ViscoelasticFilm(relaxed_young=2.2e6, prony=((2.2e6, 0.01), (1.1e6, 0.5)), speed=speed)
    for n, L in ((256, 20.0), (1024, 13.7), (66, 3.0)):
        grid = Grid.centered(n, L, 0.3)
        op = FourierOperator(grid, film.compliance_symbol(mu, (1.0, 0.0))) + constant
        for k_cut in (1e-9, 0.37 * float(grid.kmag.max()), float(grid.kmag[5]), 1e9):
            P = op.preconditioner(k_cut)
            full = np.broadcast_to(op._evaluate(np.full(grid.kshape, k_cut)), grid.kshape)
            ref = np.where(grid.kmag < k_cut, 1.0 / full,
                           1.0 / np.where(op.symbol == 0, 1.0, op.symbol))
            assert np.array_equal(P, ref)
