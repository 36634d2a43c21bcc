"""Exact contact by Lagrange multipliers (method ``lagrange``): the contact pressure is an unknown.

Space: the unknown lives on ``W = V x Q``, ``V`` the displacement space
(vector Lagrange, P1 or P2) and ``Q`` scalar P1 for the pressure ``p``
(positive in compression). dolfinx 0.5.2 cannot assemble a mixed form whose
second field lives on a submesh of the boundary, so ``Q`` is P1 on the whole
mesh and the pressure dofs off the contact surface are removed from the
problem by Dirichlet conditions ``p = 0`` (identity rows and columns of the
assembled Jacobian, decoupled from the rest). They are kept out of the
linear solve by PETSc's field split: ``pc_type fieldsplit`` (additive) with
two index sets, ``free`` (displacement and surface pressures: MUMPS LU) and
``pinned`` (Jacobi, exact on the identity block); the blocks do not couple,
so the additive split is the exact inverse and MUMPS factors only the real
unknowns (:meth:`PressureUnknown.field_split`, set by the solver; a
``-fc_pc_type`` on the command line replaces it). Which dofs are "on the
surface" is decided by ``locate_dofs_topological`` on the contact facets,
which communicates shared dofs, so every rank agrees. Reported sizes
(``Setup.dofs``) count only the real unknowns (displacement and surface
pressures: ``pinned_dofs`` are subtracted). Not PETSc's PCREDISTRIBUTE
(which drops the rows holding only their diagonal): the inactive pressure
rows are diagonal-only too, so its reduced size changes with the active set
and PETSc 3.18 stops at the second Newton iteration ("Cannot change local
size of Amat after use"); the field split's index sets are fixed (the
surfaces are). The Jacobian's matrix holds only what can be nonzero
(:func:`~fenics_contact.sparse.trimmed_matrix`: the bodies' displacement
pairs, the contact cells' blocks, the diagonal), not dolfinx's pattern of
every pair of a cell's dofs (a third of its entries on mindlin3d).

Constraint, per contact vertex (vertex quadrature ``contact_measure(...,
"nodal")``, so the integrals are weighted nodal values): the spec's
complementarity function ``C(p, g) = p - max(0, p + c g)`` (gap ``g > 0``
penetration) is zero iff ``g <= 0, p >= 0, p g = 0``. The residual is

    u rows:  dW[v] + int p dg[v] ds
    p rows:  int -C(p, g) q ds = int (max(0, p + c g) - p) q ds

(a force, like the ``u`` rows, so that the residual's norm does not depend on the units: active rows are
``c dg[du] q``, ``c`` times the transpose of the ``u`` rows' ``dp dg[v]``; inactive rows are ``-dp q``). The
Jacobian is ``ufl.derivative`` of the residual: the
derivative of ``max_value`` is UFL's generalized (semismooth) derivative, so
SNES ``newtonls`` is a semismooth Newton / primal-dual active-set method.
``c`` changes the iterates, not the converged solution.

Quadratic displacements (Papadopoulos & Solberg's "two-point" element for a
rigid obstacle): the gap is enforced at the two end nodes of each contact
facet only, the pressure is linear on the facet, and its work ``int p dg[v]``
is integrated with Simpson's rule (``quadrature="simpson"``) so the middle
node carries its share. The penalty regularization ``p = eps <g>`` at the
end nodes is the law :class:`~fenics_contact.laws.PenaltyMultiplier` on the
same space (``C = p - eps max(0, g)``).

Two bodies (:func:`two_body_multipliers`): each slave vertex's pressure is
an unknown and its gap is measured against the current master facets by
:mod:`twobody`'s projection and mirror fields; the master rows and the
constraint rows' dependence on the master displacement go through twobody's
coupling ``I`` (its coupling forms are built from ``residual(v)``). One pass
by default; ``passes="two"`` makes each surface slave once (weight 1/2, a
pressure on both surfaces), which is well posed only where no vertex of one
surface nearly coincides with a vertex of the other (otherwise the two
constraints are nearly the same and the pressure splits arbitrarily between
the passes; the paper collocates ``p(1) = p(2)`` there, not done here: see
the sheet scene). Quadratic displacements (the sheet): the two-point element
as for a rigid obstacle, the constraint at the end nodes of each slave facet
against the master's curved quadratic facets, the work with Simpson's rule
(``work_quadrature="simpson"``).

Linear solver: the Jacobian is a saddle point with zero diagonal on the
active pressure rows; the solver's default direct LU by MUMPS (unsymmetric
LU, threshold partial pivoting ``CNTL(1) = 0.01``, MUMPS's automatic
ordering ``ICNTL(7) = 7``) factors the ``free`` block of the field split.

Solver ``iterative`` (:attr:`PressureUnknown.iterative_solver_options`): the
same additive split (the pinned pressure dofs out, Jacobi), its ``free``
block split again into the displacement ``u`` and the surface pressures
``p`` (:meth:`PressureUnknown.schur_split`, index sets in the free block's
numbering) and preconditioned by the upper triangular Schur factorization
(``pc_fieldsplit_schur_fact_type upper``: one ``A_uu`` cycle per Krylov
iteration, where ``full`` takes two) with ``S ~ A_pp - A_pu
diag(A_uu)^-1 A_up`` (``selfp``; inactive pressure rows keep their ``-1``
(times the vertex weight) diagonal, active rows get ``A_pu D^-1 A_up``): ``A_uu`` by one GAMG cycle
with the rigid-body modes as near-nullspace (block size 2 or 3; on a linear body the hierarchy of the first
solve serves the whole run, set up again only on a new pattern: mindlin3d with friction at 72,461 / 507,916 dofs,
2 ranks, Newton iterations 33 -> 33 / 44 -> 45, Krylov iterations 1327 -> 1324 / 2376 -> 2478, the same figures,
linear solves 20.7 -> 16.8 s / 308 -> 252 s), ``S`` by
block Jacobi ILU(0); outer FGMRES, ``rtol`` from :data:`KRYLOV_RTOL_MAX` down to 1e-8 as the Newton residual
falls (:meth:`~fenics_contact.solver.newton.Newton.forcing`), restart 100, at most 500
iterations. A block's options can be replaced on the command line
(``-fc_fieldsplit_free_fieldsplit_u_pc_type lu``: an exact displacement
block). Measured (one run each, 2 ranks unless said): mindlin3d with
friction (two bodies, 3D) at 72,461 / 162,021 dofs, the same Newton
iterations (+-1), Krylov iterations and figures as ``full`` in 0.75 / 0.67 of
its linear solve time; the sheet (collocated element, 4 load steps; Krylov
iterations per Newton iteration, ``full`` -> ``upper``): n_arc = 24 (1742
dofs, serial) 73 -> 81, 48 (3458, serial) 176 -> 224 (0.9 of the time), 96
(6890) over the 500 cap at the first step (the run fails with the default
cap). The Schur approximation is not what degrades: with an exact ``A_uu``
(LU) the counts are 17, 26 and 43 (docs/benchmarks.md). GAMG (and
BoomerAMG with nodal coarsening: 44-120, 48-147, 133-469) on the thin sheet
wrapped on a 100x stiffer cylinder is: plain GAMG on the three-point
penalty's Jacobian of the same sheet needs 174 and 470 iterations per
Newton iteration at n_arc = 24, 48. Same figures as LU to 1e-12.
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from .capabilities import check, of
from .compat import collapse, function_space, mixed_space
from .contact import ContactSurface, contact_measure, is_mixed
from .laws import ContactLaw, LagrangeMultiplier, ufl_ops
from .obstacles import Obstacle
from .twobody import TwoBodySurface

__all__ = ["KRYLOV_RTOL_MAX", "unknown", "PressureUnknown", "MultiplierContact", "TwoBodyMultiplier"]


def unknown(mesh, degree: int, law: ContactLaw, name: str = "displacement",
            model: str | None = None) -> tuple[fem.Function, object]:
    """The problem's unknown and the displacement (sub)space for Dirichlet data.

    ``(u, V)`` with ``u`` on the vector Lagrange space ``V`` of ``degree``, or ``(w, W.sub(0))`` with ``w`` on a
    mixed space: for method ``lagrange`` (displacement of ``degree``, contact pressure P1; with friction the contact
    traction, a P1 vector: :mod:`~fenics_contact.multiplier_friction`), or for a mixed bulk
    ``model`` (``neohookean-mixed``, ``linear-mixed``; Taylor-Hood: displacement of ``degree``, the bulk pressure
    of ``degree - 1``). ``V.sub(i)`` are the components either way.

    Args:
        mesh: the mesh.
        degree: the displacement's polynomial degree (1 or 2).
        law: the method's law (a mixed unknown for ``lagrange`` and ``penalty_multiplier``).
        name: the Function's name (output).
        model: the bulk model's name (:data:`~fenics_contact.models.MODELS`), checked with the law on the
            capability grid; a mixed model makes the Taylor-Hood unknown; None: a displacement model.

    Returns:
        ``(u, V)``: the unknown and the displacement (sub)space.
    """
    from .models import MODELS

    check(**of(law), dim=mesh.geometry.dim, degree=degree, model=model)
    traction = isinstance(getattr(law, "normal", None), LagrangeMultiplier)  # with friction: the traction vector
    if traction:
        W = mixed_space(mesh, degree, 1, vector=True)
        return fem.Function(W, name="displacement_traction"), W.sub(0)
    if isinstance(law, LagrangeMultiplier) or (model is not None and MODELS[model].mixed):
        W = mixed_space(mesh, degree, 1 if isinstance(law, LagrangeMultiplier) else degree - 1)
        return fem.Function(W, name="displacement_pressure"), W.sub(0)
    V = function_space(mesh, "Lagrange", degree, (mesh.geometry.dim,))
    return fem.Function(V, name=name), V


# The iterative solve's largest Krylov tolerance (relative to the Newton residual; newton.Newton.forcing: it follows
# the residual's fall down to ksp_rtol). Measured with a fixed tolerance on mindlin3d with friction (162,021 dofs, 2
# ranks, one run each; rtol 1e-8 / 1e-5 / 1e-4 / 1e-3): Newton iterations 36 / 37 / 38 / 38, Krylov iterations
# 1797 / 941 / 711 / 479, whole solve 92 / 72 / 63 / 58 s, the figures to 1e-8 (Q: 1.5e-8 at 1e-4, a loose last
# solve: hence the tolerance follows the residual). With the forcing, 1e-4 -> 1e-3 (2 ranks, one run each, side by
# side): 36,331 / 72,461 / 162,021 / 507,916 dofs, Newton iterations 32 -> 34 / 34 -> 35 / 41 -> 45 / 46 -> 50,
# Krylov iterations 517 -> 402 / 511 -> 391 / 726 -> 614 / 877 -> 707, whole solve 11.0 -> 10.0 / 31.3 -> 27.9 /
# 165 -> 155 / 268 -> 233 s, the forces to 3e-8; 3e-3 at 72,461 dofs: 46 Newton iterations, no faster. The PETSc
# Eisenstat-Walker forcing with its cap at 1e-2 (inexact Newton) let a cap held by friction alone slide off its
# support: refused with friction on the capability grid.
KRYLOV_RTOL_MAX = 1e-3


class PressureUnknown:
    """What every surface with its pressure in the mixed unknown ``w`` shares: the pressure dofs off all
    such surfaces fixed to 0 (one Dirichlet condition, carried by the first surface built on ``w``).
    ``self.u`` is the mixed unknown (``self.w`` is two-body's mirror field). A vertex on two such surfaces has
    one pressure (their rows add)."""

    pinned_dofs = 0  # global number of pressure dofs fixed to 0 off the surfaces (set on the first surface)
    # Full semismooth Newton steps: the l2 line search damps the active-set changes (cylinders: 9 iterations
    # per step for c = 1e2 .. 1e4 with basic, 17-30 with l2; bt fails).
    solver_options = {"snes_linesearch_type": "basic"}
    # A direct solve (pc_type lu) becomes the exact additive field split (see the module docstring).
    direct_solver_options = {"pc_type": "fieldsplit", "pc_fieldsplit_type": "additive",
                             "fieldsplit_free_ksp_type": "preonly", "fieldsplit_free_pc_type": "lu",
                             "fieldsplit_free_pc_factor_mat_solver_type": "mumps",
                             "fieldsplit_pinned_ksp_type": "preonly", "fieldsplit_pinned_pc_type": "jacobi"}
    # The iterative solve (solver "iterative"): the same additive split, its free block preconditioned by the
    # Schur complement split of (displacement u, surface pressures p) (see the module docstring).
    iterative_solver_options = {
        "ksp_type": "fgmres", "ksp_rtol": 1e-8, "ksp_rtol_max": KRYLOV_RTOL_MAX, "ksp_max_it": 500,
        "ksp_gmres_restart": 100,
        "pc_type": "fieldsplit", "pc_fieldsplit_type": "additive",
        "fieldsplit_pinned_ksp_type": "preonly", "fieldsplit_pinned_pc_type": "jacobi",
        "fieldsplit_free_ksp_type": "preonly", "fieldsplit_free_pc_type": "fieldsplit",
        "fieldsplit_free_pc_fieldsplit_type": "schur", "fieldsplit_free_pc_fieldsplit_schur_fact_type": "upper",
        "fieldsplit_free_pc_fieldsplit_schur_precondition": "selfp",
        "fieldsplit_free_fieldsplit_u_ksp_type": "preonly", "fieldsplit_free_fieldsplit_u_pc_type": "gamg",
        "fieldsplit_free_fieldsplit_p_ksp_type": "preonly", "fieldsplit_free_fieldsplit_p_pc_type": "bjacobi"}
    # A linear material's displacement block changes from one iterate to the next only in the contact's rows: its
    # GAMG hierarchy, built at the first solve, serves every later one (set up again only on a new pattern).
    constant_bulk_solver_options = {"fieldsplit_free_fieldsplit_u_ksp_reuse_preconditioner": True}

    def _pressure_setup(self, w: fem.Function, facets: np.ndarray) -> None:
        if not is_mixed(w.function_space):
            raise ValueError(f"method {self.law.name!r} needs the mixed unknown of multipliers.unknown(...)")
        W = w.function_space
        self._on_surface = fem.locate_dofs_topological(W.sub(1), W.mesh.topology.dim - 1, facets)
        surfaces = w.__dict__.setdefault("_fc_pressure_surfaces", [])  # all multiplier surfaces on w
        surfaces.append(self)
        self._bcs = None

    @property
    def bcs(self) -> tuple:
        """``p = 0`` on the pressure dofs off every multiplier surface of ``w`` (first surface only)."""
        surfaces = self.u._fc_pressure_surfaces
        if surfaces[0] is not self:
            return ()
        if self._bcs is None:
            W = self.u.function_space
            Q, q_to_w = collapse(W.sub(1))
            q_to_w = np.asarray(q_to_w, dtype=np.int32)
            on = np.unique(np.concatenate([c._on_surface for c in surfaces]))
            # and the components a surface found prescribed (friction: the support takes that force)
            prescribed = np.concatenate([getattr(c, "_prescribed", np.zeros(0, np.int32)) for c in surfaces])
            off_q = np.flatnonzero(~np.isin(q_to_w, on) | np.isin(q_to_w, prescribed)).astype(np.int32)
            order = np.argsort(q_to_w[off_q])
            off, off_q = q_to_w[off_q][order], off_q[order]
            if Q.dofmap.index_map_bs == 1 and Q.num_sub_spaces == 0:  # a pressure
                self._bcs = (fem.dirichletbc(fem.Constant(W.mesh, 0.0), off, W.sub(1)),)
            else:  # a traction vector: a zero Function on the collapsed space
                self._bcs = (fem.dirichletbc(fem.Function(Q), [off, off_q], W.sub(1)),)
            n_owned = W.dofmap.index_map.size_local * W.dofmap.index_map_bs
            self._pinned_owned = off[off < n_owned]
            self.pinned_dofs = W.mesh.comm.allreduce(len(self._pinned_owned))
        return self._bcs

    def field_split(self) -> list[tuple[str, PETSc.IS]] | None:
        """The linear solve's blocks as global index sets of ``w``'s owned dofs: ``("free", ...)`` (displacement
        and surface pressures) and ``("pinned", ...)`` (pressure dofs fixed to 0 off the surfaces); ``None`` on
        all but the first surface of ``w``, or when no dof is pinned anywhere."""
        if not self.bcs:
            return None
        if self.pinned_dofs == 0:
            return None
        W = self.u.function_space
        imap = W.dofmap.index_map
        n_owned = imap.size_local * W.dofmap.index_map_bs
        off = self._pinned_owned
        free = np.setdiff1d(np.arange(n_owned, dtype=np.int32), off)
        start = imap.local_range[0] * W.dofmap.index_map_bs
        comm = W.mesh.comm
        return [("free", PETSc.IS().createGeneral((free + start).astype(PETSc.IntType), comm=comm)),
                ("pinned", PETSc.IS().createGeneral((off + start).astype(PETSc.IntType), comm=comm))]

    def schur_split(self) -> tuple[list[tuple[str, PETSc.IS]], PETSc.NullSpace] | None:
        """The ``free`` block's two fields in the block's own numbering (each rank's owned free dofs in turn, in
        ``w``'s order): ``("u", ...)`` the displacement, ``("p", ...)`` the surface pressures; and the rigid-body
        modes of the displacement field (near-nullspace of its algebraic multigrid). None where
        :meth:`field_split` is None."""
        fields = self.field_split()
        if fields is None:
            return None
        W = self.u.function_space
        comm = W.mesh.comm
        imap = W.dofmap.index_map
        n_owned = imap.size_local * W.dofmap.index_map_bs
        start = imap.local_range[0] * W.dofmap.index_map_bs
        free = fields[0][1].getIndices() - start  # owned, local, sorted
        offset = comm.exscan(len(free)) or 0
        V, v_to_w = collapse(W.sub(0))
        v_to_w = np.asarray(v_to_w)
        owned = v_to_w < n_owned
        u_local = v_to_w[owned]
        order = np.argsort(u_local)
        u_local = u_local[order]
        is_u = np.searchsorted(free, u_local)
        is_p = np.setdiff1d(np.arange(len(free)), is_u)
        # near-nullspace: the rigid-body modes at the displacement dofs, in the u field's order
        bs = V.dofmap.index_map_bs
        node = np.flatnonzero(owned)[order]
        X = V.tabulate_dof_coordinates()[node // bs]
        comp = node % bs
        rotations = [(0, 1)] if bs == 2 else [(0, 1), (1, 2), (2, 0)]  # rotation in the (i, j) plane
        modes = np.zeros((bs + len(rotations), len(node)))
        for i in range(bs):  # translations
            modes[i][comp == i] = 1.0
        for k, (i, j) in enumerate(rotations):
            modes[bs + k] = np.where(comp == i, -X[:, j], np.where(comp == j, X[:, i], 0.0))
        vecs = []
        for m in modes:  # Gram-Schmidt
            v = PETSc.Vec().createWithArray(m.copy(), comm=comm)
            for w in vecs:
                v.axpy(-v.dot(w), w)
            v.normalize()
            vecs.append(v)
        nullspace = PETSc.NullSpace().create(vectors=vecs, comm=comm)
        iu = PETSc.IS().createGeneral((is_u + offset).astype(PETSc.IntType), comm=comm)
        # the components of a node next to each other (x, y): block size 2, so that the multigrid aggregates nodes
        paired = bool(len(node) % bs == 0 and np.all(comp.reshape(-1, bs) == np.arange(bs))
                      and np.all(node.reshape(-1, bs) // bs == (node[::bs] // bs)[:, None]))
        if comm.allreduce(paired, op=MPI.LAND):
            iu.setBlockSize(bs)
        return ([("u", iu),
                 ("p", PETSc.IS().createGeneral((is_p + offset).astype(PETSc.IntType), comm=comm))], nullspace)

    def _constraint(self, v: ufl.Argument) -> ufl.Form:
        """``-int C(p, g) q ds`` (vertex rule): the pressure rows, forces like the displacement rows."""
        C = self.law.complementarity(self.pressure, self.gap, self.params, ufl_ops())
        return -C * ufl.split(v)[1] * self.ds


class MultiplierContact(PressureUnknown, ContactSurface):
    """A contact surface (rigid obstacle) whose pressure (> 0 compression) is the second field of the mixed
    unknown ``w``; the results of :class:`~fenics_contact.contact.ContactSurface`, the force and the mean
    pressure with the quadrature of the work term (``quadrature``: ``nodal`` or ``simpson``).

    Args:
        w: the mixed unknown of :func:`unknown`.
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag: the contact boundary: a tag value, or a region name of ``facet_tags``.
        obstacle: the rigid :class:`Obstacle`.
        law: a :class:`LagrangeMultiplier` (or :class:`PenaltyMultiplier`).
        load: the load parameter ``t`` (a scalar ``Constant``); the obstacle moves by ``t * motion``.
        quadrature: ``nodal`` or ``simpson``.
        name: the surface's name, in messages and output.
    """

    def __init__(self, w: fem.Function, facet_tags, tag: int, obstacle: Obstacle, law: LagrangeMultiplier,
                 load: fem.Constant, quadrature: str = "nodal", name: str = "contact"):
        if quadrature not in ("nodal", "simpson"):
            raise ValueError(f"method {law.name!r} enforces the contact at the vertices; the pressure's work "
                             f"is integrated with quadrature 'nodal' or 'simpson', got {quadrature!r}")
        super().__init__(w, facet_tags, tag, obstacle, law, load, "nodal", name)
        self._pressure_setup(w, self.facets)
        self.work_quadrature = quadrature
        self.ds_work = contact_measure(w.function_space.mesh, facet_tags, tag, quadrature)
        # Figures with the quadrature of the work term, so that the contact force balances the loads.
        mesh = w.function_space.mesh
        self._force_forms = [fem.form(self.pressure * self.normal[i] * self.ring * self.ds_work)
                             for i in range(mesh.geometry.dim)]
        self._area_form = fem.form(self.ring * self.ds_work)
        self._mean_p_form = fem.form(self.pressure * self.ring * self.ds_work)

    def _pressure(self):
        return ufl.split(self.u)[1]

    def residual(self, v: ufl.Argument) -> ufl.Form:
        """``int p dg[v] ds_work - int C(p, g) q ds`` (``v`` the mixed test function; ``ds`` the vertex
        rule, ``ds_work`` the vertex rule or Simpson's)."""
        return self.pressure * ufl.derivative(self.gap, self.u, v) * self.ring * self.ds_work + self._constraint(v)


class TwoBodyMultiplier(PressureUnknown, TwoBodySurface):
    """Two-body contact (:class:`~fenics_contact.twobody.TwoBodySurface`) with the slave pressure (> 0
    compression) in the mixed unknown: nodal Signorini conditions of the slave vertices against the current
    master facets; the results of the two-body surface, the pressure the unknown's.

    Args:
        args: the arguments of :class:`~fenics_contact.twobody.TwoBodySurface`, in its order; ``u`` is the mixed
            unknown of :func:`unknown`, ``law`` a :class:`~fenics_contact.laws.LagrangeMultiplier`.
        kwargs: its keyword arguments.
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._pressure_setup(self.u, self.facets)

    def _pressure(self):
        return ufl.split(self.u)[1]  # p = 0 where unpaired: the gap is then -open_gap (open)

    def residual(self, v):
        """``weight int p dg/du[v] ds_work - int C(p, g) q ds``; the master part is ``add_residual``."""
        return (self.weight * self.ring * self.pressure * ufl.derivative(self.gap, self.u, v) * self.ds_work
                + self._constraint(v))

    def _point_pressure(self, g):
        """The pressure unknown at the slave points: P1, so linear along a quadratic facet (the middle
        node gets the mean of the ends)."""
        sd, Wp = self.slave_data, self.u.function_space.sub(1)
        loc = sd.vertex_local if self.quadratic else sd.local
        dofs = np.array([Wp.dofmap.cell_dofs(c)[lo] for c, lo in zip(sd.cells, loc)],
                        dtype=np.int32).reshape(-1, loc.shape[1])
        if not len(dofs):
            return np.zeros_like(g)
        pv = self.u.x.array[dofs]
        if self.quadratic:
            return np.stack([pv[:, 0], 0.5 * (pv[:, 0] + pv[:, 1]), pv[:, 1]], axis=1)
        return np.einsum("qk,fk->fq", self.B, pv)
