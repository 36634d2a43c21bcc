"""Figures of block, hertz and slab as JSON, for comparing dolfinx versions (the Debian 13 and wheel lanes).

    python scripts/lane_figures.py figures.json
    python scripts/lane_figures.py --compare a.json b.json   # exit 1 if any differs by > 1e-8 relative
"""
import json
import logging
import sys

CASES = [("block", "penalty", {"K": 1e5}, 0, "nodal"),
         ("block", "cross", {"K_hat": 1e5, "F_hat": 100.0}, 10, "gauss"),
         ("hertz", "cross", {"K_hat": 1e6}, 30, "nodal"),
         ("hertz", "auglag", {"K": 1e6}, 30, "nodal"),
         ("hertz", "lagrange", {}, 0, "nodal"),
         ("slab", "coulomb", {"mu": 1.0}, 0, "nodal")]


def compute() -> dict:
    logging.getLogger().setLevel(logging.WARNING)
    from fenics_contact.app.scenes import build
    from fenics_contact.methods import make_law
    from fenics_contact.solver import Solver

    out = {}
    for scene, method, params, aug, quad in CASES:
        setup = build(scene, law=make_law(method, **params), quadrature=quad)
        Solver(setup.problem, augment_max=aug, augment_tol=1e-10, quiet=True).run(setup.loads)
        out[f"{scene}/{method}/{quad}"] = _scalars(setup.figures())
    return out


def _scalars(figures: dict) -> dict:
    """Numbers, and numbers of nested dicts as ``outer.inner``; not lists, not round-off sized equilibrium errors."""
    flat = {}
    for k, v in figures.items():
        if isinstance(v, dict):
            flat.update({f"{k}.{i}": w for i, w in v.items() if isinstance(w, (int, float))})
        elif isinstance(v, (int, float)) and not k.endswith("equilibrium_error"):
            flat[k] = v
    return flat


def compare(a: dict, b: dict, rtol: float = 1e-8, floor: float = 1e-6) -> list[str]:
    bad = []
    for case, figs in a.items():
        for k, v in figs.items():
            w = b[case][k]
            if abs(v - w) > rtol * max(abs(v), abs(w), floor):
                bad.append(f"{case} {k}: {v!r} vs {w!r}")
    return bad


if __name__ == "__main__":
    if sys.argv[1:2] == ["--compare"]:
        a, b = (json.load(open(p)) for p in sys.argv[2:4])
        bad = compare(a, b)
        n = sum(len(f) for f in a.values())
        print("\n".join(bad) or f"lane figures: {n} figures agree to 1e-8 relative")
        sys.exit(1 if bad else 0)
    figures = compute()
    from mpi4py import MPI

    if MPI.COMM_WORLD.rank == 0:
        with open(sys.argv[1], "w") as fh:  # a file: some MPI stacks print to stdout
            json.dump(figures, fh, indent=1)
