"""GAMG on the 3D two-body case (sphere octant on a deformable block): near-nullspace and GAMG options.

    python scripts/gamg_bodies.py --level 0 --modes union bodies [--threshold 0.01] [--options k=v ...]

For each near-nullspace (``union``: the 6 rigid-body modes of the whole mesh, what the solver sets; ``bodies``: 6 per
body, each zero on the other body, 12 in all: ``fenics_contact.nullspace``) solves the scene (penalty, its
K, GMRES + GAMG) and prints Newton iterations, Krylov iterations per Newton iteration and the time per Newton iteration
((assembly + linear solves) / Newton iterations, as ``demos/scaling.py``).
"""
from __future__ import annotations

import argparse
import time

from mpi4py import MPI

import fenics_contact as fc
import fenics_contact.app as app
from fenics_contact.app.cli import LINEAR_SOLVERS
from fenics_contact.app.scenes import sphere
from fenics_contact.nullspace import rigid_body_modes
from fenics_contact.solver import Solver


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
        setup = app.build("sphere", law=fc.make_law("penalty", K=sphere.DEFAULT_K), plate="meshed", level=args.level,
                         size=args.size)
        solver = Solver(setup.problem, quiet=True, options={**LINEAR_SOLVERS["iterative"], **extra})
        if modes == "bodies":  # the solver sets the union's modes
            solver.A.setNearNullSpace(rigid_body_modes(setup.problem.u.function_space, per_body=True))
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
