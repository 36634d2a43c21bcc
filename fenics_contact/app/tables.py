"""Tables written by the demos as CSV and Markdown: the method comparison and the Newton residual table.

Not collective: call on one rank (rank 0) with values already reduced.
"""
from __future__ import annotations

import csv
from pathlib import Path
from typing import Sequence

__all__ = ["METHOD_COLUMNS", "method_row", "write_table", "merge_method_tables", "residual_table"]

METHOD_COLUMNS = ("scene", "method", "converged", "newton_iterations", "augmentations", "load_steps", "wall_time_s",
                  "failure", "ranks", "dofs")


def method_row(summary: dict, method: str | None = None) -> dict:
    """One row of the comparison table from a ``summary.json`` dictionary (``method``: a longer label)."""
    failure = summary.get("failure")
    what = "" if not failure else (f"{failure['kind']} (step {failure['step']}, augmentation "
                                   f"{failure['augmentation']}, {failure['iterations']} iterations)")
    return {"scene": summary["scene"], "method": method or summary["method"], "converged": summary["converged"],
            # every Newton iteration done, the failed solve's included (summary's total counts converged steps)
            "newton_iterations": sum(s["newton_iterations"] for s in summary["steps"]),
            "augmentations": summary["augmentations"],
            "load_steps": summary["load_steps"], "wall_time_s": round(summary["wall_time_s"], 3), "failure": what,
            "ranks": summary["ranks"], "dofs": summary["dofs"]}


def write_table(rows: Sequence[dict], stem: str | Path, columns: Sequence[str] | None = None) -> str:
    """Write ``stem.csv`` and ``stem.md`` (a Markdown table); return the Markdown text."""
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    columns = list(columns or (rows[0].keys() if rows else ()))
    with open(stem.with_suffix(".csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=columns, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(_fmt(r.get(c, "")) for c in columns) + " |" for r in rows]
    text = "\n".join(lines) + "\n"
    stem.with_suffix(".md").write_text(text)
    return text


def merge_method_tables(root: str | Path, name: str = "methods") -> str:
    """Every ``<root>/*/<name>.csv`` (one per demo) in one table ``<root>/<name>.csv|md``; returns the Markdown."""
    root = Path(root)
    rows = []
    for path in sorted(root.glob(f"*/{name}.csv")):
        with open(path, newline="") as fh:
            rows += list(csv.DictReader(fh))
    return write_table(rows, root / name, METHOD_COLUMNS)


def residual_table(steps: Sequence[dict], stem: str | Path, solve: int = -1) -> str:
    """Newton residual norms, one row per load step and one column per iteration (the paper's Table I).

    ``steps``: the ``steps`` list of ``summary.json``; ``solve``: which solve of each step (augmentation
    index, default the last). Iteration 0 is the residual before the first Newton update.
    """
    width = max((len(s["residuals"][solve]) for s in steps if s["residuals"]), default=0)
    rows = []
    for s in steps:
        r = s["residuals"][solve] if s["residuals"] else []
        rows.append({"step": s["step"], "load": f"{s['load']:.4g}", "iterations": max(len(r) - 1, 0),
                     **{str(k): f"{v:.2e}" for k, v in enumerate(r)}})
    return write_table(rows, stem, ["step", "load", "iterations", *map(str, range(width))])


def _fmt(v) -> str:
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)
