"""What a bulk whose Jacobian does not depend on the displacement (a linear material) keeps between iterates: its
Jacobian matrix (:class:`KeptJacobian`), and with it its residual as a product (:class:`AffineResidual`)."""
from __future__ import annotations

import dolfinx.fem.petsc as fem_petsc
import numpy as np
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from .compat import apply_lifting, assemble_matrix, create_vector, set_bc
from .form_inputs import input_values, same_everywhere
from .sparse import KEPT_ATTRIBUTES

__all__ = ["BULK_PATTERN", "KeptJacobian", "AffineResidual"]

# The PETSc attributes (kept by sparse.widen) of a matrix the kept matrix was last added into (KeptJacobian's mark)
# and of one made with the bulk form's pattern explicit, zeros included (ContactProblem.create_matrix of a multiplier)
_KEPT, BULK_PATTERN = KEPT_ATTRIBUTES


class KeptJacobian:
    """The matrix of the compiled Jacobian ``form``, kept while the values of its ``inputs``
    (:func:`~.form_inputs.form_inputs`) stay the same (a linear material's stiffness: the whole run); never kept if
    they include the displacement ``u``. ``create()`` makes an empty matrix of the problem's pattern."""

    def __init__(self, form: fem.Form, inputs: tuple[list, list], u: fem.Function, create):
        self.form, self.inputs, self.u = form, inputs, u
        self.create = create  # makes the kept matrix, with the pattern of the matrices it is added to
        self.matrix: PETSc.Mat | None = None
        self.reuse = True  # False: assembled every time (the cost of a fresh linear solve)
        self._values: list | None = None
        # Marks the matrices the form was assembled into since it was kept: an attribute of the PETSc object (a
        # handle, the address, may come back for a new matrix after one is destroyed, on one rank and not another).
        # A new mark for every kept matrix: the products made with the last one (AffineResidual) know it by it.
        self.mark = object()

    @property
    def constant(self) -> bool:
        """True if the matrix is the same at every iterate (its inputs leave out the displacement ``u``)."""
        return not any(f is self.u for f in self.inputs[1])

    def is_current(self) -> bool:
        """True when the kept matrix is that of the present values of the inputs (and :attr:`reuse` is on): made by
        the last :meth:`current` with these values. Collective."""
        if not (self.reuse and self.constant and self.matrix is not None):  # the same on every rank
            return False
        return same_everywhere(self.u.function_space.mesh.comm, input_values(self.inputs, self.u), self._values)

    def current(self, bcs: list, diagonal: float) -> PETSc.Mat | None:
        """The kept matrix for the present values of the inputs (Dirichlet rows and columns: ``diagonal`` times the
        identity), assembled if they changed; None while :attr:`reuse` is False or the form depends on ``u``.
        Collective."""
        if not (self.reuse and self.constant):
            return None
        if not self.is_current():
            if self.matrix is not None:
                self.matrix.destroy()
            self.matrix = self.create()
            assemble_matrix(self.matrix, self.form, bcs, diagonal)
            self.matrix.assemble()
            self._values, self.mark = input_values(self.inputs, self.u), object()
        return self.matrix

    def give_pattern(self, A: PETSc.Mat, bcs: list, diagonal: float) -> None:
        """Assemble the form into ``A`` (its values to be set again by the caller) where the kept matrix exists but
        ``A``'s pattern is not known to hold the form's (a matrix not yet assembled with it). :meth:`add` would
        otherwise assemble the form into ``A`` over the entries there already, a sum in another order than every
        later one's (``A``'s entries, then the kept matrix added): with it every Jacobian of a run has the same
        sums, and a run restarted from a checkpoint solves, bit for bit, what the uninterrupted run solved.
        Collective."""
        K = self.current(bcs, diagonal)
        holds = K is None or A.getAttr(_KEPT) is self.mark or A.getAttr(BULK_PATTERN) is True
        if not A.getComm().tompi4py().allreduce(int(holds), op=MPI.MIN):
            self.add(A, bcs, diagonal)

    def add(self, A: PETSc.Mat, bcs: list, diagonal: float) -> None:
        """Add the form's matrix (Dirichlet rows and columns: ``diagonal`` times the identity) into ``A`` and
        assemble ``A``: the kept matrix (:meth:`current`) where ``A``'s pattern holds the form's (made explicit with
        it, :data:`BULK_PATTERN`, or the kept matrix added into it before; a contact may have widened it), else
        assembled from the form; always assembled while :attr:`reuse` is False. Collective."""
        K = self.current(bcs, diagonal)
        holds = K is not None and (A.getAttr(_KEPT) is self.mark or A.getAttr(BULK_PATTERN) is True)
        if A.getComm().tompi4py().allreduce(int(holds), op=MPI.MIN):  # a matrix may be marked on one rank only
            A.assemble()
            info = PETSc.Mat.InfoType.GLOBAL_SUM  # the same choice on every rank (MatAXPY is collective)
            if A.getInfo(info)["nz_used"] != K.getInfo(info)["nz_used"]:
                # A's pattern is wider (a contact's entries): the kept matrix takes it, once, so that every later
                # sum is over the same pattern (an axpy of the value arrays, not an insertion row by row: 0.05 s
                # of every Jacobian at 1.6e5 dofs); its values copied into the wider pattern, not assembled again
                # (a bulk assembly: 2.5 s at 1.6e5 dofs). The old and the new kept matrix and A at once: no more
                # than A's own widening (sparse.widen) holds.
                wide = A.duplicate(copy=False)
                wide.setOption(PETSc.Mat.Option.NEW_NONZERO_LOCATIONS, False)
                wide.axpy(1.0, K, structure=PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
                K.destroy()
                self.matrix = K = wide
            A.axpy(1.0, K, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)
            A.setAttr(_KEPT, self.mark)
            return
        assemble_matrix(A, self.form, bcs, diagonal)
        A.assemble()
        if K is not None:  # A holds the form's pattern from now on (explicit: every entry of a cell is inserted)
            A.setAttr(_KEPT, self.mark)
            A.setAttr(BULK_PATTERN, True)


class AffineResidual:
    """The bodies' residual where their Jacobian does not depend on the displacement, and so the residual is affine
    in it: with ``K`` the kept Jacobian (Dirichlet rows and columns out), ``r0`` the residual at ``u = 0`` (the loads)
    and ``g`` the Dirichlet values, the assembled residual with its Dirichlet lifting is, on the free rows,
    ``K x + r0 + K_{:,D} g`` (``K_{:,D}``: the unconstrained Jacobian's columns at the Dirichlet dofs). ``r0`` and the
    lifting ``K_{:,D} g`` are assembled again only when the loads' or the Dirichlet values change; every iterate
    costs one matrix-vector product instead of an assembly over every cell and a lifting over every cell at a
    Dirichlet boundary. Only where ``K`` is current (:meth:`KeptJacobian.is_current`: the Jacobian assembled since
    its inputs last changed); elsewhere the residual is assembled: a Jacobian that changes with the load (a
    load-scaled spring) would otherwise be assembled again at every load a residual is evaluated at (the tangent
    predictor's three).

    Args:
        form: the compiled residual of the bodies (the loads included).
        inputs: its Constants and Functions (:func:`~.form_inputs.form_inputs`; ``u`` among them is left out).
        jacobian: its Jacobian's :class:`KeptJacobian`.
    """

    def __init__(self, form: fem.Form, inputs: tuple[list, list], jacobian: KeptJacobian):
        self.form, self.jacobian, self.u = form, jacobian, jacobian.u
        self.inputs = (inputs[0], [f for f in inputs[1] if f is not self.u])
        self._vectors: list[PETSc.Vec] | None = None  # r0, lifting, g, work
        self._r0_of: list | None = None
        self._lifting_of: tuple | None = None

    def ready(self) -> bool:
        """True when the residual is the product: the kept Jacobian current (:meth:`KeptJacobian.is_current`).
        Collective."""
        return self.jacobian.is_current()

    def add(self, b: PETSc.Vec, x: PETSc.Vec, bcs: list) -> None:
        """``b += K x + r0 + K_{:,D} g`` (owned entries; ``u`` is ``x``; the caller sets the Dirichlet rows). Only
        where :meth:`ready`. Collective."""
        comm = self.u.function_space.mesh.comm
        K = self.jacobian.matrix
        if self._vectors is None:
            self._vectors = [create_vector(self.form) for _ in range(4)]
        r0, lifting, g, work = self._vectors
        now = input_values(self.inputs, self.u)
        if not same_everywhere(comm, now, self._r0_of):
            saved = self.u.x.array.copy()
            self.u.x.array[:] = 0.0
            with r0.localForm() as local:
                local.set(0.0)
            fem_petsc.assemble_vector(r0, self.form)
            r0.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
            self.u.x.array[:] = saved
            self._r0_of = now
        with g.localForm() as local:
            local.set(0.0)
        set_bc(g, bcs)
        key = (self.jacobian.mark, g.array.copy())
        same = self._lifting_of is not None and key[0] is self._lifting_of[0] and np.array_equal(
            key[1], self._lifting_of[1])
        if not comm.allreduce(int(same), op=MPI.MIN):
            with lifting.localForm() as local:
                local.set(0.0)
            apply_lifting(lifting, self.jacobian.form, bcs, None, -1.0)  # += K_{:,D} g (x0 = 0)
            lifting.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
            self._lifting_of = key
        K.mult(x, work)
        b.axpy(1.0, work)
        b.axpy(1.0, r0)
        b.axpy(1.0, lifting)

    def destroy(self) -> None:
        """Destroy the vectors. Collective."""
        for v in self._vectors or []:
            v.destroy()
        self._vectors = None
