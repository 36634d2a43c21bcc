"""Self-contact (a surface against itself, :func:`fenics_contact.self_contact_surfaces`): the pairing leaves out a
point's own neighbourhood, a surface made of two facing sides is the two-pass two-body contact of those sides, and
what the capability grid refuses is refused before any assembly."""
import numpy as np
import pytest
import ufl
from dolfinx import fem
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.app.meshes import stacked_blocks
from fenics_contact.app.meshes.tube import tube_section

E, NU = 1000.0, 0.3


@pytest.mark.parametrize("wall", ["inner", "outer"])
def test_a_smooth_wall_at_rest_pairs_with_nothing(wall):
    """A tube's concave (inner) or convex (outer) wall at rest: no point is paired (its neighbours face its way,
    the rest is beyond the search radius), so no contact force without a fold."""
    mesh, _, ft = tube_section(MPI.COMM_WORLD, 1.0, 0.5, 32, 2)
    law = fc.make_law("penalty", K=1e5)
    u, V = fc.unknown(mesh, 1, law)
    (surface,) = fc.self_contact_surfaces(u, ft, wall, lambda: law, fem.Constant(mesh, 0.0))
    assert MPI.COMM_WORLD.allreduce(int(np.sum(surface.pairs.facet >= 0))) == 0


@pytest.mark.parametrize("quadrature", ["nodal", "gauss"])
def test_a_block_with_sharp_corners_at_rest_pairs_with_nothing(quadrature):
    """A square's whole boundary as one self-contact surface, at rest: a point near a corner lies behind the
    other face's facets (turned by 90 degrees, so not facing its way), the first ones and those a few facets
    round the corner alike, and pairs with none of them (a contact force without a fold); squeezed, likewise. A
    corner node may pair with the other face's first facet, on it: gap 0, no force."""
    from dolfinx import mesh as dmesh

    from fenics_contact.app.meshes.structured import exterior_facets, facet_tags

    msh = dmesh.create_unit_square(MPI.COMM_WORLD, 8, 8, diagonal=dmesh.DiagonalType.crossed)
    facets, _ = exterior_facets(msh)
    ft = facet_tags(msh, facets, np.ones(len(facets), np.int32), {"boundary": 1})
    law = fc.make_law("penalty", K=1e5)
    u, V = fc.unknown(msh, 1, law)
    (surface,) = fc.self_contact_surfaces(u, ft, "boundary", lambda: law, fem.Constant(msh, 0.0),
                                          quadrature=quadrature)

    def largest_gap():  # > 0: penetration
        return MPI.COMM_WORLD.allreduce(float(np.max(surface.pairs.projection["gap"], initial=-np.inf)), op=MPI.MAX)

    assert largest_gap() <= 1e-12
    u.interpolate(lambda x: np.stack([0.05 * x[0], -0.1 * x[1]]))  # squeezed 10 %, bulging 5 %
    surface.update()
    assert largest_gap() <= 1e-12


def _blocks(self_contact: bool, method: str):
    """Two stacked blocks (non-matching meshes), the upper one pressed by a traction on half of its top: the two
    facing sides as one surface against itself, or as the two-pass two-body contact of the two sides."""
    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 1.0, 1.0, (4, 2), (5, 2), 1e-6)
    law = (lambda: fc.make_law("penalty", K=1e5)) if method == "penalty" else (lambda: fc.make_law("nitsche"))
    u, V = fc.unknown(mesh, 1, law())
    load = fem.Constant(mesh, 0.0)
    material = fc.LinearElastic(E, NU)
    if self_contact:
        ft = fc.merge_regions(mesh, ft, "interface", ["upper_bottom", "lower_top"])
        contacts = fc.self_contact_surfaces(u, ft, "interface", law, load, material=material)
    else:
        contacts = fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", law, load, passes="two",
                                        material=material)
    x = ufl.SpatialCoordinate(mesh)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=ft.meshtags, subdomain_id=ft["upper_top"])
    half = ufl.conditional(ufl.lt(x[0], 0.5), 1.0, 0.0)
    dirichlet = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", 1), fc.Dirichlet.on_facets(V, ft, "left", 0)]
    problem = fc.ContactProblem(u, material, load, dirichlet, contacts, [(ufl.as_vector((0.0, -20.0 * half)), ds)])
    fc.Solver(problem, quiet=True).run([0.5, 1.0])
    return u, contacts


@pytest.mark.parametrize("method", ["penalty", "nitsche"])
def test_two_facing_sides_are_the_two_pass_contact_of_the_sides(method):
    """The facing sides of two blocks as one self-contact surface: every point pairs with the other side (the
    own side faces the same way) at weight 1/2, the unbiased two-pass contact of the two sides, to round-off."""
    u_self, _ = _blocks(True, method)
    u_two, _ = _blocks(False, method)
    scale = np.max(np.abs(u_two.x.array))
    assert scale > 0
    assert np.max(np.abs(u_self.x.array - u_two.x.array)) <= 1e-9 * scale


@pytest.mark.parametrize("method, kw, match", [
    ("lagrange", {}, "self-contact"), ("coulomb", {}, "self-contact"), ("vi", {}, "self-contact"),
    ("penalty", {"quadrature": "segment"}, "segment"),
    ("penalty_multiplier", {}, "self-contact"),
])
def test_refused_before_assembly(method, kw, match):
    mesh, _, ft = tube_section(MPI.COMM_WORLD, 1.0, 0.5, 16, 1)
    law = fc.make_law(method, **({"K": 1e5} if method in ("penalty", "penalty_multiplier") else {}))
    u, _ = fc.unknown(mesh, 1, law)
    with pytest.raises(fc.UnsupportedCombination, match=match):
        fc.self_contact_surfaces(u, ft, "inner", lambda: law, fem.Constant(mesh, 0.0), **kw)


def test_friction_is_refused():
    mesh, _, ft = tube_section(MPI.COMM_WORLD, 1.0, 0.5, 16, 1)
    law = fc.Friction(fc.make_law("penalty", K=1e5), mu=0.3, omega_t=1e5)
    u, _ = fc.unknown(mesh, 1, law)
    with pytest.raises(fc.UnsupportedCombination, match="frictionless"):
        fc.self_contact_surfaces(u, ft, "inner", lambda: law, fem.Constant(mesh, 0.0))


def test_self_contact_needs_one_tag():
    mesh, _, ft = tube_section(MPI.COMM_WORLD, 1.0, 0.5, 16, 1)
    law = fc.make_law("penalty", K=1e5)
    u, _ = fc.unknown(mesh, 1, law)
    with pytest.raises(ValueError, match="must be equal"):
        fc.TwoBodySurface(u, ft, "inner", "outer", law, fem.Constant(mesh, 0.0), self_contact=True)
    with pytest.raises(ValueError, match="must differ"):
        fc.TwoBodySurface(u, ft, "inner", "inner", law, fem.Constant(mesh, 0.0))
