"""The tutorials (``tutorials/*.py``) run as they are, in process, each asserting its figure against a closed form
or a published value; the two-body ones under ``mpirun -n 2`` too, with the same figure on every rank. The pages
``docs/tutorials/*.md`` are the conversion of the scripts (``scripts/tutorials.py``)."""
import importlib.util
import runpy
from pathlib import Path

import numpy as np
import pytest
from mpi4py import MPI

ROOT = Path(__file__).resolve().parents[1]
TUTORIALS = sorted(p.stem for p in (ROOT / "tutorials").glob("[0-9]*.py"))
TWO_BODY = {"03_two_blocks_patch"}  # run under mpirun as well: figures reduced over the ranks
FIGURES = {"03_two_blocks_patch": "deviation"}  # the figure each rank must agree on
PICTURES = {"07_results_and_paraview": "pictures"}  # the PNG files a tutorial plots from its written output


def _converter():
    spec = importlib.util.spec_from_file_location("tutorials_script", ROOT / "scripts" / "tutorials.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_there_are_tutorials():
    assert len(TUTORIALS) >= 6 and TWO_BODY <= set(TUTORIALS)


def test_pages_are_the_conversion_of_the_tutorials():
    converter = _converter()
    pages = converter.pages()
    for path, text in pages.items():
        assert path.is_file() and path.read_text() == text, f"{path.name}: run python scripts/tutorials.py"
    assert set((ROOT / "docs" / "tutorials").glob("*.md")) == set(pages)
    assert "tutorials/index" in (ROOT / "docs" / "index.md").read_text()


def test_conversion_of_cells():
    converter = _converter()
    text = "# %% [markdown]\n# # Title\n#\n# Text.\n\n# %%\nx = 1\n\n# %% [markdown]\n# More.\n"
    cells = converter.cells(text)
    assert [k for k, _ in cells] == ["code", "markdown", "code", "markdown"]


@pytest.mark.parametrize("name", TUTORIALS)
def test_tutorial_runs(name, tmp_path, monkeypatch):
    comm = MPI.COMM_WORLD
    if comm.size > 1 and name not in TWO_BODY:
        pytest.skip("a one-body tutorial: serial lane")
    if comm.size == 1:
        monkeypatch.chdir(tmp_path)  # where a tutorial writes its output
    scope = runpy.run_path(str(ROOT / "tutorials" / f"{name}.py"), run_name="__main__")
    if name in PICTURES and comm.rank == 0:
        pytest.importorskip("matplotlib")
        pictures = scope[PICTURES[name]]
        assert pictures and all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and p.stat().st_size > 10_000
                                for p in pictures)
    if name in FIGURES:
        figure = scope[FIGURES[name]]
        assert np.allclose(comm.allgather(figure), figure, rtol=0, atol=0)
