"""Pictures: without pyvista (the ``demos`` extra) a demo goes on without its picture of the deformed mesh."""
import importlib.util
import logging

from dolfinx import fem
from dolfinx import mesh as dmesh

from fenics_contact.app.plotting import plot_deformed
from fenics_contact.compat import function_space


def test_without_pyvista_no_picture_and_a_warning(comm, tmp_path, monkeypatch, caplog):
    mesh = dmesh.create_unit_square(comm, 2, 2)
    u = fem.Function(function_space(mesh, "Lagrange", 1, (2,)))
    s = fem.Function(function_space(mesh, "Lagrange", 1), name="s")
    find_spec = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "pyvista" else find_spec(name, *a))
    with caplog.at_level(logging.WARNING):
        plot_deformed(u, s, tmp_path / "p.png")
    assert not (tmp_path / "p.png").exists()
    assert comm.rank != 0 or "pyvista is not installed" in caplog.text
