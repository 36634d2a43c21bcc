"""Method ``coulomb`` between two bodies: the step solver of :class:`~.two_body_surface.CondensedTwoBody`.

With the fixed pairing of the surface (master facet, weights ``N_ik``, normal ``n_i``, tangent ``t_i``, reference
distance ``d0_i`` of slave vertex ``i``): relative displacement ``w_i = u_s,i - sum_k N_ik u_m(i,k)``, distance
``d_i = d0_i + n_i . w_i`` (>= 0 open), slip increment ``s_i = t_i . (w_i - w_i(previous converged step))``,
all linear in ``u``. Condensed dofs: the free components of the paired slave vertices and of the vertices of the
master facets they are paired with (a prescribed component enters ``w`` as data). The contact force of the
master on slave vertex ``i`` is ``p_i n_i + q_i t_i``, its reaction ``-N_ik (p_i n_i + q_i t_i)`` on master vertex
``k``; with ``R = S u_c + r(t)`` the force the contact dofs need, ``p_i = n_i . R_s,i`` and ``q_i = t_i .
R_s,i`` are eliminated and the unknowns are ``u_c`` only: per paired slave vertex the two Alart-Curnier rows
(:mod:`.newton`) in ``(p_i, q_i, d_i, s_i)``, per free master component the linear row ``R_m + sum_i N_im (p_i
n_i + q_i t_i) = 0`` (action and reaction: the contact forces on the two bodies are equal and opposite by
construction); as many rows as unknowns. A paired slave vertex with one prescribed component (a symmetry plane
across the surface) carries no friction (``q_i = 0``; ``p_i`` from its free component); a prescribed normal
motion is refused. ``n_c`` = both surfaces' contact dofs (the mindlin scene: 568 for 14 200 dofs).
"""
from __future__ import annotations

import numpy as np
from scipy import sparse

from .disk import disk_rows
from .fixedrows import FixedRowsSolve, master_elimination
from .operator import CondensedStiffness
from .rowupdate import RowUpdatedSolve
from .states import OPEN, classify
from .step import CondensedStepSolver
from .two_body_surface import CondensedTwoBody

__all__ = ["CondensedTwoBodyCoulomb"]


class CondensedTwoBodyCoulomb(CondensedStepSolver):
    """Signorini contact with Coulomb friction between two linear-elastic bodies (small sliding), solved exactly on
    the system condensed onto both surfaces' contact dofs (see the module): the problem's step solver
    (``ContactProblem(..., step_solver=CondensedTwoBodyCoulomb(contact))``). ``max_it`` semismooth Newton
    iterations at most per try, converged at the relative residual ``tol``.

    Args:
        contact: the :class:`CondensedTwoBody`.
        max_it: semismooth Newton iterations per try.
        tol: the relative residual at convergence.
    """

    def __init__(self, contact: CondensedTwoBody, max_it: int = 50, tol: float = 1e-11):
        if not isinstance(contact, CondensedTwoBody):
            raise ValueError(f"contact must be the CondensedTwoBody of method 'coulomb', got {type(contact).__name__}")
        super().__init__(contact.comm, max_it, tol)
        self.contact, self.mu = contact, contact.mu

    def _contact_dofs(self, problem, K: CondensedStiffness) -> np.ndarray:
        """The free components of every paired slave vertex, then those of the vertices of the master facets they
        are paired with (each sorted by position). A prescribed component (Dirichlet) is not condensed: its
        value enters the relative displacement as data. A paired slave vertex with prescribed components (a
        symmetry plane across the contact surface) slips only in its free directions (see the module); one whose
        free components cannot carry its normal motion is refused."""
        c, dim = self.contact, self.contact.dim
        ps = np.flatnonzero(c.paired)
        if not len(ps):
            raise ValueError(f"{c.name}: no slave vertex is within the search radius {c.radius:g} of the master "
                             "surface (nothing to condense)")
        sdofs = (dim * c.slave_dofs[ps][:, None] + np.arange(dim)).astype(np.int64)  # (ns, dim) global components
        sfree = ~np.isin(sdofs, K.dir_all)
        bad = np.linalg.norm(np.where(sfree, c.normal[ps], 0.0), axis=1) <= 0.1
        if bad.any():
            i = ps[np.flatnonzero(bad)[0]]
            raise ValueError(f"{c.name}: slave vertex at {tuple(np.round(c.X[i], 12))} is within the search radius "
                             "of the master and its normal motion is prescribed (Dirichlet): method 'coulomb' needs "
                             "a free normal component at every paired slave vertex (or pass a smaller radius)")
        mverts, minv = np.unique(c.master_facets[c.facet[ps]], return_inverse=True)  # global block dofs
        minv = minv.reshape(-1, dim)
        pos = np.zeros((len(mverts), dim))  # master vertex positions, for a partition-independent order
        pos[minv.ravel()] = c.master_X[c.facet[ps]].reshape(-1, dim)
        morder = np.lexsort(np.round(pos, 12).T[::-1])
        rank = np.empty(len(mverts), np.int64)
        rank[morder] = np.arange(len(mverts))
        mverts, minv = mverts[morder], rank[minv]
        mdofs = (dim * mverts[:, None] + np.arange(dim)).astype(np.int64)  # (nm, dim)
        mfree = ~np.isin(mdofs, K.dir_all)
        self._maps(ps, sdofs, sfree, mdofs, mfree, minv)
        return np.concatenate([sdofs[sfree], mdofs[mfree]])

    def _tangents(self, ps: np.ndarray, sfree: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Tangent basis (ns, m, dim) of the paired slave vertices ``ps`` and the directions each has (ns, m):
        the surface's basis where every component is free; with one prescribed component ``e_P`` in 3D the one
        direction ``e_P x n`` (normalized); none in 2D with one prescribed component or in 3D with two."""
        c, dim = self.contact, self.contact.dim
        T = c.tangent[ps].copy()
        nfree = sfree.sum(axis=1)
        has = np.repeat((nfree == dim)[:, None], dim - 1, axis=1)
        if dim == 3:
            one = np.flatnonzero(nfree == 2)
            if len(one):
                eP = (~sfree[one]).astype(float)
                t = np.cross(eP, c.normal[ps[one]])
                T[one, 0] = t / np.linalg.norm(t, axis=1)[:, None]
                T[one, 1] = 0.0
                has[one, 0] = True
        T[~has] = 0.0
        return T, has

    def _maps(self, ps: np.ndarray, sdofs: np.ndarray, sfree: np.ndarray, mdofs: np.ndarray, mfree: np.ndarray,
              minv: np.ndarray) -> None:
        """The linear maps of the rows from the condensed dofs: the paired slave vertices ``ps``, their global
        components ``sdofs`` (ns, dim) (``sfree``: not prescribed), the master vertices' ``mdofs`` (nm, dim)
        (``mfree``) and the master vertex of each paired vertex's facet corners ``minv`` (ns, dim). The maps
        have a few entries per row: they are formed sparse, from their entries (a dense product costs
        ``O(n_c^3)``, as much as the semismooth Newton's solves)."""
        c, dim = self.contact, self.contact.dim
        ns = len(ps)
        n, N = c.normal[ps], c.N[ps]
        T, has = self._tangents(ps, sfree)
        m = dim - 1
        # Positions in u_c (-1: prescribed) and in the list of prescribed components (-1: free).
        nsf = int(sfree.sum())
        scol, mcol = np.full(sdofs.shape, -1, np.int64), np.full(mdofs.shape, -1, np.int64)
        scol[sfree], mcol[mfree] = np.arange(nsf), nsf + np.arange(int(mfree.sum()))
        nc = nsf + int(mfree.sum())
        self._presc = np.concatenate([sdofs[~sfree], mdofs[~mfree]])  # values from the load mode u_0(t)
        npc = len(self._presc)
        spc, mpc = np.full(sdofs.shape, -1, np.int64), np.full(mdofs.shape, -1, np.int64)
        spc[~sfree] = np.arange(int((~sfree).sum()))
        mpc[~mfree] = int((~sfree).sum()) + np.arange(int((~mfree).sum()))
        self._ps, self._ns, self._nc, self._T, self._has = ps, ns, nc, T, has
        # w_i = u_s,i - sum_k N_ik u_m(i,k): entries (vertex i, component j, coefficient, column in u_c or in the
        # prescribed values, free or not), the slave's own component then each master corner's.
        rows = np.arange(ns)
        vi = np.concatenate([np.repeat(rows, dim)] + [np.repeat(rows, dim)] * dim)
        comp = np.tile(np.arange(dim), (dim + 1) * ns)
        coef = np.concatenate([np.ones(ns * dim)] + [np.repeat(-N[:, k], dim) for k in range(dim)])
        mk = minv.T  # (dim corners, ns)
        free = np.concatenate([sfree.ravel()] + [mfree[mk[k]].ravel() for k in range(dim)])
        col = np.concatenate([np.where(sfree, scol, spc).ravel()]
                             + [np.where(mfree[mk[k]], mcol[mk[k]], mpc[mk[k]]).ravel() for k in range(dim)])

        def project(vectors: np.ndarray, on: np.ndarray, width: int) -> sparse.csr_matrix:
            """``sum_j vectors[i, ..., j] w_i,j``, row ``r ns + i`` for the ``r``-th vector of vertex ``i``, over
            the entries ``on``: (vectors per vertex * ns, width), duplicates summed."""
            per = vectors.reshape(ns, -1, dim)
            r = per.shape[1]
            val = per[vi[on], :, comp[on]] * coef[on, None]  # (entries, r)
            out = sparse.coo_matrix((val.T.ravel(), (np.add.outer(np.arange(r) * ns, vi[on]).ravel(),
                                                     np.tile(col[on], r))), shape=(r * ns, width))
            return out.tocsr()

        self._sGn, self._sGt = project(n, free, nc), project(T, free, nc)  # (ns, nc), (m ns, nc)
        self._Pn = project(n, ~free, npc).toarray()
        self._Pt = project(T, ~free, npc).toarray().reshape(m, ns, npc).transpose(1, 0, 2)  # (ns, m, n_presc)
        # Contact forces from R (force f_i = p_i n_i + T_i q_i, its free components R_s,i): the tangents lie in
        # the free components and are orthogonal to n, so p_i = n_F . R_s,i / |n_F|^2 (n_F: n's free
        # components; n_F = n when all are free) and q_i = T_i R_s,i. Maps (ns, nc) and (m ns, nc).
        nF = np.where(sfree, n, 0.0)
        nF /= np.einsum("ij,ij->i", nF, nF)[:, None]
        si, sj = np.nonzero(sfree)
        self._sNn = sparse.csr_matrix((nF[si, sj], (si, scol[si, sj])), shape=(ns, nc))
        self._sNt = sparse.csr_matrix((T[si, :, sj].T.ravel(), (np.add.outer(np.arange(m) * ns, si).ravel(),
                                                                np.tile(scol[si, sj], m))), shape=(m * ns, nc))
        # Master rows: R_m + sum_i N_im f_i = 0 for each free master component (action and reaction), with
        # f_i,j = sum_j' (n_i,j nF_i,j' + T_i,j . T_i,j') R_s,i,j' over the free j'.
        coupling = np.einsum("ij,ik->ijk", n, nF) + np.einsum("imj,imk->ijk", T, np.where(sfree[:, None], T, 0.0))
        i, k, j, jj = (a.ravel() for a in np.meshgrid(rows, np.arange(dim), np.arange(dim), np.arange(dim),
                                                        indexing="ij"))
        on = mfree[minv[i, k], j] & sfree[i, jj]
        i, k, j, jj = i[on], k[on], j[on], jj[on]
        nmf = int(mfree.sum())
        self._sM = sparse.csr_matrix((np.concatenate([np.ones(nmf), N[i, k] * coupling[i, j, jj]]),
                                      (np.concatenate([np.arange(nmf), mcol[minv[i, k], j] - nsf]),
                                       np.concatenate([mcol[mfree], scol[i, jj]]))), shape=(nmf, nc))
        self._d0 = c.d0[ps]
        self._ref = np.zeros((ns, m))  # T . w at the last converged step
        self._w0n, self._w0t = np.zeros(ns), np.zeros((ns, m))
        self._Gn, self._Gt = self._sGn.toarray(), self._sGt.toarray()  # dense too: the Jacobian's rows copy them
        self._nsf = nsf  # u_c = (u_s, u_m): the slave dofs first
        self._blocks_of = None  # the S the Jacobian's fixed blocks were formed with
        self._jacobian = None  # the last Jacobian and its rows' coefficients (c, active, coef, J)

    def _step_data(self) -> None:
        """The prescribed components' values at the step (read from the load mode ``u_0(t)``), the Jacobian's
        fixed blocks and the solver of the Newton systems (formed again only when S has been condensed again)."""
        vals = self.K.values(self._presc, self.K.x)
        self._w0n, self._w0t = self._Pn @ vals, self._Pt @ vals
        if self._blocks_of is not self.S:
            self._PnS, self._PtS, self._MS = (np.asarray(m @ self.S) for m in (self._sNn, self._sNt, self._sM))
            eliminated = master_elimination(self.S, self._MS, self._nsf)
            self.linear = RowUpdatedSolve() if eliminated is None else FixedRowsSolve(*eliminated)
            self._blocks_of = self.S
            self._jacobian = None

    def _by_vertex(self, v: np.ndarray) -> np.ndarray:
        """(m ns,) direction by direction -> (ns, m)."""
        return v.reshape(-1, self._ns).T

    def _kinematics(self, uc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distance ``d`` (> 0 open) (ns,) and ``T . w`` (ns, m) of every paired slave vertex at ``uc``."""
        return self._d0 + self._sGn @ uc + self._w0n, self._by_vertex(self._sGt @ uc) + self._w0t

    def _residual(self, uc: np.ndarray, t: float, c: float):
        """Alart-Curnier rows of the slave vertices (normal, tangential direction by direction) and the master
        rows; generalized Jacobian; state per slave vertex (0 open, 1 slip, in 2D -1 for a slip along -t, 2
        stick); ``R``. The Jacobian is the previous call's array with only the rows whose coefficients changed
        formed again (a row of a sticking or open vertex stays; the semismooth Newton's solver reads it before
        the next call, told which rows were formed)."""
        ns, has = self._ns, self._has
        R = self.S @ uc + self._r
        p, q = self._sNn @ R, self._by_vertex(self._sNt @ R)
        d, tw = self._kinematics(uc)
        lam = p - c * d
        active = lam > 0
        Ft, A, B, g, stick, e = disk_rows(q, tw - self._ref, lam, self.mu, c, has)
        j, v = np.nonzero(has.T)  # tangential rows, direction by direction: (direction, vertex)
        F = np.concatenate([np.where(active, c * d, p), Ft[v, j], self._sM @ R])
        # Each row's coefficients: normal rows c Gn (active) or PnS; tangential rows dF_t = A dq + B ds + g dlam
        # (dq_k = PtS[k ns + v], ds_k = Gt[k ns + v], dlam = PnS - c Gn).
        coef = np.concatenate([A[v, j], B[v, j], g[v, j][:, None]], axis=1)
        cached = self._jacobian
        if cached is None or cached[0] != c or cached[1].shape != active.shape or cached[2].shape != coef.shape:
            nt = len(v)
            J = np.empty((ns + nt + self._MS.shape[0], len(uc)))
            J[ns + nt:] = self._MS
            normal, tangential = np.arange(ns), np.arange(nt)
        else:
            J = cached[3]
            normal = np.flatnonzero(active != cached[1])
            tangential = np.flatnonzero(np.any(coef != cached[2], axis=1))
        if len(normal):
            J[normal] = self._PnS[normal]
            on = normal[active[normal]]
            J[on] = c * self._Gn_dense(on)
        if len(tangential):
            J[ns + tangential] = self._tangential_rows(tangential, v, coef, c)
        self.linear.touched(None if cached is None or J is not cached[3] else np.concatenate([normal, ns + tangential]))
        self._jacobian = (c, active, coef, J)
        state = np.where(active, np.where(stick, 2, 1), 0)
        if has.shape[1] == 1:  # 2D: the slip direction too
            state = np.where(active & ~stick & has[:, 0] & (e[:, 0] < 0), -1, state)
        return F, J, state, R

    def _tangential_rows(self, rows: np.ndarray, v: np.ndarray, coef: np.ndarray, c: float) -> np.ndarray:
        """The Jacobian's tangential ``rows`` (dense, (rows, n_c)) from their coefficients ``coef`` (A (m), B (m),
        g per row; ``v`` the vertex of every tangential row)."""
        ns, m = self._ns, self._has.shape[1]
        vr, cr = v[rows], coef[rows]
        out = np.zeros((len(rows), self._PnS.shape[1]))
        for k in range(m):  # A and B vanish in a direction a vertex lacks (its PtS and Gt rows are zero too)
            a, b = cr[:, k], cr[:, m + k]
            on = np.flatnonzero(a)
            if len(on):
                out[on] += a[on, None] * self._PtS[k * ns + vr[on]]
            on = np.flatnonzero(b)
            if len(on):
                out[on] += b[on, None] * self._Gt[k * ns + vr[on]]
        on = np.flatnonzero(cr[:, 2 * m])
        if len(on):  # slipping: the disk's radius follows lam
            out[on] += cr[on, 2 * m, None] * (self._PnS[vr[on]] - c * self._Gn_dense(vr[on]))
        return out

    def _Gn_dense(self, which: np.ndarray) -> np.ndarray:
        """Rows ``which`` (a mask or indices) of the normal kinematic map, dense."""
        return self._Gn[which]

    def _set_output(self, uc: np.ndarray, t: float) -> None:
        """Nodal forces, gaps (> 0 penetration; ``-radius`` unpaired), states and slip increments of every slave
        vertex to the surface."""
        c, dim = self.contact, self.contact.dim
        R = self.S @ uc + self._r
        p, q = self._sNn @ R, self._by_vertex(self._sNt @ R)
        d, tw = self._kinematics(uc)
        nv = len(c.X)
        fn, ft, gap, slip = np.zeros(nv), np.zeros((nv, dim)), np.full(nv, -c.radius), np.zeros((nv, dim))
        ps = self._ps
        fn[ps], gap[ps] = p, -d
        ft[ps] = np.einsum("im,imj->ij", q, self._T)
        slip[ps] = np.einsum("im,imj->ij", tw - self._ref, self._T)
        state = np.full(nv, OPEN)
        state[ps] = classify(p, np.linalg.norm(q, axis=1), self.mu)
        c.set_solution(fn, ft, gap, state, slip)

    def _slip_reference(self, uc: np.ndarray) -> np.ndarray:
        return self._kinematics(uc)[1]
