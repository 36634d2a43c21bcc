"""Convert the tutorials (``tutorials/*.py``, jupytext "percent" format) to MyST pages ``docs/tutorials/<name>.md``.

    python scripts/tutorials.py           write docs/tutorials/<name>.md and docs/tutorials/index.md
    python scripts/tutorials.py --check   exit 1 if a committed page differs from the conversion

A ``# %% [markdown]`` cell becomes text (its lines without the leading ``# ``), a ``# %%`` cell a ```` ```python ````
block. ``make docs`` runs it before Sphinx; ``tests/test_tutorials.py`` checks the committed pages.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SOURCES = ROOT / "tutorials"
PAGES = ROOT / "docs" / "tutorials"


def cells(text: str) -> list[tuple[str, list[str]]]:
    """``[(kind, lines)]`` of a percent-format script, ``kind`` ``markdown`` or ``code`` (lines before the first
    marker are code)."""
    out: list[tuple[str, list[str]]] = [("code", [])]
    for line in text.splitlines():
        if line.startswith("# %%"):
            out.append(("markdown" if "[markdown]" in line else "code", []))
        else:
            out[-1][1].append(line)
    return out


def _strip(lines: list[str]) -> list[str]:
    while lines and not lines[0].strip():
        lines = lines[1:]
    while lines and not lines[-1].strip():
        lines = lines[:-1]
    return lines


def convert(path: Path) -> str:
    """The MyST page of the tutorial at ``path``."""
    blocks, first = [], True
    for kind, lines in cells(path.read_text()):
        lines = _strip(lines)
        if not lines:
            continue
        if kind == "markdown":
            bad = [line for line in lines if line and line != "#" and not line.startswith("# ")]
            if bad:
                raise ValueError(f"{path.name}: a markdown line that is not a '# ' comment: {bad[0]!r}")
            blocks.append("\n".join(line[2:] for line in lines))
            if first:
                blocks.append(f"*Generated from `tutorials/{path.name}` by `scripts/tutorials.py`; run it with "
                              f"`python tutorials/{path.name}` (also under `mpirun -n 2`).*")
                first = False
        else:
            blocks.append("```python\n" + "\n".join(lines) + "\n```")
    return "\n\n".join(blocks) + "\n"


def index(names: list[str]) -> str:
    """The tutorials' index page with its toctree."""
    return ("# Tutorials\n\nSmall problems of one's own, each a Python script of `tutorials/` that checks its figure "
            "against a closed form or a published value and runs in a few seconds. Run one with\n"
            "`python tutorials/<name>.py`; `tests/test_tutorials.py` runs them all.\n\n"
            "```{toctree}\n:maxdepth: 1\n\n" + "\n".join(names) + "\n```\n")


def pages() -> dict[Path, str]:
    """Every generated page and its text."""
    sources = sorted(SOURCES.glob("[0-9]*.py"))
    out = {PAGES / f"{p.stem}.md": convert(p) for p in sources}
    out[PAGES / "index.md"] = index([p.stem for p in sources])
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare with the committed pages, write nothing")
    args = parser.parse_args(argv)
    wanted = pages()
    if args.check:
        stale = [str(p.relative_to(ROOT)) for p, text in wanted.items() if not p.is_file() or p.read_text() != text]
        extra = [str(p.relative_to(ROOT)) for p in PAGES.glob("*.md") if p not in wanted]
        if stale or extra:
            print(f"out of date: {stale}; not a tutorial: {extra} (run python scripts/tutorials.py)", file=sys.stderr)
            return 1
        return 0
    PAGES.mkdir(parents=True, exist_ok=True)
    for p in PAGES.glob("*.md"):
        if p not in wanted:
            p.unlink()
    for p, text in wanted.items():
        p.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
