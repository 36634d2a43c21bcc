"""What the demos of a full model with self-contact and its half on the symmetry plane share (``tube``,
``lipseal``): solve the half, then the full model with the check against it; write both models' figures and their
deformed shapes."""
from __future__ import annotations

import csv
from pathlib import Path
from typing import Callable

from . import cli
from .run import run
from .scenes import build

__all__ = ["solve_full_and_half", "write_models"]


def solve_full_and_half(args, scene: str, build_kwargs: dict, parameters: dict, out: Path,
                        profile: Callable, agreement: Callable) -> tuple:
    """Solve scene ``scene`` (``build_kwargs`` besides ``law``, ``quadrature`` and ``half``): with ``args.half`` the
    half model alone into ``out``; else the half into ``out/half``, then the full one into ``out`` with the check
    ``agreement(full figures, half figures, E / K)`` (:func:`~.checks.mirror_agreement`). ``parameters``: the
    scene's own, recorded beside the method's; ``profile(setup)``: the profile kept per step.

    Returns:
        ``(summary, profiles, setup, history, reference, half_setup)``: the last model's summary, its profiles per
        load and set-up, its figures per step; the half model's figures and set-up (None with ``args.half``).
    """
    def solve(half: bool, folder: Path, history: list, check=None) -> tuple[dict, dict, object]:
        setup = build(scene, law=cli.law_from_args(args), quadrature=args.quadrature, half=half, **build_kwargs)
        profiles = {}

        def after_step(t: float) -> None:
            history.append(setup.figures())
            profiles[f"{t:.6g}"] = profile(setup)

        summary = run(setup, folder, args.method, {**cli.method_parameters(args), **parameters},
                      args.augment, args.augment_tol, args.quiet, options=cli.solver_options(args),
                      on_step=after_step, keep=(history, profiles), check=check, xdmf=not args.no_xdmf,
                      restart=args.restart, overwrite=args.overwrite)
        summary["history"] = history
        return summary, profiles, setup

    history = []
    if args.half:
        summary, profiles, setup = solve(True, out, history)
        return summary, profiles, setup, history, None, None
    reference = []
    _, _, half_setup = solve(True, out / "half", reference)
    law = cli.law_from_args(args)
    K = law.scalars.get("K", law.scalars.get("c_n"))
    summary, profiles, setup = solve(False, out, history, check=lambda s: agreement(history, reference, args.E / K))
    return summary, profiles, setup, history, reference, half_setup


def write_models(args, out: Path, stem: str, what: str, at: str, setup, history: list, reference: list | None,
                 half_setup) -> bool:
    """``<stem>_figures.csv`` (every step of each model) and, unless ``args.no_pictures``, the deformed shapes
    ``<stem>_deformed.png`` and ``<stem>_half_deformed.png`` (the last contact's pressure; ``what`` names the body,
    ``at`` the figure that names the load). Collective. Returns True on the rank that writes the tables (rank 0)."""
    if not args.no_pictures:
        from .plotting import plot_deformed

        for model, s, rows, name in ((("half" if args.half else "full"), setup, history, f"{stem}_deformed.png"),
                                     ("half", half_setup, reference, f"{stem}_half_deformed.png")):
            if s is None:
                continue
            contact = s.contacts[-1]
            contact.update_output()
            plot_deformed(contact.displacement_out, contact.pressure_out, out / name,
                          title=f"{model} {what}, {at} {rows[-1][at]:.3g}")
    if setup.problem.comm.rank != 0:
        return False
    with open(out / f"{stem}_figures.csv", "w", newline="") as fh:
        rows = [{"model": "half" if args.half else "full", **h} for h in history]
        rows += [{"model": "half", **h} for h in (reference or [])]
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return True
