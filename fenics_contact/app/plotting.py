"""Pictures: deformed meshes (pyvista, off screen) and pressure profiles (matplotlib, Agg).

pyvista and matplotlib are imported inside the functions, so this module imports
without them.
"""
from __future__ import annotations

import contextlib
import importlib.util
import logging
import os
import sys
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from dolfinx.fem import Function, FunctionSpace

__all__ = ["plot_deformed", "plot_profile", "STATE_COLOURS", "STATE_NAMES", "plot_contact_face", "plot_curves"]


def _save(path: str | Path, write: Callable[[str], object]) -> None:
    """``write(path)`` into ``path``'s folder (made if missing); an ``OSError`` is an
    :class:`~fenics_contact.output.OutputError` naming the picture (one line on the command line)."""
    from ..output import OutputError

    try:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        write(str(path))
    except OSError as exc:
        raise OutputError(f"could not write the picture {path}: {exc.strerror or exc}") from None


def _vtk_mesh(V: FunctionSpace) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """VTK (topology, cell types, dof coordinates) of the owned cells of V."""
    from dolfinx import plot

    create = getattr(plot, "create_vtk_mesh", None) or plot.vtk_mesh  # dolfinx < 0.7 / >= 0.7
    return create(V)


def _cell_nodes(V: FunctionSpace) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(local dof-node indices per owned cell in VTK order, VTK cell types, node coordinates)."""
    topology, cell_types, x = _vtk_mesh(V)
    return topology.reshape(-1, V.dofmap.dof_layout.num_dofs + 1)[:, 1:], cell_types, x


@contextlib.contextmanager
def _deepbind() -> Iterator[None]:
    """Within the block, load extension modules with RTLD_NOW | RTLD_DEEPBIND.

    dolfinx 0.5 leaves the dlopen flags at RTLD_GLOBAL, and its exported C++ std::regex
    symbols then override VTK's (other C++ ABI): VTK aborts in std::bad_alloc.
    """
    flags = sys.getdlopenflags()
    sys.setdlopenflags(os.RTLD_NOW | getattr(os, "RTLD_DEEPBIND", 0))
    try:
        yield
    finally:
        sys.setdlopenflags(flags)


def plot_deformed(u: Function, scalar: Function, path: str | Path, title: str = "",
                  scale: float = 1.0, clim: Sequence[float] | None = None) -> None:
    """Save a picture of the mesh warped by ``scale * u``, coloured by ``scalar``.

    ``u``: vector Lagrange Function (2D or 3D; of a higher degree: its P1 interpolant is drawn);
    ``scalar``: scalar P1 Function on the
    same mesh, its name titles the scalar bar; ``clim``: colour range (default:
    data range). 2D meshes are viewed from +z. Collective: every rank calls it;
    the owned cells are gathered to rank 0, which renders and writes ``path``.
    Updates the ghost values of ``u`` and ``scalar``. Without pyvista (the ``demos`` extra): no picture, a
    warning.
    """
    V, S = u.function_space, scalar.function_space
    comm = V.mesh.comm
    if importlib.util.find_spec("pyvista") is None:
        if comm.rank == 0:
            logging.getLogger(__name__).warning("no picture %s: pyvista is not installed (pip install pyvista)", path)
        return
    u.x.scatter_forward()
    from fenics_contact.compat import space_degree

    if space_degree(V) > 1:  # the picture's cells are the mesh's: the vertex values
        from dolfinx import fem

        from fenics_contact import function_space

        u1 = fem.Function(function_space(V.mesh, "Lagrange", 1, (V.dofmap.index_map_bs,)))
        u1.interpolate(u)
        u, V = u1, u1.function_space
    scalar.x.scatter_forward()
    cells, cell_types, x = _cell_nodes(V)
    scalar_cells, _, _ = _cell_nodes(S)
    if comm.allreduce(scalar_cells.shape != cells.shape or S.dofmap.index_map_bs != 1):
        raise ValueError("scalar must be a scalar Function with u's cells and nodes per cell")
    bs = V.dofmap.index_map_bs
    disp = np.zeros((x.shape[0], 3))
    disp[:, :bs] = u.x.array.real.reshape(-1, bs)[:, :3]
    points = (x + scale * disp)[cells].reshape(-1, 3)  # one copy of each node per cell
    values = scalar.x.array.real[scalar_cells].reshape(-1)
    gathered = comm.gather((points, values, cell_types, cells.shape[1]), root=0)
    if comm.rank == 0:
        with _deepbind():
            _render(gathered, scalar.name, V.mesh.geometry.dim, path, title, clim)


def _render(gathered: list, name: str, gdim: int, path: str | Path, title: str,
            clim: Sequence[float] | None) -> None:
    """Render the gathered (points, values, cell types, nodes per cell) with pyvista."""
    import pyvista

    pyvista.OFF_SCREEN = True
    points = np.concatenate([g[0] for g in gathered])
    values = np.concatenate([g[1] for g in gathered])
    cell_types = np.concatenate([g[2] for g in gathered]).astype(np.uint8)
    k = max(g[3] for g in gathered)
    connectivity = np.hstack([np.full((len(cell_types), 1), k), np.arange(len(points)).reshape(-1, k)])
    grid = pyvista.UnstructuredGrid(connectivity.ravel(), cell_types, points)
    grid.point_data[name] = values
    plotter = pyvista.Plotter(off_screen=True, window_size=(1200, 900))
    plotter.add_mesh(grid, scalars=name, cmap="viridis", clim=clim,
                     scalar_bar_args={"title": name, "vertical": True})
    if title:
        plotter.add_title(title, font_size=12)
    if gdim == 2:
        plotter.view_xy()
    try:
        _save(path, plotter.screenshot)
    finally:
        plotter.close()


def plot_profile(x: np.ndarray, p: np.ndarray, path: str | Path, x_ref: np.ndarray | None = None,
                 p_ref: np.ndarray | None = None, xlabel: str = "x",
                 ylabel: str = "contact pressure", labels: Sequence[str] = ("computed", "reference"),
                 title: str = "") -> None:
    """Save a plot of the computed points ``(x, p)``, sorted by x, over the reference curve.

    Not collective: call it on one rank (rank 0) with gathered arrays.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.4))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    if x_ref is not None and p_ref is not None:
        ax.plot(x_ref, p_ref, "-", color="black", lw=1.5, label=labels[1])
    order = np.argsort(x)
    ax.plot(np.asarray(x)[order], np.asarray(p)[order], "o-", ms=3, lw=0.8, color="tab:red",
            label=labels[0])
    ax.set(xlabel=xlabel, ylabel=ylabel, title=title)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    _save(path, lambda name: fig.savefig(name, dpi=150))


STATE_COLOURS = ("0.75", "tab:red", "tab:blue")  # open, slip, stick
STATE_NAMES = ("open", "slip", "stick")


def plot_contact_face(x: np.ndarray, y: np.ndarray, state: np.ndarray, path: str | Path,
                      traction: np.ndarray | None = None, title: str = "", xlabel: str = "x",
                      ylabel: str = "y") -> None:
    """Save a map of a flat contact face coloured by slip state (0 open, 1 slip, 2 stick; regions bounded
    half-way between vertices), with the tangential traction ``traction`` (n, 2) as arrows.

    Not collective: call it on one rank (rank 0) with gathered vertex arrays.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch
    from matplotlib.tri import Triangulation

    fig = Figure(figsize=(6.4, 5.6))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    tri = Triangulation(x, y)
    ax.tricontourf(tri, np.asarray(state, float), levels=[-0.5, 0.5, 1.5, 2.5], colors=STATE_COLOURS)
    ax.plot(x, y, ".", color="black", ms=2)
    if traction is not None:
        ax.quiver(x, y, traction[:, 0], traction[:, 1], color="black", width=0.003, label="tangential traction")
    handles = [Patch(color=c, label=n) for c, n in zip(STATE_COLOURS, STATE_NAMES)]
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=3)
    ax.set(xlabel=xlabel, ylabel=ylabel, title=title, aspect="equal")
    fig.tight_layout()
    _save(path, lambda name: fig.savefig(name, dpi=150))


def plot_curves(curves: Sequence[tuple[np.ndarray, np.ndarray, str, str]], path: str | Path, xlabel: str = "x",
                ylabel: str = "contact pressure", title: str = "") -> None:
    """Save a plot of several curves ``(x, y, label, matplotlib style)``. Not collective (call on rank 0)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.4))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    for x, y, label, style in curves:
        ax.plot(x, y, style, ms=3, lw=1.0, label=label)
    ax.set(xlabel=xlabel, ylabel=ylabel, title=title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    _save(path, lambda name: fig.savefig(name, dpi=150))
