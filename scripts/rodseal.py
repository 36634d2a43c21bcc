"""A rod seal's friction: the ``oring`` scene as a rod gland (the inner wall the rod), the cord squeezed, the fluid
pressure applied, then the rod sliding along +z under Coulomb friction (penalty, stick penalty E / h); per pressure
the rod's axial drag per unit circumference against its travel (sticking, then the break-out to sliding) and the
sliding drag against the pressure, beside mu times the rod's normal force.

    python scripts/rodseal.py [--mu 0.2] [--squeeze 0.2] [--pressures 0 0.025 0.05 0.1] [--h 0.0625]
        [--out results/rodseal] [--chart docs/rodseal_friction.png]

Writes rodseal.csv (every step of every pressure) into --out and the chart; prints one Markdown row per pressure.
Pressures are per E; the rod's stroke is 0.6 d in --stroke-steps steps (the cord rolls with the rod until the side
wall stops it, then the rod slides under it).
"""
from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path

from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.app.scenes import build, oring

BREAK_OUT = 1 - 1e-6  # the rod's drag over its capacity mu F at which it slides everywhere it is loaded


def run(mu: float, squeeze: float, pressure: float, h: float, stroke_steps: int, comm=MPI.COMM_WORLD) -> list[dict]:
    """Every step's figures of one rod-seal run (pressure per E)."""
    law = fc.Friction(fc.make_law("penalty", K=oring.DEFAULT_K * oring.E / h), mu=mu,
                      omega_t=oring.OMEGA_T * oring.E / h)
    setup = build("oring", law=law, comm=comm, h=h, steps=2, squeeze=squeeze, pressure=pressure * oring.E,
                  pressure_steps=2, stroke=0.6 * oring.D, stroke_steps=stroke_steps)
    history = []
    with fc.Solver(setup.problem, quiet=True) as solver:
        solver.on_step = lambda t: history.append(setup.figures())
        solver.run(setup.loads)
    return history


def chart(rows: dict[float, list[dict]], mu: float, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    sliding = []
    for p, hist in rows.items():
        steps = [h for h in hist if h["t"] >= 2.0]
        line, = ax.plot([h["stroke"] for h in steps], [h["friction_rod"] for h in steps], "o-",
                        label=f"p = {p:g} E")
        out = [h for h in steps if h["rod_mobilised"] >= BREAK_OUT]
        if out:  # the break-out: the first step whose drag takes the rod's whole capacity mu F
            ax.plot(out[0]["stroke"], out[0]["friction_rod"], "*", ms=14, color=line.get_color())
        end = steps[-1]
        sliding.append((p * oring.E, end["friction_rod"], mu * end["force_bottom"]))
    ax.set(xlabel="rod travel (d)", ylabel="drag on the rod per unit circumference",
           title="stick, then sliding (star: the break-out, drag = mu F)")
    ax2.plot([s[0] for s in sliding], [s[1] for s in sliding], "o-", label="sliding drag")
    ax2.plot([s[0] for s in sliding], [s[2] for s in sliding], "k--", label="mu x the rod's normal force")
    ax2.set(xlabel="fluid pressure", ylabel="drag on the rod per unit circumference", title=f"mu = {mu:g}")
    for a in (ax, ax2):
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--mu", type=float, default=0.2)
    p.add_argument("--squeeze", type=float, default=0.2)
    p.add_argument("--pressures", type=float, nargs="+", default=[0.0, 0.025, 0.05, 0.1])
    p.add_argument("--h", type=float, default=oring.H * oring.D)
    p.add_argument("--stroke-steps", type=int, default=12)
    p.add_argument("--out", default="results/rodseal")
    p.add_argument("--chart", default="docs/rodseal_friction.png")
    a = p.parse_args(argv)
    rows = {pr: run(a.mu, a.squeeze, pr, a.h, a.stroke_steps) for pr in a.pressures}
    if MPI.COMM_WORLD.rank == 0:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        with open(out / "rodseal.csv", "w", newline="") as fh:
            keys = ["pressure_per_E", *rows[a.pressures[0]][0]]
            w = csv.DictWriter(fh, fieldnames=keys)
            w.writeheader()
            w.writerows({"pressure_per_E": pr, **h} for pr, hist in rows.items() for h in hist)
        chart(rows, a.mu, Path(a.chart))
        print("| pressure | rod normal force | drag before the stroke | break-out travel | sliding drag | "
              "mu x normal |\n|---|---|---|---|---|---|")
        for pr, hist in rows.items():
            before = [h for h in hist if h["t"] <= 2.0][-1]
            steps = [h for h in hist if h["t"] > 2.0]
            out_at = next((h["stroke"] for h in steps if h["rod_mobilised"] >= BREAK_OUT), math.nan)
            end = steps[-1]
            print(f"| {pr * oring.E:g} | {end['force_bottom']:.4g} | {before['friction_rod']:.4g} | {out_at:.3g} | "
                  f"{end['friction_rod']:.4g} | {a.mu * end['force_bottom']:.4g} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
