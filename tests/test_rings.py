"""Two concentric rings under external pressure: Lamé's interface pressure and radial displacements."""
import numpy as np
import pytest
from mpi4py import MPI

from fenics_contact.laws import LagrangeMultiplier
from fenics_contact.scenes import build, rings
from fenics_contact.solver import Solver


def lame_by_hooke(q, E1, nu1, E2, nu2, plane, a=rings.A, b=rings.B, c=rings.C):
    """Interface pressure and ``u_r(a), u_r(c)`` from the four conditions on the constants ``A_i, B_i`` of
    ``sigma_r = A - B/r^2``, ``sigma_t = A + B/r^2``, with Hooke's law in 3D (plane strain: ``sigma_z =
    nu (sigma_r + sigma_t)``; plane stress: ``sigma_z = 0``) for ``u_r = r eps_t``: independent of the
    scene's ``E' = E/(1-nu^2)`` substitution."""
    def u_coef(r, E, nu):  # u_r = r eps_t as coefficients of (A, B)
        sz = (2 * nu, 0.0) if plane == "strain" else (0.0, 0.0)  # sigma_z = nu * 2A in plane strain
        # eps_t = (sigma_t - nu (sigma_r + sigma_z)) / E
        cA = (1 - nu * (1 + sz[0])) / E
        cB = (1 + nu) / E / r**2
        return np.array([r * cA, r * cB])

    M = np.zeros((4, 4))
    rhs = np.zeros(4)
    M[0, :2] = [1, -1 / a**2]  # sigma_r1(a) = 0
    M[1, 2:] = [1, -1 / c**2]  # sigma_r2(c) = -q
    rhs[1] = -q
    M[2] = [1, -1 / b**2, -1, 1 / b**2]  # sigma_r continuous at b
    M[3, :2], M[3, 2:] = u_coef(b, E1, nu1), -u_coef(b, E2, nu2)  # u_r continuous at b
    A1, B1, A2, B2 = np.linalg.solve(M, rhs)
    return -(A1 - B1 / b**2), u_coef(a, E1, nu1) @ [A1, B1], u_coef(c, E2, nu2) @ [A2, B2]


@pytest.mark.parametrize("plane", rings.PLANES)
@pytest.mark.parametrize("materials", [(1000.0, 0.3, 1000.0, 0.3), (1000.0, 0.3, 3000.0, 0.45),
                                       (2500.0, 0.1, 700.0, 0.35)])
def test_lame_closed_form(plane, materials):
    q = 7.0
    p = rings.lame_pressure(q, *materials, plane)
    ua, uc = rings.lame_displacements(q, *materials, plane)
    assert np.allclose([p, ua, uc], lame_by_hooke(q, *materials, plane), rtol=1e-12)
    if materials[:2] == materials[2:]:  # equal materials: no dependence on nu or on the plane assumption
        a, b, c = rings.A, rings.B, rings.C
        assert np.isclose(p, q * c**2 * (1 - a**2 / b**2) / (c**2 - a**2), rtol=1e-12)
