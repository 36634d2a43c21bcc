# %% [markdown]
# # A block pressed on a rigid plane
#
# An elastic block, 1 wide and 2 high, stands on a rigid plane. Its top is moved down by `d`; its left side
# is a roller (`u_x = 0`), so the block is free to expand sideways. The contact is frictionless, the
# material linear elastic in plane strain. The exact state is uniform: the contact pressure is
# `p = E / (1 - nu^2) d / H` everywhere. With an exact method (Lagrange multipliers) the discrete solution
# is this state to round-off.
#
# The mesh is a gmsh model built with the gmsh API; its regions have **names** (physical groups), and
# `fc.read_gmsh(None, ...)` reads the model of this process.

# %%
import gmsh
import numpy as np
from dolfinx import fem
from mpi4py import MPI

import fenics_contact as fc

E, nu, W, H, d = 1000.0, 0.3, 1.0, 2.0, 0.02

gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("block")
block = gmsh.model.occ.addRectangle(0.0, 0.0, 0.0, W, H)
gmsh.model.occ.synchronize()
sides = {}
for _, curve in gmsh.model.getBoundary([(2, block)], oriented=False):
    x, y, _ = gmsh.model.occ.getCenterOfMass(1, abs(curve))
    name = "base" if np.isclose(y, 0) else "top" if np.isclose(y, H) else "left" if np.isclose(x, 0) else "right"
    sides[name] = abs(curve)
gmsh.model.addPhysicalGroup(2, [block], 1)
gmsh.model.setPhysicalName(2, 1, "block")
for tag, name in enumerate(("base", "top", "left"), start=2):
    gmsh.model.addPhysicalGroup(1, [sides[name]], tag)
    gmsh.model.setPhysicalName(1, tag, name)
gmsh.option.setNumber("Mesh.CharacteristicLengthMax", 0.25)
gmsh.model.mesh.generate(2)
mesh, cells, facets = fc.read_gmsh(None, MPI.COMM_WORLD, gdim=2)
gmsh.finalize()
if MPI.COMM_WORLD.rank == 0:
    print(facets)  # the named regions

# %% [markdown]
# The method: `lagrange` makes the contact pressure an unknown, so `fc.unknown` returns a mixed function
# (displacement, pressure) and `V` is its displacement space. The load parameter `load` runs from 0 to 1:
# Dirichlet values are `amplitude * t`.

# %%
law = fc.make_law("lagrange")
u, V = fc.unknown(mesh, 1, law)
load = fem.Constant(mesh, 0.0)
contact = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load)
problem = fc.ContactProblem(u, fc.LinearElastic(E, nu), load,
                            [fc.Dirichlet.on_facets(V, facets, "top", 1, -d),  # u_y = -d t on the top
                             fc.Dirichlet.on_facets(V, facets, "left", 0)],    # u_x = 0 on the left
                            [contact])
fc.Solver(problem, quiet=True).run([0.5, 1.0])

# %% [markdown]
# `total_force()` is the resultant of the plane's pressure on the block (per unit thickness);
# `surface_values()` the reference position, gap (> 0: penetration) and pressure (> 0: compression) at the
# contact points. Both are the same on every rank.

# %%
exact = E / (1 - nu**2) * d / H
x, gap, pressure = contact.surface_values()
force = contact.total_force()
if MPI.COMM_WORLD.rank == 0:
    print(f"pressure {pressure.min():.10f} .. {pressure.max():.10f}, exact {exact:.10f}; force {force}")
assert np.allclose(pressure, exact, rtol=1e-8)
assert np.isclose(force[1], exact * W, rtol=1e-8) and abs(gap).max() < 1e-10
