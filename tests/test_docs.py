"""The HTML documentation builds, Sphinx warnings as errors: the pages of docs/ (MyST markdown) and the API
reference from the docstrings (``make docs`` without regenerating the generated pages). Slow lane, serial only;
skipped where the ``docs`` extra is not installed (the Debian 13 lane runs the distribution's Python)."""
import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI

ROOT = Path(__file__).resolve().parent.parent
serial = pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="a subprocess from the serial lane only")
MISSING = [m for m in ("sphinx", "myst_parser") if importlib.util.find_spec(m) is None]


@serial
@pytest.mark.skipif(bool(MISSING), reason=f"{' and '.join(MISSING)} not importable: the docs extra "
                                          "(pip install -e '.[docs]') is not installed")
def test_html_documentation_builds_without_warnings(tmp_path):
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_"))}
    out = tmp_path / "html"
    proc = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                           str(ROOT / "docs"), str(out)], capture_output=True, text=True, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert not proc.stderr.strip(), proc.stderr
    api = (out / "api.html").read_text()
    for anchor in ("fenics_contact.Solver", "fenics_contact.contact_surface", "module-fenics_contact.capabilities"):
        assert f'id="{anchor}"' in api, anchor  # autodoc imported the package and documented it


def _calls(text: str, name: str):
    """The argument text of every call ``name(...)`` in ``text`` (balanced parentheses)."""
    for match in re.finditer(rf"(?<![\w.])(?:fc\.)?{name}\(", text):
        depth, start = 1, match.end()
        for i in range(start, len(text)):
            depth += {"(": 1, ")": -1}.get(text[i], 0)
            if depth == 0:
                yield text[start:i]
                break


def _keywords(arguments: str) -> list[str]:
    """The keyword names given at the top level of a call's argument text (comments and strings left out)."""
    arguments = re.sub(r"#[^\n]*", "", re.sub(r"\"[^\"\n]*\"|'[^'\n]*'", '""', arguments))
    depth, found = 0, []
    for i, c in enumerate(arguments):
        depth += {"(": 1, "[": 1, "{": 1, ")": -1, "]": -1, "}": -1}.get(c, 0)
        if depth == 0 and c == "=" and arguments[i + 1:i + 2] != "=" and arguments[i - 1:i] not in "=!<>":
            word = re.search(r"(\w+)\s*$", arguments[:i])
            if word:
                found.append(word.group(1))
    return found


def test_keywords_in_the_documentation_are_the_api_arguments():
    """Every call of a public function or class of ``fc.__all__`` written in the docs pages, the README and the
    tutorials gives keyword arguments that its signature has (``law_factory``, not ``law``)."""
    import inspect

    import fenics_contact as fc

    texts = {p: p.read_text() for p in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md")),
                                        *sorted((ROOT / "tutorials").glob("*.py"))] if "_build" not in p.parts}
    wrong, seen = [], 0
    for name in fc.__all__:
        obj = getattr(fc, name)
        if not callable(obj) or inspect.ismodule(obj):
            continue
        try:
            params = inspect.signature(obj).parameters
        except (TypeError, ValueError):
            continue
        if any(p.kind == p.VAR_KEYWORD for p in params.values()):
            continue  # any keyword is accepted
        for path, text in texts.items():
            for arguments in _calls(text, name):
                seen += 1
                wrong += [f"{path.relative_to(ROOT)}: {name}(... {k}=...)" for k in _keywords(arguments)
                          if k not in params]
    assert seen > 50  # the pages do call the API
    assert not wrong, wrong


def test_no_development_history_in_docs_or_comments():
    """No page of docs/ nor the README, and no comment or docstring of the package, the tests, the scripts or the
    tutorials, carries development history (:data:`history.HISTORY`)."""
    import io
    import tokenize

    from history import HISTORY

    hits = []
    for path in [ROOT / "README.md", *(ROOT / "docs").rglob("*.md")]:
        if "_build" not in path.parts:
            hits += [f"{path.relative_to(ROOT)}: {m.group(0)}" for m in HISTORY.finditer(path.read_text())]
    sources = [*(ROOT / "fenics_contact").rglob("*.py"), *(ROOT / "tests").glob("*.py"),
               *(ROOT / "scripts").glob("*.py"), *(ROOT / "tutorials").glob("*.py"), *(ROOT / "demos").glob("*.py")]
    for path in sources:
        if path.name == "history.py":
            continue  # the pattern itself
        for tok in tokenize.generate_tokens(io.StringIO(path.read_text()).readline):
            if tok.type == tokenize.COMMENT or (tok.type == tokenize.STRING and
                                               tok.string.lstrip("rbuRBU").startswith(('"""', "\'\'\'"))):
                hits += [f"{path.relative_to(ROOT)}:{tok.start[0]}: {m.group(0)}" for m in HISTORY.finditer(tok.string)]
    assert HISTORY.search("as in round 3, the issue's target") and not HISTORY.search("the load path (t_k, f_k)")
    assert not hits, hits


def test_the_failure_guide_names_every_failure_kind():
    """docs/guide/failures.md has a row for every kind a failed solve can be given (``failure.KINDS``)."""
    from fenics_contact import failure

    rows = re.findall(r"^\| `(\w+)` \|", (ROOT / "docs" / "guide" / "failures.md").read_text(), re.M)
    assert sorted(rows) == sorted(failure.KINDS), sorted(set(rows) ^ set(failure.KINDS))
