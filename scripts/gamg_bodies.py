"""GAMG on the 3D two-body case (sphere octant on a deformable block): near-nullspace and GAMG options.

    python scripts/gamg_bodies.py --level 0 --modes union bodies [--threshold 0.01] [--options k=v ...]

For each near-nullspace (``union``: the 6 rigid-body modes of the whole mesh, what the solver sets; ``bodies``:
6 per body, each zero on the other body, 12 in all) solves the scene (penalty, its K, GMRES + GAMG) and prints
Newton iterations, Krylov iterations per Newton iteration and the time per Newton iteration
((assembly + linear solves) / Newton iterations, as ``demos/scaling.py``).
"""
from __future__ import annotations

import argparse
import time

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

import fenics_contact as fc
from fenics_contact.cli import LINEAR_SOLVERS
from fenics_contact.scenes import sphere
from fenics_contact.solver import Solver


def body_modes(V, body_of_dof: np.ndarray) -> PETSc.NullSpace:
    """6 rigid-body modes per body (translations, rotations about the body's centroid), each zero off its body,
    orthonormalised (Gram-Schmidt on the owned entries)."""
    x = V.tabulate_dof_coordinates()[:, :3]
    n_local = V.dofmap.index_map.size_local
    comm = V.mesh.comm
    vecs = []
    for b in np.unique(np.concatenate(comm.allgather(np.unique(body_of_dof[:n_local])))):
        on = body_of_dof == b
        centre = np.array(comm.allreduce(x[:n_local][on[:n_local]].sum(axis=0))) / comm.allreduce(
            int(on[:n_local].sum()))
        xc = x - centre
        for k in range(6):
            a = np.zeros((len(x), 3))
            if k < 3:
                a[:, k] = 1.0
            else:
                i, j = [(0, 1), (1, 2), (2, 0)][k - 3]
                a[:, i], a[:, j] = -xc[:, j], xc[:, i]
            a[~on] = 0.0
            v = PETSc.Vec().createWithArray(a[:n_local].ravel().copy(), comm=comm)
            for w in vecs:
                v.axpy(-v.dot(w), w)
            v.normalize()
            vecs.append(v)
    return PETSc.NullSpace().create(vectors=vecs, comm=comm)


def bodies(V) -> np.ndarray:
    """Body of each local dof (block index): 1 for the block's cells (centroid below z = 0), 0 for the ball's."""
    mesh = V.mesh
    tdim = mesh.topology.dim
    n_cells = mesh.topology.index_map(tdim).size_local + mesh.topology.index_map(tdim).num_ghosts
    x = mesh.geometry.x
    geo = mesh.geometry.dofmap
    body = np.full(V.dofmap.index_map.size_local + V.dofmap.index_map.num_ghosts, -1)
    for c in range(n_cells):
        z = x[geo.links(c), 2].mean()
        body[V.dofmap.cell_dofs(c)] = 1 if z < 0 else 0
    return body


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--level", type=int, default=0)
    p.add_argument("--size", type=float, default=None, help="mesh-size factor instead of the level's")
    p.add_argument("--modes", nargs="+", default=["union", "bodies"], choices=["union", "bodies"])
    p.add_argument("--options", nargs="*", default=[], help="extra PETSc options of the solver, key=value")
    args = p.parse_args()
    comm = MPI.COMM_WORLD
    extra = dict(o.split("=", 1) for o in args.options)
    for modes in args.modes:
        setup = fc.build("sphere", law=fc.make_law("penalty", K=sphere.DEFAULT_K), plate="meshed", level=args.level,
                         size=args.size)
        solver = Solver(setup.problem, quiet=True, options={**LINEAR_SOLVERS["iterative"], **extra})
        if modes == "bodies":
            V = setup.problem.u.function_space
            solver.A.setNearNullSpace(body_modes(V, bodies(V)))
        t0 = time.perf_counter()
        solver.run(setup.loads)
        wall = comm.allreduce(time.perf_counter() - t0, op=MPI.MAX)
        s = solver.summary()
        split = s["time_split"]
        newton = s["newton_iterations_spent"]
        if comm.rank == 0:
            print(f"{modes:6s} {extra} level {args.level} ({setup.dofs} dofs, {comm.size} ranks): Newton {newton}"
                  f" (converged {s['converged']}), Krylov per Newton {s['linear_iterations'] / newton:.1f}, time per"
                  f" Newton {(split['assembly_s'] + split['linear_solve_s']) / newton:.3f} s, wall {wall:.1f} s, "
                  f"p0 {setup.figures().get('p0', float('nan')):.6g}")


if __name__ == "__main__":
    main()
