"""Load paths of tractions and body forces: a block on a rigid plane loaded by a traction and by its weight,
each along its own path, against the closed form at every load step; and the refusal of a malformed path."""
import re

import numpy as np
import pytest
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.contact import displacement

E, NU, W, H = 1000.0, 0.3, 1.0, 2.0


def _block(tractions_of, n=(2, 4), top=None):
    """A W x H block on the rigid plane y = 0, left side a roller, exact contact (Lagrange multipliers); the
    tractions from ``tractions_of(mesh, ds)``; ``top``: the top's ``(u_y amplitude, path)`` if prescribed.
    Returns (contact, problem, V, facets)."""
    mesh = dmesh.create_rectangle(MPI.COMM_WORLD, [np.zeros(2), np.array([W, H])], list(n))
    facets = fc.tag_boundary(mesh, [("base", lambda x: np.isclose(x[1], 0.0)),
                                     ("top", lambda x: np.isclose(x[1], H)),
                                     ("left", lambda x: np.isclose(x[0], 0.0))])
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets.meshtags)
    law = fc.make_law("lagrange")
    u, V = fc.unknown(mesh, 1, law)
    load = fem.Constant(mesh, 0.0)
    contact = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load)
    dirichlet = [fc.Dirichlet.on_facets(V, facets, "left", 0)]
    if top is not None:
        dirichlet.append(fc.Dirichlet.on_facets(V, facets, "top", 1, top[0], path=top[1]))
    problem = fc.ContactProblem(u, fc.LinearElastic(E, NU), load, dirichlet, [contact],
                                tractions=tractions_of(mesh, ds, facets))
    return contact, problem, V, facets


def _top_shortening(problem, facets):
    """-(mean u_y over the top face), over all ranks."""
    mesh = problem.u.function_space.mesh
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets.meshtags)
    local = fem.assemble_scalar(fem.form(-displacement(problem.u)[1] * ds(facets["top"])))
    return mesh.comm.allreduce(local, op=MPI.SUM) / W


def test_traction_follows_its_path_at_every_step():
    """A pressure q f(t) on the top, f piecewise linear (up to 1, over to 1.6, back down to 0.4): the plane
    carries p = q f(t) uniformly and the block shortens by (1 - nu^2) q f(t) H / E (plane strain, free to expand
    sideways) at every load step, including the unloading ones."""
    q = 5.0
    path = ([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 1.6, 0.4])
    contact, problem, _, facets = _block(
        lambda mesh, ds, facets: [(fem.Constant(mesh, np.array([0.0, -q])), ds(facets["top"]), path)])
    seen = []

    def check(t):
        f = float(np.interp(t, *path))
        _, gap, pressure = contact.surface_values()
        np.testing.assert_allclose(pressure, q * f, rtol=1e-9)
        assert np.isclose(contact.total_force()[1], q * f * W, rtol=1e-9)
        assert abs(gap).max() < 1e-10 * q * H / E
        assert np.isclose(_top_shortening(problem, facets), (1 - NU**2) * q * f * H / E, rtol=1e-9)
        seen.append(f)

    fc.Solver(problem, quiet=True, on_step=check).run([0.5, 1.0, 1.5, 2.0, 2.5, 3.0])
    assert seen == [0.5, 1.0, 1.3, 1.6, 1.0, 0.4]


def test_prescribed_displacement_follows_its_path_at_every_step():
    """The top moved down by d f(t) (``Dirichlet.on_facets`` with a path: up, over, back down): the plane carries
    p = E d f(t) / ((1 - nu^2) H) uniformly at every load step (plane strain, free to expand sideways)."""
    d = 0.01
    path = ([0.0, 1.0, 2.0], [0.0, 1.5, 0.5])
    contact, problem, _, _ = _block(lambda mesh, ds, facets: [], top=(-d, path))
    seen = []

    def check(t):
        f = float(np.interp(t, *path))
        p = E * d * f / ((1 - NU**2) * H)
        np.testing.assert_allclose(contact.surface_values()[2], p, rtol=1e-9)
        assert np.isclose(contact.total_force()[1], p * W, rtol=1e-9)
        seen.append(f)

    fc.Solver(problem, quiet=True, on_step=check).run([1.0, 1.5, 2.0])
    assert seen == [1.5, 1.0, 0.5]


def test_body_force_and_traction_on_separate_paths():
    """The block's weight b per volume along f_b(t) = t^2 (a callable) and a pressure q along f_q = t (no path):
    the plane's resultant is q W t + b W H t^2 at every step (equilibrium)."""
    q, b = 5.0, 2.0
    contact, problem, _, facets = _block(
        lambda mesh, ds, facets: [(fem.Constant(mesh, np.array([0.0, -q])), ds(facets["top"])),
                                  (fem.Constant(mesh, np.array([0.0, -b])), ufl.dx(domain=mesh), lambda t: t**2)])
    forces = []
    fc.Solver(problem, quiet=True, on_step=lambda t: forces.append((t, contact.total_force()[1]))).run([0.5, 1.0, 2.0])
    for t, force in forces:
        assert np.isclose(force, q * W * t + b * W * H * t**2, rtol=1e-9), (t, force)
    assert [t for t, _ in forces] == [0.5, 1.0, 2.0]


@pytest.mark.parametrize("entry, message", [
    (("v", "ds", ([0.0, 1.0], [0.0])), "tractions[0] path must be"),
    (("v", "ds", ([1.0, 0.0], [0.0, 1.0])), "tractions[0] path must be"),
    (("v",), "tractions[0] must be (vector, measure)"),
])
def test_malformed_traction_path_is_refused_in_one_line(entry, message):
    mesh = dmesh.create_unit_square(MPI.COMM_WORLD, 1, 1)
    u, _ = fc.unknown(mesh, 1, fc.make_law("penalty", K=1.0))
    with pytest.raises(ValueError, match=re.escape(message)) as err:
        fc.ContactProblem(u, fc.LinearElastic(E, NU), fem.Constant(mesh, 0.0), tractions=[entry])
    assert "\n" not in str(err.value)
