# %% [markdown]
# # Two deformable blocks, non-matching meshes, two materials: the patch test
#
# A soft block (`E = 1000`) stands on a stiff one (`E = 3000`), both 1 wide and 1 high, meshed
# independently: the nodes of the interface do not match. The bottom is a roller (`u_y = 0`), the left
# sides too (`u_x = 0`), and the top is moved down by `d`. With `nu = 0` both blocks keep their width, so
# the exact state is uniform in each block: the blocks are two springs in series and the contact pressure
# is `p = d / (H_lower / E_lower + H_upper / E_upper)` everywhere on the interface. A method passes the
# *patch test* if it reproduces this uniform pressure on non-matching meshes: segment-to-segment
# integration does.
#
# One body's surface is the **slave** (its points are projected on the other, the **master**):
# `fc.two_body_surfaces(u, facets, slave, master, ...)`. Take the finer mesh, or the softer body, as the
# slave; `passes="two"` makes each surface slave once.

# %%
import gmsh
import numpy as np
from dolfinx import fem
from mpi4py import MPI

import fenics_contact as fc

E_lower, E_upper, nu, d = 3000.0, 1000.0, 0.0, 0.01

gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("blocks")
occ = gmsh.model.occ
lower, upper = occ.addRectangle(0, 0, 0, 1, 1), occ.addRectangle(0, 1, 0, 1, 1)  # not fused: two bodies
occ.synchronize()
groups = {"lower": (2, [lower]), "upper": (2, [upper])}
for body, size in ((lower, 1 / 5), (upper, 1 / 7)):  # different sizes: non-matching interface nodes
    gmsh.model.mesh.setSize(gmsh.model.getBoundary([(2, body)], recursive=True), size)
    for _, curve in gmsh.model.getBoundary([(2, body)], oriented=False):
        x, y, _ = occ.getCenterOfMass(1, abs(curve))
        name = {0.0: "bottom", 1.0: "lower_top" if body == lower else "upper_bottom", 2.0: "top"}.get(round(y, 6))
        if np.isclose(x, 0.0):
            name = "left"
        if name is not None:
            groups.setdefault(name, (1, []))[1].append(abs(curve))
for tag, (name, (dim, entities)) in enumerate(groups.items(), start=1):
    gmsh.model.addPhysicalGroup(dim, entities, tag)
    gmsh.model.setPhysicalName(dim, tag, name)
gmsh.model.mesh.generate(2)
mesh, cells, facets = fc.read_gmsh(None, MPI.COMM_WORLD, gdim=2)
gmsh.finalize()

# %% [markdown]
# One material per body: `fc.Materials` maps each cell region to its material. The upper block (finer
# mesh, softer) is the slave. The augmented Lagrangian with segment-to-segment integration; each surface
# needs its own law, hence a factory.

# %%
u, V = fc.unknown(mesh, 1, fc.make_law("auglag", K=1e5))
load = fem.Constant(mesh, 0.0)
materials = fc.Materials(mesh, cells, {"lower": fc.LinearElastic(E_lower, nu), "upper": fc.LinearElastic(E_upper, nu)})
contacts = fc.two_body_surfaces(u, facets, facets["upper_bottom"], facets["lower_top"],
                                lambda: fc.make_law("auglag", K=1e5), load, quadrature="segment")
problem = fc.ContactProblem(u, materials, load,
                            [fc.Dirichlet.on_facets(V, facets, "top", 1, -d),
                             fc.Dirichlet.on_facets(V, facets, "bottom", 1),
                             fc.Dirichlet.on_facets(V, facets, "left", 0)], contacts)
fc.Solver(problem, quiet=True, augment_max=20, augment_tol=1e-12).run([1.0])

# %% [markdown]
# `total_force()` is the force of the master (lower block) on the slave (upper block): upwards. The figures
# are reduced over the ranks: the same under `mpirun -n 2` as serially.

# %%
exact = d / (1 / E_lower + 1 / E_upper)
x, gap, pressure = contacts[0].surface_values()
deviation = np.abs(pressure / exact - 1).max()
force = contacts[0].total_force()
if MPI.COMM_WORLD.rank == 0:
    print(f"pressure {pressure.mean():.8f} (exact {exact:.8f}), max deviation {deviation:.1e}, force {force}")
assert deviation < 1e-8 and np.isclose(force[1], exact, rtol=1e-8)  # upwards on the upper block
