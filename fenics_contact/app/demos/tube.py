"""Thick-walled rubber tube crushed between two plates until its inner wall folds onto itself (self-contact).

    python demos/tube.py                       # the full tube (self-contact), then the half tube as its reference
    python demos/tube.py --half                # the half tube on its symmetry plane only
    mpirun -n 2 python demos/tube.py --n-theta 32 --n-r 2

Plane strain, neo-Hookean rubber (E = 1000, nu = 0.4999), Taylor-Hood P2-P1 mixed; inner radius 1, wall 1; the
rigid frictionless plates approach each other by 0.6 of the outer diameter (fenics_contact.app.scenes.tube). The
hole flattens into a slit; its walls fold at the slit's ends and meet in the middle, and the contact zones grow. The
full tube's inner wall is one surface in contact with itself; the half tube has the symmetry plane as a rigid
obstacle for it. The check: by symmetry the two are the same problem, so at every step past first contact the
full model's plate force and fold force equal the half model's (difference at most 1e-3 of the plate force), and
the fold's two sides overlap by no more than the law's penetration at a pressure E (E / K). Writes to --out:
summary.json and tube.xdmf (full), half/ (the half's), tube_figures.csv, tube_forces.png (force against
approach), tube_fold.png (the fold's pressure profile), tube_deformed.png and tube_half_deformed.png.
"""
import math
from pathlib import Path

import numpy as np

from fenics_contact.app import cli
from fenics_contact.app.checks import mirror_agreement
from fenics_contact.app.mirror_demo import solve_full_and_half, write_models
from fenics_contact.app.scenes import add_scene_options, scene_arguments, tube

TOLERANCE = 1e-3  # the two models' forces, per the plate force (both solve the same problem to round-off)


def _h(args) -> float:
    return 2 * math.pi * args.r_in / args.n_theta


def main(argv=None) -> dict:
    # 1. Options: the tube, the mesh, the model (full or half), the stepping.
    p = cli.parser(__doc__.splitlines()[0], default_K=lambda a: tube.DEFAULT_K * a.E / _h(a))
    p.set_defaults(method="penalty", quadrature="simpson")
    p.add_argument("--half", action="store_true",
                   help="the half tube on its symmetry plane (a rigid obstacle) only; default: the full tube with "
                        "self-contact, then the half as its reference")
    p.add_argument("--steps", type=cli.COUNT, default=tube.STEPS,
                   help=f"equal load steps up to t = {tube.FINE_FROM:g} (of the whole --approach)")
    p.add_argument("--fold-steps", type=cli.COUNT, default=tube.FOLD_STEPS,
                   help=f"equal load steps from t = {tube.FINE_FROM:g} to 1")
    p.add_argument("--n-theta", type=cli.count(8), default=tube.N_THETA,
                   help="cells around the whole circle (a multiple of 4)")
    p.add_argument("--n-r", type=cli.COUNT, default=tube.N_R, help="cells through the wall")
    scene = add_scene_options(p, tube.build)  # --r-in, --thickness, --E, --nu, --approach
    args = cli.parse(p, argv)
    if args.n_theta % 4:
        p.error(f"argument --n-theta: must be a multiple of 4, got {args.n_theta}")
    if args.method not in tube.METHODS:
        p.error(f"argument --method: the tube takes {', '.join(tube.METHODS)} (self-contact on the mixed P2 "
                f"model), got {args.method!r}")
    out = Path(args.out or "results/tube")
    cli.refuse_unsupported(args, kind="rigid" if args.half else "self", dim=2, degree=2, model="neohookean-mixed")

    # 2. Each model: build, solve, keep the figures and the fold's profile of every step (the half first: the
    # reference of the full model's check).
    def profile(setup) -> list:
        _, x, pressure = setup.profile()
        return [x[:, 0].tolist(), pressure.tolist()]

    scene_kwargs = dict(steps=args.steps, fold_steps=args.fold_steps, n_theta=args.n_theta, n_r=args.n_r,
                        **scene_arguments(args, scene))
    summary, profiles, setup, history, reference, half_setup = solve_full_and_half(
        args, "tube", scene_kwargs, {"steps": args.steps, "fold_steps": args.fold_steps}, out, profile, agreement)

    # 3. Tables and pictures (rank 0; every figure is already reduced over ranks).
    if write_models(args, out, "tube", "tube", "approach", setup, history, reference, half_setup) \
            and not args.no_pictures:
        _pictures(history, reference, profiles, out)
    return summary


def agreement(full: list, half: list, overlap_tolerance: float) -> dict:
    """The check: the largest difference of the plate force and the fold force between the full and the half model
    over the steps past first contact, per the step's plate force; failed too if the fold's sides overlap by more
    than ``overlap_tolerance`` (a length, E / K)."""
    return mirror_agreement(full, half, TOLERANCE, overlap_tolerance, force="plate_force", contact="fold_force",
                            overlap="fold_overlap", at="approach",
                            models="the full tube (self-contact) against the half tube on its symmetry plane",
                            closed="the fold never closed: increase --approach")


def _pictures(history: list, reference: list | None, profiles: dict, out: Path) -> None:
    from fenics_contact.app.plotting import plot_curves

    def series(rows, key):
        return np.array([r["approach"] for r in rows]), np.array([r[key] for r in rows])

    curves = []
    for rows, name, style in ((history, "full (self-contact)", "-o"), (reference, "half (symmetry plane)", "--s")):
        if rows:
            curves += [(*series(rows, "plate_force"), f"plate force, {name}", style),
                       (*series(rows, "fold_force"), f"fold force, {name}", style)]
    plot_curves(curves, out / "tube_forces.png", xlabel="approach of the plates (length)",
                ylabel="force per unit length", title="tube crushed between two plates")
    loaded = [(float(t), x, p) for t, (x, p) in profiles.items() if max(p, default=0.0) > 0]
    shown = {min(loaded, key=lambda row: abs(row[0] - target))[0]: None for target in (0.7, 0.8, 0.9, 1.0)} \
        if loaded else {}
    fold = [(np.array(x), np.array(p), f"t = {t:g}", "-o") for t, x, p in loaded if t in shown]
    if fold:
        plot_curves(fold, out / "tube_fold.png", xlabel="x (current)", ylabel="contact pressure (nominal)",
                    title="the fold's pressure on the upper inner wall")


if __name__ == "__main__":
    cli.main(main)
