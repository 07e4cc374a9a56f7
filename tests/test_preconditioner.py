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
