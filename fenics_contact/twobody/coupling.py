"""The coupling of the mirror fields to the master dofs, and its blocks in the global residual and Jacobian.

``I`` (:func:`interpolation_operator`) is the sparse operator (rows: mirror dofs, columns: global
displacement dofs) with ``w = I u``: a selection of master vertex values (nodal points) or its combination
with the inverse of the facet's Gauss-point interpolation (``gauss``: the mirror lives in DG1 whose trace has
one value per Gauss point). With the slave-side forms ``r_u = dP/du``, ``r_w = dP/dw`` and their derivatives
compiled once by FFCx (:class:`MirrorCoupling`), the contact residual and tangent on the global dofs are::

    R = r_u + I^T r_w,
    K = A_uu + A_uw I + I^T A_wu + I^T A_ww I        (MatMatMult, TransposeMatMult, PtAP)

``A_uu`` goes in the problem's own Jacobian form; the rest is added by the solver's hooks. Dirichlet dofs
(:func:`dirichlet_columns`) are dropped from the columns of ``I`` and the coupling forms are assembled with
the boundary conditions, so the constrained rows and columns stay the identity. A master facet owned by
another rank is just a column of ``I`` with a global index: PETSc moves the values. The global matrix gets
the coupling's extra sparsity by ``MatAXPY(DIFFERENT_NONZERO_PATTERN)`` only when the pairing changed since
the last Jacobian (:class:`JacobianPattern`; the pattern then only grows and the solver resets its
factorization); otherwise the pattern is reused. While the pairing (``I``) stays, the three products keep their
patterns too and only their values are computed (``MAT_REUSE_MATRIX``).

A block is assembled again only when the values of its form's inputs (:func:`~fenics_contact.form_inputs.form_inputs`)
changed, and its product only then or on a new ``I``: with small sliding (reference pairs and normals, a gap linear in
``u``) the master rows ``r_w`` are linear in the pressure alone, so ``A_wu`` changes only with the pairing and
``A_ww`` is zero (its product is left out); only ``A_uw`` (the constraint rows, through the active set) is made at
every Jacobian.
"""
from __future__ import annotations

import dolfinx.fem.petsc as fem_petsc
import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from ..compat import bc_dofs
from ..form_inputs import form_inputs, input_values, same_everywhere
from ..sparse import aij_matrix, widen
from .mirror import MirrorFields

__all__ = ["dirichlet_columns", "interpolation_operator", "MirrorCoupling", "JacobianPattern"]


def dirichlet_columns(V: fem.FunctionSpace, comm, bcs) -> np.ndarray:
    """Sorted global numbers (int64) of the unknowns of ``V`` fixed by the Dirichlet conditions ``bcs``, the
    same on every rank. Collective."""
    Vmap, bs = V.dofmap.index_map, V.dofmap.index_map_bs
    local = np.unique(np.concatenate([bc_dofs(b) for b in bcs])) if bcs else np.zeros(0, int)
    local = local[local < Vmap.size_local * bs]
    glob = Vmap.local_to_global(local // bs) * bs + local % bs if len(local) else np.zeros(0, np.int64)
    return np.unique(np.concatenate(comm.allgather(glob))).astype(np.int64)


def interpolation_operator(comm, mirror: MirrorFields, V: fem.FunctionSpace, facet: np.ndarray,
                           master_dofs: np.ndarray, dirichlet: np.ndarray) -> PETSc.Mat:
    """``I`` with ``w = I u``: rows the mirror dofs of the local slave points (owned or not: PETSc moves
    off-process rows), columns the global displacement dofs of their master facets' nodes.

    Args:
        facet: (nf, nq) each slave point's master facet, index into ``master_dofs`` (-1: unpaired, no entry).
        master_dofs: (n, nv, gdim) global displacement dofs of the received master facets.
        dirichlet: global dofs left out of the columns (:func:`dirichlet_columns`).
    """
    d, nv = mirror.gdim, mirror.nv
    bs = nv * d
    Wmap, Vmap = mirror.space.dofmap.index_map, V.dofmap.index_map
    Vbs = V.dofmap.index_map_bs
    sizes = ((Wmap.size_local * bs, Wmap.size_global * bs), (Vmap.size_local * Vbs, Vmap.size_global * Vbs))
    inverse_rule = mirror.points.from_points
    nn, nq = inverse_rule.shape
    # Entries (row, column, B^-1 weight) of every paired point, summed where two points of one mirror node share
    # a master vertex, Dirichlet columns dropped; rows of ghost slave facets are inserted by both ranks with
    # the same values (INSERT), PETSc moves the off-process ones.
    nf = facet.shape[0]
    f, a, q = (x.ravel() for x in np.meshgrid(np.arange(nf), np.arange(nn), np.arange(nq), indexing="ij"))
    m, w = facet[f, q], inverse_rule[a, q]
    keep = (m >= 0) & (w != 0.0)
    f, a, m, w = f[keep], a[keep], m[keep], w[keep]
    local = (np.arange(nv)[:, None] * d + np.arange(d)).ravel()
    rows = (mirror.global_nodes[f, a].astype(np.int64) * bs)[:, None] + local
    cols = master_dofs[m].reshape(len(m), nv * d).astype(np.int64)
    vals = np.broadcast_to(w[:, None], rows.shape)
    fac = np.broadcast_to(f[:, None], rows.shape)
    rows, cols, vals, fac = rows.ravel(), cols.ravel(), vals.ravel(), fac.ravel()
    if len(dirichlet):
        free = ~np.isin(cols, dirichlet)
        rows, cols, vals, fac = rows[free], cols[free], vals[free], fac[free]
    if len(rows):
        # Sum over the points of one facet; a mirror node shared by two slave facets gets the same row from
        # each (one insert, as INSERT_VALUES would leave it).
        key, inverse = np.unique(np.stack([rows, cols, fac]), axis=1, return_inverse=True)
        vals = np.bincount(inverse.ravel(), weights=vals)
        rc, first = np.unique(key[:2], axis=1, return_index=True)
        rows, cols, vals = rc[0], rc[1], vals[first]
    return aij_matrix(comm, sizes, rows, cols, vals, addv=PETSc.InsertMode.INSERT_VALUES)


class MirrorCoupling:
    """The contact's residual and tangent blocks through the mirror displacement ``w = I u``.

    Args:
        u: the problem's unknown.
        mirror: the mirror fields; ``mirror.displacement`` is ``w``.
        r_u: the contact residual on the unknown's test function (slave rows; multipliers: with the
            constraint rows).
        r_w: the contact residual on the mirror's test function (master rows, mapped by ``I^T``).
        seconds: the surface's timings; building ``I`` adds to ``coupling_s``.

    ``operator``: ``I`` of the last :meth:`rebuild` (None before).
    """

    def __init__(self, u: fem.Function, mirror: MirrorFields, r_u: ufl.Form, r_w: ufl.Form, seconds):
        self.comm, self.V, self.mirror, self._u = u.function_space.mesh.comm, u.function_space, mirror, u
        w = mirror.displacement
        du, dw = ufl.TrialFunction(self.V), ufl.TrialFunction(mirror.space)
        self._r_w = fem.form(r_w)
        blocks = (ufl.derivative(r_u, w, dw), ufl.derivative(r_w, u, du), ufl.derivative(r_w, w, dw))
        self._forms = tuple(fem.form(a) for a in blocks)  # A_uw, A_wu, A_ww
        self._inputs = [form_inputs(a) for a in blocks]
        self._seconds = seconds
        self.operator: PETSc.Mat | None = None
        self._blocks: tuple[PETSc.Mat, PETSc.Mat, PETSc.Mat] | None = None  # A_uw, A_wu, A_ww (matrix)
        self._values: list = [None, None, None]  # each block's input values when last assembled (None: assemble)
        # A block that has no inputs and assembled to zero (A_ww with small sliding): its product is left out
        self._zero = [False, False, False]
        # (I, A_uw I, I^T A_wu, I^T A_ww I (None: a zero block's)) of the last Jacobian: kept while I (the pairing)
        # stays
        self._products: tuple | None = None
        self._tmp: PETSc.Vec | None = None

    def rebuild(self, facet: np.ndarray, master_dofs: np.ndarray, dirichlet: np.ndarray) -> None:
        """A new ``I`` for a pairing (arguments of :func:`interpolation_operator`). Collective."""
        with self._seconds.measure("coupling_s"):
            operator = interpolation_operator(self.comm, self.mirror, self.V, facet, master_dofs, dirichlet)
            self._destroy_products()
            if self.operator is not None:
                self.operator.destroy()
            self.operator = operator

    def add_residual(self, b: PETSc.Vec) -> None:
        """``b += I^T r_w`` (owned entries; before boundary conditions are set)."""
        rw = fem_petsc.assemble_vector(self._r_w)
        rw.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        if self._tmp is None:
            self._tmp = b.duplicate()
        self.operator.multTranspose(rw, self._tmp)
        b.axpy(1.0, self._tmp)
        rw.destroy()

    def matrices(self, bcs: list) -> tuple[PETSc.Mat, ...]:
        """``A_uw I``, ``I^T A_wu`` and ``I^T A_ww I`` (Dirichlet rows and columns zero; a zero block's product left
        out): the coupling's matrix as a sum, valid until the next call (the caller does not destroy them). Added
        to the Jacobian one by one, not summed first: only ``A_uw I`` changes from one iterate to the next with
        small sliding, and a sum would copy the others every time. ``bcs``: the same conditions at every call."""
        # The three blocks' patterns depend on the slave facets only: made once, not per Jacobian (their rows span
        # the whole mirror space, nv gdim values per vertex: each build allocated 0.16 GB at 4e5 dofs).
        if self._blocks is None:
            self._blocks = tuple(fem_petsc.create_matrix(a) for a in self._forms)
        fresh = [self._assemble(i, b) for i, b in enumerate((bcs, bcs, []))]
        A_uw, A_wu, A_ww = self._blocks
        op = self.operator
        if self._products is not None and self._products[0] is op:
            # the same pairing: the products' patterns hold, only the values of those of new blocks are computed
            # (MAT_REUSE_MATRIX)
            _, C1, C2, C3 = self._products
            if fresh[0]:
                A_uw.matMult(op, result=C1)
            if fresh[1]:
                op.transposeMatMult(A_wu, result=C2)
            if fresh[2] and C3 is not None:
                A_ww.PtAP(op, result=C3)
        else:
            self._destroy_products()
            C1, C2 = A_uw.matMult(op), op.transposeMatMult(A_wu)
            C3 = None if self._zero[2] else A_ww.PtAP(op)
            self._products = (op, C1, C2, C3)
        return tuple(m for m in self._products[1:] if m is not None)

    def _assemble(self, i: int, bcs: list) -> bool:
        """Assemble block ``i`` unless its inputs have the values it was last assembled with. Returns True if it was
        assembled. Collective."""
        now = input_values(self._inputs[i], self._u)
        if same_everywhere(self.comm, now, self._values[i]):
            return False
        M = self._blocks[i]
        M.zeroEntries()
        fem_petsc.assemble_matrix(M, self._forms[i], bcs=bcs)
        M.assemble()
        self._values[i] = now
        constant = not any(self._inputs[i])  # no Constant, no Function: the same matrix for good
        self._zero[i] = constant and M.norm(PETSc.NormType.INFINITY) == 0.0
        return True

    def _destroy_products(self) -> None:
        if self._products is not None:
            for m in self._products[1:]:
                if m is not None:
                    m.destroy()
        self._products = None


class JacobianPattern:
    """Whether the contact block's nonzero pattern changed since it was last added to the Jacobian.

    ``version`` counts the pattern changes (a pairing change, a new problem); ``merged`` is the version last
    added to a Jacobian by :meth:`add`; ``seen`` holds (values zero) the union of every pattern added, which the
    Jacobian's pattern holds beyond the bodies' (it only grows): :meth:`state` and :meth:`restore` carry it over
    a checkpoint, so that a restarted run widens its Jacobian alike (a direct solver's pivot order follows the
    pattern, explicit zeros included)."""

    def __init__(self):
        self.version = 0
        self.merged = -1
        self.seen: PETSc.Mat | None = None

    def changed(self) -> bool:
        """True when the next :meth:`add` rebuilds the Jacobian's pattern."""
        return self.merged != self.version

    def add(self, A: PETSc.Mat, C: tuple[PETSc.Mat, ...]) -> bool:
        """``A += sum(C)`` (the matrices stay the caller's), one after the other, on every call alike: the same
        bits whether the pattern was rebuilt or not. Returns True when ``A``'s nonzero pattern was rebuilt."""
        rebuild = self.changed()
        if rebuild:  # A's pattern widened once by the union of C's (values zero): A copied once
            union = C[0].duplicate(copy=True)
            for m in C[1:]:
                union.axpy(1.0, m, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
            union.zeroEntries()
            if self.seen is not None:
                union.axpy(1.0, self.seen, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
                self.seen.destroy()
            widen(A, union)
            self.seen = union
        for m in C:
            A.axpy(1.0, m, structure=PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
        self.merged = self.version
        return rebuild

    def state(self) -> dict | None:
        """``seen`` as this rank's rows: sizes, row offsets and global columns (None before the first :meth:`add`)."""
        if self.seen is None:
            return None
        indptr, cols, _ = self.seen.getValuesCSR()
        return {"sizes": self.seen.getSizes(), "start": self.seen.getOwnershipRange()[0], "indptr": indptr.copy(),
                "cols": cols.copy()}

    def restore(self, state: dict | None, comm) -> None:
        """Take ``seen`` from a :meth:`state` where none is known yet (a fresh surface, restarted from a checkpoint;
        a step cut back within a run keeps its own, which holds the older one). Collective."""
        if not comm.allreduce(int(self.seen is None and state is not None), op=MPI.MIN):
            return
        rows = state["start"] + np.repeat(np.arange(len(state["indptr"]) - 1), np.diff(state["indptr"]))
        self.seen = aij_matrix(comm, state["sizes"], rows, state["cols"], np.zeros(len(rows)))
        self.merged = -1  # the next add widens the Jacobian by it
