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

from .operator import CondensedStiffness
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
        value enters the relative displacement as data. A paired slave vertex with one prescribed component
        (a symmetry plane across the contact surface) carries no friction force (``q = 0``: its support takes
        the tangential force), ``p`` from its free component; two prescribed components are refused."""
        c = self.contact
        ps = np.flatnonzero(c.paired)
        if not len(ps):
            raise ValueError(f"{c.name}: no slave vertex is within the search radius {c.radius:g} of the master "
                             "surface (nothing to condense)")
        sdofs = (2 * c.slave_dofs[ps][:, None] + np.arange(2)).astype(np.int64)  # (ns, 2) global components
        sfree = ~np.isin(sdofs, K.dir_all)
        roller = sfree.sum(axis=1) == 1
        bad = ~sfree.all(axis=1) & ~(roller & (np.abs(np.where(sfree, c.normal[ps], 0.0)).sum(axis=1) > 0.1))
        if bad.any():
            i = ps[np.flatnonzero(bad)[0]]
            raise ValueError(f"{c.name}: slave vertex at {tuple(np.round(c.X[i], 12))} is within the search radius "
                             "of the master and its normal motion is prescribed (Dirichlet): method 'coulomb' needs "
                             "a free normal component at every paired slave vertex (or pass a smaller radius)")
        mverts, minv = np.unique(c.master_facets[c.facet[ps]], return_inverse=True)  # global block dofs
        minv = minv.reshape(-1, 2)
        pos = np.zeros((len(mverts), 2))  # master vertex positions, for a partition-independent order
        pos[minv.ravel()] = c.master_X[c.facet[ps]].reshape(-1, 2)
        morder = np.lexsort(np.round(pos, 12).T[::-1])
        rank = np.empty(len(mverts), np.int64)
        rank[morder] = np.arange(len(mverts))
        mverts, minv = mverts[morder], rank[minv]
        mdofs = (2 * mverts[:, None] + np.arange(2)).astype(np.int64)  # (nm, 2)
        mfree = ~np.isin(mdofs, K.dir_all)
        self._maps(ps, sdofs, sfree, roller, mdofs, mfree, minv)
        return np.concatenate([sdofs[sfree], mdofs[mfree]])

    def _maps(self, ps: np.ndarray, sdofs: np.ndarray, sfree: np.ndarray, roller: np.ndarray, mdofs: np.ndarray,
              mfree: np.ndarray, minv: np.ndarray) -> None:
        """The linear maps of the rows from the condensed dofs: the paired slave vertices ``ps``, their global
        components ``sdofs`` (ns, 2) (``sfree``: not prescribed; ``roller``: one prescribed), the master vertices'
        ``mdofs`` (nm, 2) (``mfree``) and the master vertex of each paired vertex's facet ends ``minv`` (ns, 2)."""
        c = self.contact
        ns = len(ps)
        n, t, N = c.normal[ps], c.tangent[ps], c.N[ps]
        # Positions in u_c (-1: prescribed) and in the list of prescribed components (-1: free).
        nsf = int(sfree.sum())
        scol, mcol = np.full(sdofs.shape, -1, np.int64), np.full(mdofs.shape, -1, np.int64)
        scol[sfree], mcol[mfree] = np.arange(nsf), nsf + np.arange(int(mfree.sum()))
        nc = nsf + int(mfree.sum())
        self._presc = np.concatenate([sdofs[~sfree], mdofs[~mfree]])  # values from the load mode u_0(t)
        spc, mpc = np.full(sdofs.shape, -1, np.int64), np.full(mdofs.shape, -1, np.int64)
        spc[~sfree] = np.arange(int((~sfree).sum()))
        mpc[~mfree] = int((~sfree).sum()) + np.arange(int((~mfree).sum()))
        self._ps, self._ns, self._nc, self._fric = ps, ns, nc, np.flatnonzero(~roller)
        # w_i = u_s,i - sum_k N_ik u_m(i,k) = Gw u_c + Pw u_presc: (ns, 2, nc) and (ns, 2, n_presc)
        Gw, Pw = np.zeros((ns, 2, nc)), np.zeros((ns, 2, len(self._presc)))
        rows = np.arange(ns)
        for j in range(2):
            f = sfree[:, j]
            Gw[rows[f], j, scol[f, j]] = 1.0
            Pw[rows[~f], j, spc[~f, j]] = 1.0
            for k in range(2):
                m = minv[:, k]
                f = mfree[m, j]
                np.add.at(Gw, (rows[f], j, mcol[m[f], j]), -N[f, k])
                np.add.at(Pw, (rows[~f], j, mpc[m[~f], j]), -N[~f, k])
        self._Gn, self._Gt = np.einsum("ij,ijc->ic", n, Gw), np.einsum("ij,ijc->ic", t, Gw)
        self._Pn, self._Pt = np.einsum("ij,ijc->ic", n, Pw), np.einsum("ij,ijc->ic", t, Pw)
        # Contact forces from R: p_i = n_i . R_s,i, q_i = t_i . R_s,i; a roller: p_i = R_s,i[free] / n_i[free],
        # q_i = 0. Rows of the maps (ns, nc).
        self._Nn, self._Nt = np.zeros((ns, nc)), np.zeros((ns, nc))
        for j in range(2):
            f = sfree[:, j] & ~roller
            self._Nn[rows[f], scol[f, j]] = n[f, j]
            self._Nt[rows[f], scol[f, j]] = t[f, j]
            f = sfree[:, j] & roller
            self._Nn[rows[f], scol[f, j]] = 1.0 / n[f, j]
        # Master rows: R_m + sum_i N_im (p_i n_i + q_i t_i) = 0 for each free master component (action and
        # reaction); for a slave vertex without a prescribed component p_i n_i + q_i t_i = R_s,i.
        self._M = np.zeros((int(mfree.sum()), nc))
        self._M[np.arange(self._M.shape[0]), mcol[mfree]] = 1.0
        for k in range(2):
            m = minv[:, k]
            for j in range(2):
                f = np.flatnonzero(mfree[m, j])
                np.add.at(self._M, mcol[m[f], j] - nsf,
                          N[f, k, None] * (n[f, j, None] * self._Nn[f] + t[f, j, None] * self._Nt[f]))
        self._d0 = c.d0[ps]
        self._ref = np.zeros(ns)  # t . w at the last converged step
        self._w0n, self._w0t = np.zeros(ns), np.zeros(ns)
        # The maps have a few entries per row: sparse products (the dense ones, O(n_c^3) each, cost as much as
        # the semismooth Newton's solves).
        self._sNn, self._sNt, self._sM = (sparse.csr_matrix(a) for a in (self._Nn, self._Nt, self._M))
        self._sGn, self._sGt = sparse.csr_matrix(self._Gn), sparse.csr_matrix(self._Gt)
        self._blocks_of = None  # the S the Jacobian's fixed blocks were formed with

    def _step_data(self) -> None:
        """The prescribed components' values at the step (read from the load mode ``u_0(t)``), the Jacobian's
        fixed blocks (formed again only when S has been condensed again)."""
        vals = self.K.values(self._presc, self.K.x)
        self._w0n, self._w0t = self._Pn @ vals, self._Pt @ vals
        if self._blocks_of is not self.S:
            self._PnS, self._PtS, self._MS = (np.asarray(m @ self.S) for m in (self._sNn, self._sNt, self._sM))
            self._blocks_of = self.S

    def _kinematics(self, uc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distance ``d`` (> 0 open) and ``t . w`` of every paired slave vertex at ``uc``."""
        return self._d0 + self._sGn @ uc + self._w0n, self._sGt @ uc + self._w0t

    def _residual(self, uc: np.ndarray, t: float, c: float):
        """Alart-Curnier rows of the slave vertices (normal, tangential) and the master rows; generalized
        Jacobian; state per slave vertex (0 open, +-1 slip and its direction, 2 stick); ``R``."""
        mu = self.mu
        R = self.S @ uc + self._r
        p, q = self._sNn @ R, self._sNt @ R
        d, tw = self._kinematics(uc)
        s = tw - self._ref
        PnS, PtS = self._PnS, self._PtS
        lam = p - c * d
        active = lam > 0
        bound = mu * np.maximum(lam, 0.0)
        qtr = q - c * s
        stick = active & (np.abs(qtr) <= bound)
        direction = np.sign(qtr)
        Fn = np.where(active, c * d, p)
        Ft = np.where(stick, c * s, q - bound * direction)
        fr = self._fric  # the vertices with a tangential row (not the rollers: q = 0 there)
        F = np.concatenate([Fn, Ft[fr], self._sM @ R])
        # J row by row into one array: normal rows, tangential rows of fr, master rows.
        ns, nf = len(p), len(fr)
        J = np.empty((ns + nf + self._MS.shape[0], len(uc)))
        Jn, Jt = J[:ns], J[ns:ns + nf]
        Jn[:] = PnS
        Jn[active] = c * self._Gn[active]
        Jt[:] = PtS[fr]
        slipping = np.flatnonzero(active[fr] & ~stick[fr])
        if len(slipping):
            v = fr[slipping]
            Jt[slipping] -= (mu * direction[v])[:, None] * (PnS[v] - c * self._Gn[v])
        sticking = np.flatnonzero(stick[fr])
        Jt[sticking] = c * self._Gt[fr[sticking]]
        J[ns + nf:] = self._MS
        state = active.astype(np.int64)
        state[fr] = np.where(active[fr], np.where(stick[fr], 2, np.where(direction[fr] < 0, -1, 1)), 0)
        return F, J, state, R

    def _set_output(self, uc: np.ndarray, t: float) -> None:
        """Nodal forces, gaps (> 0 penetration; ``-radius`` unpaired), states and slip increments of every slave
        vertex to the surface."""
        c = self.contact
        R = self.S @ uc + self._r
        p, q = self._sNn @ R, self._sNt @ R
        d, tw = self._kinematics(uc)
        nv = len(c.X)
        fn, ft, gap, slip = np.zeros(nv), np.zeros(nv), np.full(nv, -c.radius), np.zeros(nv)
        ps = self._ps
        fn[ps], ft[ps], gap[ps], slip[ps] = p, q, -d, tw - self._ref
        state = np.full(nv, OPEN)
        state[ps] = classify(p, q, self.mu)
        c.set_solution(fn, ft, gap, state, slip)

    def _slip_reference(self, uc: np.ndarray) -> np.ndarray:
        return self._kinematics(uc)[1]

