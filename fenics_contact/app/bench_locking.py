"""Volumetric locking of a benchmark scene: displacement-only and mixed bulk models over Poisson's ratio.

A scene takes part when its ``BENCH`` has ``locking``: ``method`` (one contact method, its K the scene's),
``quadrature``, ``nu`` (the ratios), ``figures`` (summary keys), ``variants`` (label, demo options: the bulk
models and degrees compared), ``reference`` (label, demo options: the run each variant is measured against at the
same ``nu``, e.g. the mixed model on a fine mesh) and ``args`` (demo options of every run). Each run is a fresh
serial demo process (:func:`~fenics_contact.app.bench.run_one`); the rows go to ``<scene>_locking.csv`` (and
``.json``), the table to ``<scene>_locking.md`` (per variant and ``nu``: each figure's relative error against the
reference, Newton iterations, time; ``failed`` where the run did not converge) and the chart to
``<scene>_locking.png`` (the errors against ``1 - 2 nu``, the volumetric compliance that vanishes at
incompressibility).
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Sequence

from . import bench

__all__ = ["runs", "locking", "errors", "table", "plot_locking", "report"]


def runs(scene: str) -> list[dict]:
    """The locking runs of ``scene``: every variant and the reference at every ``nu``, each a
    :func:`~fenics_contact.app.bench.run_config` with its ``variant`` (the label of its variant), ``nu``, demo
    options ``args`` and a ``label`` naming both (its run's folder)."""
    s = bench.spec(scene)
    lk = s["locking"]
    out = []
    for nu in lk["nu"]:
        for label, args in (*lk["variants"], lk["reference"]):
            cfg = bench.run_config(lk["method"], s["K"], 0, lk["quadrature"])
            out.append(dict(cfg, label=f"{label}, nu = {nu:g}", variant=label, nu=nu,
                            args=[*lk.get("args", []), *args, "--nu", repr(nu)]))
    return out


def errors(rows: Sequence[dict], scene: str) -> list[dict]:
    """Per run but the references: its figures' relative errors against the reference run at the same ``nu``
    (``<figure>_error``; NaN where either did not converge)."""
    lk = bench.spec(scene)["locking"]
    ref_label = lk["reference"][0]
    refs = {r["nu"]: r for r in rows if r["variant"] == ref_label}
    out = []
    for r in rows:
        if r["variant"] == ref_label:
            continue
        ref = refs.get(r["nu"])
        e = {}
        for f in lk["figures"]:
            ok = r["converged"] and ref is not None and ref["converged"] and ref[f]
            e[f"{f}_error"] = abs(r[f] - ref[f]) / abs(ref[f]) if ok else float("nan")
        out.append({**r, **e})
    return out


def table(rows: Sequence[dict], scene: str) -> str:
    """Markdown: per variant (rows) and ``nu`` (columns) the errors of the figures against the reference, the
    Newton iterations and the solver time; then the reference's figures."""
    lk = bench.spec(scene)["locking"]
    nus = list(lk["nu"])
    figs = lk["figures"]
    head = "| model | " + " | ".join(f"nu = {nu:g}" for nu in nus) + " |"
    lines = [f"Errors of {' / '.join(figs)} against {lk['reference'][0]} at the same nu; Newton iterations, "
             "solver time [s]. Method " + f"{lk['method']}, {lk['quadrature']}.", "", head,
             "|---|" + "---|" * len(nus)]
    err = errors(rows, scene)
    for label, _ in lk["variants"]:
        cells = []
        for nu in nus:
            r = next((x for x in err if x["variant"] == label and x["nu"] == nu), None)
            if r is None:
                cells.append("-")
            elif not r["converged"]:
                cells.append(f"failed ({r.get('failure_kind') or 'exit'})")
            else:
                cells.append(" / ".join(f"{r[f + '_error']:.1%}" for f in figs)
                             + f"; {r['newton_iterations']} it, {r['wall_time_s']:.2g} s")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    refs = {r["nu"]: r for r in rows if r["variant"] == lk["reference"][0]}
    lines.append(f"| {lk['reference'][0]}: " + " / ".join(figs) + " | " + " | ".join(
        " / ".join(f"{refs[nu][f]:.5g}" for f in figs) if nu in refs and refs[nu]["converged"] else "failed"
        for nu in nus) + " |")
    return "\n".join(lines) + "\n"


def plot_locking(rows: Sequence[dict], scene: str, path: str | Path) -> None:
    """The errors of each variant's figures against ``1 - 2 nu`` (log-log; one colour per variant, a marker per
    figure); failed runs as red crosses at the top."""
    lk = bench.spec(scene)["locking"]
    fig, ax = bench.figure()
    err = errors(rows, scene)
    finite = [r[f + "_error"] for r in err for f in lk["figures"] if not math.isnan(r[f + "_error"])]
    top = max(finite, default=1.0) * 2
    for k, (label, _) in enumerate(lk["variants"]):
        rs = sorted((r for r in err if r["variant"] == label), key=lambda r: -r["nu"])
        for f, m in zip(lk["figures"], "os^D"):
            ok = [r for r in rs if not math.isnan(r[f + "_error"])]
            ax.plot([1 - 2 * r["nu"] for r in ok], [max(r[f + "_error"], bench.ERROR_FLOOR) for r in ok],
                    color=f"C{k}", marker=m, ls="-", label=f"{label}: {f}")
        bad = [r for r in rs if not r["converged"]]
        ax.plot([1 - 2 * r["nu"] for r in bad], [top] * len(bad), ls="", marker="x", color="red", ms=10, mew=2)
    if any(not r["converged"] for r in err):
        ax.plot([], [], ls="", marker="x", color="red", ms=10, mew=2, label="failed (drawn at the top)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.invert_xaxis()  # toward incompressibility to the right
    ax.set_xlabel("1 - 2 nu [-] (0: incompressible)")
    ax.set_ylabel(f"relative error against {lk['reference'][0]} [-]")
    ax.set_title(f"{scene}: locking of the displacement-only models", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    fig.savefig(path, dpi=100)


def report(scene: str, rows: Sequence[dict], out: str | Path, pictures: bool = True) -> str:
    """``<scene>_locking.md`` (and ``.png``) from ``rows``; returns the table."""
    out = Path(out)
    text = table(rows, scene)
    (out / f"{scene}_locking.md").write_text(text)
    if pictures:
        plot_locking(rows, scene, out / f"{scene}_locking.png")
    return text


def locking(scene: str, out: str | Path, quiet: bool = False, timeout: float = 600.0,
            pictures: bool = True) -> list[dict]:
    """Run :func:`runs` into ``out/<scene>/``; write ``<scene>_locking.csv``, ``.json``, ``.md`` and ``.png``
    (:func:`~fenics_contact.app.bench.read_rows` reads the ``.csv`` back)."""
    out = Path(out)
    rows = bench.run_all(scene, out, runs(scene), quiet, timeout, tag=" locking")
    bench.write_rows(rows, out / f"{scene}_locking.csv", out / f"{scene}_locking.json")
    report(scene, rows, out, pictures)
    return rows
