"""The condensed method's reuse of earlier load modes (:class:`~fenics_contact.condensed.loadmodes.LoadModes`):
a load that is a combination of earlier loads gets the same combination of their load modes and contact forces;
any other load is solved."""
import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from fenics_contact.condensed.loadmodes import LoadModes


def _vec(values):
    """A distributed vector holding this rank's slice of ``values`` (the same global vector on every rank)."""
    comm = MPI.COMM_WORLD
    n = len(values)
    v = PETSc.Vec().createMPI((PETSc.DECIDE, n), comm=comm)
    lo, hi = v.getOwnershipRange()
    v.array[:] = values[lo:hi]
    return v


def test_combinations_are_reused_and_other_loads_are_not():
    """Two loads (a Dirichlet press, then a traction): 0.3 of the first plus 2 of the second gives the load mode
    and contact force of that combination to round-off; a load out of their span, or with another Dirichlet
    value, gives None; after clear, nothing is reused."""
    rng = np.random.default_rng(1)
    n = 40
    f1, f2 = np.zeros(n), rng.standard_normal(n)  # the press: no force, a Dirichlet value
    g1, g2 = np.array([-1e-3, -1e-3]), np.zeros(2)  # Dirichlet values (this rank's; the same on every rank)
    x1, x2 = rng.standard_normal(n), rng.standard_normal(n)
    r1, r2 = rng.standard_normal(5), rng.standard_normal(5)
    modes = LoadModes(MPI.COMM_WORLD)
    modes.add(_vec(f1), g1, _vec(x1), r1)
    modes.add(_vec(f2), g2, _vec(x2), r2)
    x = _vec(np.zeros(n))
    r = modes.combine(_vec(0.3 * f1 + 2.0 * f2), 0.3 * g1 + 2.0 * g2, x)
    assert r is not None and np.allclose(r, 0.3 * r1 + 2.0 * r2, rtol=1e-13, atol=1e-15)
    lo, hi = x.getOwnershipRange()
    assert np.allclose(x.array, (0.3 * x1 + 2.0 * x2)[lo:hi], rtol=1e-13, atol=1e-15)
    other = f2 + 1e-6 * rng.standard_normal(n)  # a load out of the span
    assert modes.combine(_vec(other), g2, x) is None
    assert modes.combine(_vec(2.0 * f2), np.array([-1e-3, -2e-3]), x) is None  # Dirichlet values out of the span
    assert modes.reused == 1
    modes.clear()
    assert modes.combine(_vec(f2), g2, x) is None
