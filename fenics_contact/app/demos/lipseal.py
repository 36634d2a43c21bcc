"""Lip seal (a U-cup) squeezed between the rod and the groove bottom until its lips close the slot between them.

    python demos/lipseal.py                    # the full seal (self-contact), then the half seal as its reference
    python demos/lipseal.py --half             # the half seal on its symmetry plane only
    mpirun -n 2 python demos/lipseal.py --nx 6 --ny-heel 4 --ny-lip 12

Plane strain, neo-Hookean rubber (E = 1000, nu = 0.4999), Taylor-Hood P2-P1 mixed; a heel 4 wide and 2 long, two
lips 4 long whose tips stand 0.6 out past the heel on each side, a V-shaped slot between them 0.6 wide at the tips
(fenics_contact.app.scenes.lipseal). The rod and the groove bottom (rigid, frictionless) squeeze the seal by 20 % of
its free radial span: the lips bend in, their tips meet, the slot closes toward its root and the lips press on each
other over their whole length. The full seal's slot is one surface in contact with itself; the half seal has the
symmetry plane as a rigid obstacle for its lip. The check: by symmetry the two are the same problem, so at every
step past first contact the full model's plate force and slot force equal the half model's (difference at most
1e-3 of the plate force), and the lips overlap by no more than the law's penetration at a pressure E (E / K).
Writes to --out: summary.json and lipseal.xdmf (full), half/ (the half's), lipseal_figures.csv,
lipseal_forces.png (force against squeeze), lipseal_slot.png (the slot's pressure profile), lipseal_deformed.png
and lipseal_half_deformed.png.
"""
import math
from pathlib import Path

import numpy as np

from fenics_contact.app import cli
from fenics_contact.app.checks import mirror_agreement
from fenics_contact.app.mirror_demo import solve_full_and_half, write_models
from fenics_contact.app.scenes import add_scene_options, lipseal, scene_arguments

TOLERANCE = 1e-3  # the two models' forces, per the plate force (both solve the same problem to round-off)


def _h(args) -> float:
    return math.hypot(args.lip, 0.5 * args.slot) / args.ny_lip


def main(argv=None) -> dict:
    # 1. Options: the seal, the mesh, the model (full or half), the stepping.
    p = cli.parser(__doc__.splitlines()[0], default_K=lambda a: lipseal.DEFAULT_K * a.E / _h(a))
    p.set_defaults(method="penalty", quadrature="simpson")
    p.add_argument("--half", action="store_true",
                   help="the half seal on its symmetry plane (a rigid obstacle) only; default: the full seal with "
                        "self-contact, then the half as its reference")
    p.add_argument("--steps", type=cli.COUNT, default=lipseal.STEPS, help="equal load steps up to the whole --squeeze")
    p.add_argument("--nx", type=cli.COUNT, default=lipseal.NX, help="cells across each half of the seal")
    p.add_argument("--ny-heel", type=cli.COUNT, default=lipseal.NY_HEEL, help="cells along the heel")
    p.add_argument("--ny-lip", type=cli.COUNT, default=lipseal.NY_LIP, help="cells along a lip")
    scene = add_scene_options(p, lipseal.build)  # --width, --heel, --lip, --flare, --slot, --E, --nu, --squeeze
    args = cli.parse(p, argv)
    if args.method not in lipseal.METHODS:
        p.error(f"argument --method: the lip seal takes {', '.join(lipseal.METHODS)} (self-contact on the mixed P2 "
                f"model), got {args.method!r}")
    if not args.slot < args.width + 2 * args.flare:
        p.error(f"argument --slot: must be narrower than the lips' span at the tips (--width + 2 --flare = "
                f"{args.width + 2 * args.flare:g}), got {args.slot:g}")
    out = Path(args.out or "results/lipseal")
    cli.refuse_unsupported(args, kind="rigid" if args.half else "self", dim=2, degree=2, model="neohookean-mixed")

    # 2. Each model: build, solve, keep the figures and the slot's profile of every step (the half first: the
    # reference of the full model's check).
    def profile(setup) -> list:
        y, _, pressure = setup.profile()
        return [y.tolist(), pressure.tolist()]

    scene_kwargs = dict(steps=args.steps, nx=args.nx, ny_heel=args.ny_heel, ny_lip=args.ny_lip,
                        **scene_arguments(args, scene))
    summary, profiles, setup, history, reference, half_setup = solve_full_and_half(
        args, "lipseal", scene_kwargs, {"steps": args.steps}, out, profile, agreement)

    # 3. Tables and pictures (rank 0; every figure is already reduced over ranks).
    if write_models(args, out, "lipseal", "lip seal", "squeeze", setup, history, reference, half_setup) \
            and not args.no_pictures:
        _pictures(history, reference, profiles, out)
    return summary


def agreement(full: list, half: list, overlap_tolerance: float) -> dict:
    """The check: the largest difference of the plate force and the slot force between the full and the half model
    over the steps past first contact, per the step's plate force; failed too if the lips overlap by more than
    ``overlap_tolerance`` (a length, E / K)."""
    return mirror_agreement(full, half, TOLERANCE, overlap_tolerance, force="plate_force", contact="slot_force",
                            overlap="slot_overlap", at="squeeze",
                            models="the full seal (self-contact) against the half seal on its symmetry plane",
                            closed="the slot never closed: increase --squeeze")


def _pictures(history: list, reference: list | None, profiles: dict, out: Path) -> None:
    from fenics_contact.app.plotting import plot_curves

    def series(rows, key):
        return np.array([r["squeeze"] for r in rows]), np.array([r[key] for r in rows])

    curves = []
    for rows, name, style in ((history, "full (self-contact)", "-o"), (reference, "half (symmetry plane)", "--s")):
        if rows:
            curves += [(*series(rows, "plate_force"), f"plate force, {name}", style),
                       (*series(rows, "slot_force"), f"slot force, {name}", style)]
    plot_curves(curves, out / "lipseal_forces.png", xlabel="squeeze (of the free radial span)",
                ylabel="force per unit length", title="lip seal squeezed until its slot closes")
    loaded = [(float(t), y, p) for t, (y, p) in profiles.items() if max(p, default=0.0) > 0]
    shown = {min(loaded, key=lambda row: abs(row[0] - target))[0]: None for target in (0.7, 0.8, 0.9, 1.0)} \
        if loaded else {}
    slot = [(np.array(y), np.array(p), f"t = {t:g}", "-o") for t, y, p in loaded if t in shown]
    if slot:
        plot_curves(slot, out / "lipseal_slot.png", xlabel="height along the lip (reference y)",
                    ylabel="contact pressure (nominal)", title="the closed slot's pressure on a lip")


if __name__ == "__main__":
    cli.main(main)
