# %% [markdown]
# # A cylinder on a rigid plane: Hertz
#
# The lower half of a disk of radius `R = 1` (a cylinder in plane strain) is pressed onto a rigid plane by
# moving its diameter down. Hertz's solution for a cylinder on a rigid plane, with `E* = E / (1 - nu^2)`:
# half-width `a = sqrt(4 P R / (pi E*))` and peak pressure `p0 = 2 P / (pi a)`, `P` the force per unit
# thickness. The mesh is fine at the contact point (a gmsh size field) and coarse elsewhere.

# %%
import gmsh
import numpy as np
from dolfinx import fem
from mpi4py import MPI

import fenics_contact as fc

E, nu, R, push = 1000.0, 0.3, 1.0, 0.001

gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("half_disk")
geo = gmsh.model.geo
centre, left, bottom, right = (geo.addPoint(0, R, 0), geo.addPoint(-R, R, 0), geo.addPoint(0, 0, 0),
                               geo.addPoint(R, R, 0))
arcs = [geo.addCircleArc(left, centre, bottom), geo.addCircleArc(bottom, centre, right)]
diameter = geo.addLine(right, left)
disk = geo.addPlaneSurface([geo.addCurveLoop([*arcs, diameter])])
geo.synchronize()
for dim, entities, tag, name in ((2, [disk], 1, "disk"), (1, arcs, 2, "contact"), (1, [diameter], 3, "top")):
    gmsh.model.addPhysicalGroup(dim, entities, tag)
    gmsh.model.setPhysicalName(dim, tag, name)
distance = gmsh.model.mesh.field.add("Distance")
gmsh.model.mesh.field.setNumbers(distance, "PointsList", [bottom])
size = gmsh.model.mesh.field.add("Threshold")
for option, value in (("InField", distance), ("SizeMin", 0.004), ("SizeMax", 0.1), ("DistMin", 0.05),
                      ("DistMax", 0.6)):
    gmsh.model.mesh.field.setNumber(size, option, value)
gmsh.model.mesh.field.setAsBackgroundMesh(size)
for option in ("Mesh.MeshSizeExtendFromBoundary", "Mesh.MeshSizeFromPoints", "Mesh.MeshSizeFromCurvature"):
    gmsh.option.setNumber(option, 0)
gmsh.model.mesh.generate(2)
mesh, cells, facets = fc.read_gmsh(None, MPI.COMM_WORLD, gdim=2)
gmsh.finalize()

# %% [markdown]
# The augmented Lagrangian (`auglag`): a penalty `K` (about `E / h`) plus multiplier updates until the
# constraint changes by less than `augment_tol`; the penetration then vanishes up to that tolerance.

# %%
law = fc.make_law("auglag", K=1e6)
u, V = fc.unknown(mesh, 1, law)
load = fem.Constant(mesh, 0.0)
contact = fc.contact_surface(u, facets, "contact", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load)
problem = fc.ContactProblem(u, fc.LinearElastic(E, nu), load,
                            [fc.Dirichlet.on_facets(V, facets, "top", 1, -push),
                             fc.Dirichlet.on_facets(V, facets, "top", 0)], [contact])
fc.Solver(problem, quiet=True, augment_max=10, augment_tol=1e-10).run([0.5, 1.0])

# %%
P = contact.total_force()[1]
a = np.sqrt(4 * P * R / (np.pi * E / (1 - nu**2)))
p0 = 2 * P / (np.pi * a)
x, gap, pressure = contact.surface_values()
if MPI.COMM_WORLD.rank == 0:
    print(f"P = {P:.5f}, a = {a:.4f}, p0 = {pressure.max():.4f} (Hertz {p0:.4f}), {pressure.max() / p0 - 1:+.2%}")
assert abs(pressure.max() / p0 - 1) < 0.005  # measured +0.01 %
