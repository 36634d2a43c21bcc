"""Print one table of every ``summary.json`` under a results folder: scene, method, the checked figure, its
reference, its relative error, the tolerance and whether it passed (the demos' ``check``), iterations, time.

    python demos/table.py results          # exit status 1 if a check failed or a summary has none

Below the table, one line names the runs whose check failed (or that have none).
"""
import json
import sys
from pathlib import Path


def rows(root: Path) -> list[dict]:
    """Every ``<root>/*/summary.json`` (the demos' main runs), sorted by folder."""
    return [json.loads(p.read_text()) for p in sorted(root.glob("*/summary.json"))]


def _num(v, fmt: str) -> str:
    return "-" if v is None else format(v, fmt)


def failed_checks(summaries: list[dict]) -> list[str]:
    """``scene (figure: why)`` for every run whose check did not pass or that has none."""
    out = []
    for s in summaries:
        c = s.get("check") or {}
        if c.get("passed"):
            continue
        why = "no check" if not c else "no value" if c.get("rel_error") is None else \
            f"rel. error {c['rel_error']:.2e} > {c.get('tolerance', float('nan')):.0e}"
        out.append(f"{s.get('scene', '?')} ({c.get('figure', 'check')}: {why})")
    return out


def table(summaries: list[dict]) -> tuple[str, bool]:
    """The table's text and whether every run has a passed check."""
    head = (f"{'scene':12s} {'method':9s} {'ranks':>5s} {'dofs':>7s} {'figure':34s} {'value':>13s} {'reference':>13s} "
            f"{'rel. error':>10s} {'tol.':>7s} {'passed':>6s} {'newton':>6s} {'time s':>7s}")
    lines, ok = [head, "-" * len(head)], True
    for s in summaries:
        c = s.get("check") or {}
        passed = bool(c.get("passed"))
        ok = ok and passed
        lines.append(f"{s.get('scene', '?'):12s} {s.get('method', '?'):9s} {s.get('ranks', 0):5d} "
                     f"{s.get('dofs', 0):7d} {c.get('figure', '(no check)'):34s} {_num(c.get('value'), '13.6g')} "
                     f"{_num(c.get('reference'), '13.6g')} {_num(c.get('rel_error'), '10.2e')} "
                     f"{_num(c.get('tolerance'), '7.0e')} {str(passed):>6s} {s.get('newton_iterations', 0):6d} "
                     f"{s.get('wall_time_s', float('nan')):7.2f}")
    return "\n".join(lines), ok


if __name__ == "__main__":
    from fenics_contact.app import cli

    parser = cli.StrictParser(description=" ".join(__doc__.split("\n\n")[0].split()), epilog=None)
    parser.add_argument("root", nargs="?", default="results", help="folder of the runs' folders (each with a "
                        "summary.json)")
    try:
        root = Path(parser.parse_args().root)
    except cli.UsageError as exc:
        print(f"table.py: error: {exc}", file=sys.stderr)
        sys.exit(cli.EXIT_USAGE)
    summaries = rows(root)
    text, ok = table(summaries)
    print(text)
    if not ok:
        print("checks failed:", ", ".join(failed_checks(summaries)))
    sys.exit(0 if ok else 1)
