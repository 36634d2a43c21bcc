"""What the scenes with a full model and its half on the symmetry plane share (``tube``, ``lipseal``): the half's
law, twice as stiff (the full model's gap across the plane is the overlap of both sides), and the dofs on the
symmetry line."""
from __future__ import annotations

import copy

import numpy as np
from dolfinx import fem
from dolfinx import mesh as dmesh

from ...laws import ContactLaw

__all__ = ["stiffer", "vertex_dofs", "line_dofs"]


def stiffer(law: ContactLaw) -> ContactLaw:
    """A copy of ``law`` whose pressure at a gap ``g`` is its pressure at ``2 g``: the symmetry plane's law of the
    half model (the full model's gap is the overlap of both sides). Laws linear in the gap on the closed side
    (penalty, auglag, compliance with any ``m_n``)."""
    law = copy.deepcopy(law)
    scalars = law.scalars
    if "K" in scalars:
        scalars["K"] *= 2.0
    elif "c_n" in scalars:
        scalars["c_n"] *= 2.0 ** scalars.get("m_n", 1.0)
    else:
        raise ValueError(f"method {law.name!r} has no penalty to double for the half model: penalty, auglag or "
                         f"compliance")
    return law


def vertex_dofs(V, component: int, where) -> np.ndarray:
    """Dofs of displacement component ``component`` at the mesh vertices where ``where(x)`` holds."""
    mesh = V.mesh
    vertices = dmesh.locate_entities(mesh, 0, where)
    mesh.topology.create_connectivity(0, mesh.topology.dim)  # dolfinx >= 0.9 does not make it on demand
    return fem.locate_dofs_topological(V.sub(component), 0, vertices)


def line_dofs(V, component: int, where) -> np.ndarray:
    """Dofs of displacement component ``component`` on the edges (interior ones too) where ``where(x)`` holds."""
    edges = dmesh.locate_entities(V.mesh, 1, where)
    return fem.locate_dofs_topological(V.sub(component), 1, edges)
