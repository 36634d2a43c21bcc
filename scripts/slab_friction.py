"""Slab (Renaud & Feng 2003): penalty-type friction (normal compliance m_n = 1 with Coulomb, penalty c_n,
tangential penalty omega_t) against the exact condensed Signorini-Coulomb method, over mu and the penalties.

    python scripts/slab_friction.py [--out results/slab_friction] [--mu 0.4 0.8 1.0 1.3 1.4 1.5]
    mpirun -n 2 python scripts/slab_friction.py --penalties 1e6

Prints one row per (mu, c_n = omega_t): u_x(A) and its relative difference to the exact method, the zone
lengths and the largest zone-boundary shift (in elements), equilibrium errors, Newton iterations; then the
augmented variant (Uzawa on both multipliers: augmented Lagrangian K = 1e5, lam0 = 1, omega_t = E/h = 1e4,
up to 60 augmentations to 1e-9). Writes slab_friction.csv / .json into --out. Line search bt for the
penalty rows (the default l2 cycles when omega_t >> E/h), the default for the augmented ones.
"""
import argparse
import json
import logging
from pathlib import Path

import numpy as np
from mpi4py import MPI

from fenics_contact.app.scenes import build, slab
from fenics_contact.friction import Friction
from fenics_contact.laws import AugmentedLagrangian, ExactCoulomb, NormalCompliance
from fenics_contact.solver import ConvergenceError, Solver

OPTIONS = {"snes_linesearch_type": "bt", "snes_max_it": 200, "snes_rtol": 1e-10}


def solve(law, comm=MPI.COMM_WORLD, augment=0):
    setup = build("slab", law=law, comm=comm)
    solver = Solver(setup.problem, quiet=True, options=None if augment else OPTIONS, augment_max=augment,
                    augment_tol=1e-9)
    try:
        solver.run(setup.loads)
    except ConvergenceError as exc:
        return None, str(exc).split(":")[-2].strip(), solver
    return setup.figures(), "", solver


def boundary_shift(a: dict, b: dict) -> float:
    """Largest shift of a zone boundary in elements (inf if the zone patterns differ)."""
    if a["zone_pattern"] != b["zone_pattern"]:
        return float("inf")
    h = slab.WIDTH / slab.NX
    return max([abs(x - y) / h for x, y in zip(a["zone_boundaries"], b["zone_boundaries"])], default=0.0)


def main() -> None:
    logging.getLogger("UFL").setLevel(logging.ERROR)
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--mu", type=float, nargs="+", default=[0.4, 0.8, 1.0, 1.3, 1.4, 1.5])
    p.add_argument("--penalties", type=float, nargs="+", default=[1e4, 1e5, 1e6, 1e7])
    p.add_argument("--out", default="results/slab_friction")
    args = p.parse_args()
    comm = MPI.COMM_WORLD
    rows = []
    for mu in args.mu:
        exact, err, s = solve(ExactCoulomb(mu))
        if comm.rank == 0:
            print(f"mu {mu:4.2f} exact: " + (f"ux_A {exact['ux_A']:.7e} zones {exact['zones']} pattern "
                                              f"{exact['zone_pattern']}" if exact else f"FAILED ({err})"), flush=True)
        for k in [*args.penalties, "augmented"]:
            if k == "augmented":
                f, err, s = solve(Friction(AugmentedLagrangian(1e5, lam0=1.0), mu=mu, omega_t=1e4), augment=60)
            else:
                f, err, s = solve(Friction(NormalCompliance(k, 1.0), mu=mu, omega_t=k))
            row = {"mu": mu, "c_n": k, "omega_t": 1e4 if k == "augmented" else k, "converged": f is not None,
                   "error": err, "newton_iterations": s.newton_spent,  # failed attempts included
                   "augmentations": sum(r.augmentations for r in s.records if r.converged)}
            if f is not None:
                row.update(ux_A=f["ux_A"], uy_A=f["uy_A"], **f["zones"], pattern=f["zone_pattern"],
                           boundaries=f["zone_boundaries"], normal_equilibrium=f["normal_equilibrium_error"],
                           tangential_equilibrium=f["tangential_equilibrium_error"])
                if exact is not None:
                    d = abs(f["ux_A"] - exact["ux_A"]) / abs(exact["ux_A"])
                    row.update(ux_A_exact=exact["ux_A"], ux_A_rel_diff=d,
                               boundary_shift_elements=boundary_shift(f, exact))
            rows.append(row)
            if comm.rank == 0:
                label = "augmented (K 1e5, omega_t 1e4)" if k == "augmented" else f"c_n = omega_t = {k:.0e}"
                print(f"   {label}: " + (
                    "ux_A {ux_A:.7e} rel.diff {d:.2e}  zones sep {separated:.3f} slide {sliding:.3f} stick "
                    "{sticking:.3f}  boundary shift {b:.2f} el.  equilibrium {normal_equilibrium:.1e} "
                    "{tangential_equilibrium:.1e}  newton {newton_iterations} aug {augmentations}".format(
                        d=row.get("ux_A_rel_diff", np.nan), b=row.get("boundary_shift_elements", np.nan), **row)
                    if row["converged"] else f"FAILED ({err}), newton {row['newton_iterations']}"), flush=True)
    if comm.rank == 0:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "slab_friction.json").write_text(json.dumps({"ranks": comm.size, "rows": rows}, indent=1, default=str))
        keys = ["mu", "c_n", "omega_t", "converged", "ux_A", "ux_A_exact", "ux_A_rel_diff", "separated", "sliding",
                "sticking", "boundary_shift_elements", "normal_equilibrium", "tangential_equilibrium",
                "newton_iterations", "augmentations"]
        lines = [",".join(keys)] + [",".join(str(r.get(k, "")) for k in keys) for r in rows]
        (out / "slab_friction.csv").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
