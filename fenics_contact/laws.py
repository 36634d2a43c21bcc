"""Normal contact laws: a gap (and a state) mapped to a contact pressure.

Sign convention, used everywhere in the suite: the normal gap ``g`` is
positive for **penetration** and negative for an open contact (the
cross-constraints paper's convention). The contact pressure ``F(g)`` is
positive in compression. The surface term built from a law is
``+ F(g) * dg[v]`` in the residual, with ``dg[v]`` the variation of ``g``.

A law is written once against a tiny operator namespace (``ops``) so that the
same formula gives UFL (for the forms) and NumPy (for tests and reports):
``ops.exp``, ``ops.max``, ``ops.min``. Parameters are held in a mapping
``c``: *scalars* (one value on the whole surface, ``Constant`` in the forms)
and *fields* (a value per contact quadrature point, ``Function`` in the
forms; augmentation updates them).
"""
from __future__ import annotations

import math
import types
from typing import Any, Mapping

import numpy as np

__all__ = [
    "NUMPY", "ufl_ops", "Formulation", "ContactLaw", "Penalty", "AugmentedLagrangian", "CrossConstraints",
    "NormalCompliance", "SnesVI", "ExactCoulomb", "LagrangeMultiplier", "PenaltyMultiplier", "Nitsche"
]

# Former names, kept for one release: each use warns (DeprecationWarning) and gives the new class.
DEPRECATED = {"Exact": "SnesVI", "Coulomb": "ExactCoulomb", "NitscheLaw": "Nitsche"}


def __getattr__(name: str):
    if name in DEPRECATED:
        import warnings

        warnings.warn(f"fenics_contact.laws.{name} is deprecated: use {DEPRECATED[name]}", DeprecationWarning,
                      stacklevel=2)
        return globals()[DEPRECATED[name]]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

NUMPY = types.SimpleNamespace(exp=np.exp, max=np.maximum, min=np.minimum)


def ufl_ops() -> types.SimpleNamespace:
    """The UFL operator namespace (imported lazily: laws work without UFL)."""
    import ufl

    return types.SimpleNamespace(exp=ufl.exp, max=ufl.max_value, min=ufl.min_value)


def _check_positive(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return value


def _check_nonnegative(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value >= 0.0):
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return value


class Formulation:
    """A contact method's choice and its parameters, for a method whose pressure is not a law of the gap alone
    (bounds, an unknown, the condensed reaction, a stress term): see :class:`ContactLaw` for those that are.

    ``name``: the method's name; ``scalars`` and ``fields``: the initial values of the parameters (``scalars``
    one value on the whole surface, ``fields`` one per contact point, updated by augmentation).
    """

    name = "formulation"
    scalars: dict[str, float]
    fields: dict[str, float]

    @property
    def method(self) -> str:
        """The name of the method (:mod:`fenics_contact.methods`) this law belongs to."""
        return self.name

    @property
    def has_friction(self) -> bool:
        """True when the law has a tangential part (friction)."""
        return False

    @property
    def augmentable(self) -> bool:
        return bool(self.fields)

    def augment_fields(self, g: Any, c: Mapping[str, Any], ops: Any = NUMPY) -> dict[str, Any]:
        """New field values (same keys as ``fields``) from the converged gap."""
        return {}

    def augment_scalars(self, c: Mapping[str, float]) -> dict[str, float]:
        """New scalar values after an augmentation."""
        return {}

    def parameters(self) -> dict[str, float]:
        return {**self.scalars, **self.fields}

    def values(self) -> dict[str, float]:
        """Initial parameter values as plain floats (for NumPy evaluation)."""
        return self.parameters()


class ContactLaw(Formulation):
    """A contact pressure as a law of the gap: ``force`` (F), ``potential`` (P, dP/dg = F), ``stiffness``
    (K = dF/dg), each written once against ``ops`` (UFL or NumPy). ``augment_fields`` / ``augment_scalars``
    return the new parameter values after a converged solve (``{}`` for a law without augmentation)."""

    name = "law"

    def force(self, g: Any, c: Mapping[str, Any], ops: Any = NUMPY) -> Any:
        """The contact pressure ``F(g)`` (> 0 in compression) at the gap ``g`` (> 0 penetration)."""
        raise NotImplementedError

    def potential(self, g: Any, c: Mapping[str, Any], ops: Any = NUMPY) -> Any:
        """The potential ``P(g)`` with ``dP/dg = F``."""
        raise NotImplementedError

    def stiffness(self, g: Any, c: Mapping[str, Any], ops: Any = NUMPY) -> Any:
        """The stiffness ``dF/dg``."""
        raise NotImplementedError


class Penalty(ContactLaw):
    """Penalty: ``P = K/2 <g>^2``, ``F = K <g>``, ``K`` for ``g > 0``. ``K`` in pressure per length.

    ``augmented=True``: the penalty method *with augmentation* of Zavarise et al. (1998, ring test),
    where the gap status decides: ``F = lam + K g`` on a closed point (``g > 0``), ``F = 0`` on an
    open one, and ``lam <- F(g)`` per point after a converged solve. Once ``lam > 0`` the force
    jumps from ``lam`` to 0 when the point opens (unlike ``auglag``'s continuous ``<lam + K g>``):
    the discontinuity that makes the Newton iteration cycle on the ring.

    Args:
        K: the penalty stiffness (pressure per length), > 0.
        augmented: the penalty method with augmentation (gap status decides), as above.
    """

    name = "penalty"

    def __init__(self, K: float, augmented: bool = False):
        self.scalars = {"K": _check_positive("penalty K", K)}
        self.fields = {"lam": 0.0} if augmented else {}

    def force(self, g, c, ops=NUMPY):
        if "lam" in c:
            return _heaviside(g, ops) * (c["lam"] + c["K"] * ops.max(g, 0.0))
        return c["K"] * ops.max(g, 0.0)

    def potential(self, g, c, ops=NUMPY):
        gp = ops.max(g, 0.0)
        return (c["lam"] * gp if "lam" in c else 0.0) + 0.5 * c["K"] * gp * gp

    def stiffness(self, g, c, ops=NUMPY):
        # Heaviside written through max/min so that it is exact 0 or 1 in
        # both back-ends: <g>/g is avoided (0/0 at g = 0). The jump of lam at g = 0 has no derivative.
        return c["K"] * _heaviside(g, ops)

    def augment_fields(self, g, c, ops=NUMPY):
        return {"lam": self.force(g, c, ops)} if "lam" in c else {}


class AugmentedLagrangian(ContactLaw):
    """Augmented Lagrangian (Uzawa): ``F = <lam + K g>``, then ``lam <- F(g)`` after each solve.

    ``lam`` is a pressure field on the contact surface (initially ``lam0``).

    Args:
        K: the penalty stiffness (pressure per length), > 0.
        lam0: the initial multiplier (pressure, > 0 compression).
    """

    name = "auglag"

    def __init__(self, K: float, lam0: float = 0.0):
        self.scalars = {"K": _check_positive("penalty K", K)}
        self.fields = {"lam": _check_nonnegative("initial multiplier lam0", lam0)}

    def force(self, g, c, ops=NUMPY):
        return ops.max(c["lam"] + c["K"] * g, 0.0)

    def potential(self, g, c, ops=NUMPY):
        # P such that dP/dg = F: (1/2K) <lam + K g>^2, shifted to P(0) = lam^2/(2K)
        s = ops.max(c["lam"] + c["K"] * g, 0.0)
        return s * s / (2.0 * c["K"])

    def stiffness(self, g, c, ops=NUMPY):
        return c["K"] * _heaviside(c["lam"] + c["K"] * g, ops)

    def augment_fields(self, g, c, ops=NUMPY):
        return {"lam": self.force(g, c, ops)}


class CrossConstraints(ContactLaw):
    """Cross-constraints law of Zavarise, Wriggers & Schrefler (1998).

    ``F_hat``: target pressure at ``g = 0`` (``>= 0``; ``0`` is the penalty
    method), ``K_hat``: stiffness at ``g = 0`` (``> 0``), ``a`` in ``[0, 1)``:
    shape parameter (``a > 0.1`` gives adhesion), ``tau >= 1``: factor on
    ``K_hat`` at each augmentation.

    Open side (``g <= 0``): ``F = F_hat/(1-a) (e^(A g) - a e^(A a g))`` with
    ``A = K_hat / ((1+a) F_hat)``. Closed side (``g > 0``): the parabola
    ``F = F_hat + K_hat g`` (stiffness capped at ``K_hat``). Exponents are
    evaluated at ``min(g, 0)`` and ``A`` is bounded, so nothing overflows and
    ``F_hat -> 0`` gives the penalty law without a division by zero.
    Augmentation: ``F_hat <- max(F(g), 0)`` per point, ``K_hat <- tau K_hat``.

    Args:
        K_hat: the stiffness at ``g = 0`` (pressure per length), > 0.
        F_hat: the target pressure at ``g = 0`` (pressure), >= 0; 0 is the penalty law.
        a: the shape parameter, in [0, 1).
        tau: the factor on ``K_hat`` at each augmentation, >= 1.
    """

    name = "cross"

    def __init__(self, K_hat: float, F_hat: float = 0.0, a: float = 0.0, tau: float = 1.0):
        K_hat = _check_positive("cross-constraints K_hat", K_hat)
        F_hat = _check_nonnegative("cross-constraints F_hat", F_hat)
        a = float(a)
        if not (0.0 <= a < 1.0):
            raise ValueError(f"cross-constraints shape parameter a must be in [0, 1), got {a!r}")
        tau = float(tau)
        if not (math.isfinite(tau) and tau >= 1.0):
            raise ValueError(f"cross-constraints factor tau must be >= 1, got {tau!r}")
        self.a, self.tau = a, tau
        self.scalars = {"K_hat": K_hat}
        self.fields = {"F_hat": F_hat}

    def _exponent(self, g, c, ops):
        # A * min(g, 0) <= 0 always; A <= 1e200 / (1 + a) keeps A finite for F_hat = 0.
        A = c["K_hat"] / ((1.0 + self.a) * ops.max(c["F_hat"], 1e-200 * c["K_hat"]))
        # min(0, g), not min(g, 0): UFL differentiates min_value(f, h) as dh where f < h is false, so this
        # order gives the open branch's derivative at g = 0 exactly (stiffness K_hat for a point that touches
        # exactly, e.g. in the initial configuration), the other order none.
        return A * ops.min(0.0, g)

    def force(self, g, c, ops=NUMPY):
        a, x = self.a, self._exponent(g, c, ops)
        open_ = c["F_hat"] / (1.0 - a) * (ops.exp(x) - a * ops.exp(a * x)) if a else c["F_hat"] * ops.exp(x)
        return open_ + c["K_hat"] * ops.max(g, 0.0)

    def potential(self, g, c, ops=NUMPY):
        a, x = self.a, self._exponent(g, c, ops)
        k = c["F_hat"] ** 2 * (1.0 + a) / (c["K_hat"] * (1.0 - a))
        gp = ops.max(g, 0.0)
        return k * (ops.exp(x) - ops.exp(a * x)) + c["F_hat"] * gp + 0.5 * c["K_hat"] * gp * gp

    def stiffness(self, g, c, ops=NUMPY):
        a, x = self.a, self._exponent(g, c, ops)
        # At x = 0 (closed side) this is K_hat; the open branch vanishes for F_hat = 0.
        open_ = (ops.exp(x) - a * a * ops.exp(a * x)) / (1.0 - a * a)
        on = _heaviside(c["F_hat"], ops)  # F_hat = 0: no open branch at all
        return c["K_hat"] * (on * open_ + (1.0 - on) * _heaviside(g, ops))

    def augment_fields(self, g, c, ops=NUMPY):
        return {"F_hat": ops.max(self.force(g, c, ops), 0.0)}

    def augment_scalars(self, c):
        return {"K_hat": self.tau * float(c["K_hat"])}


class NormalCompliance(ContactLaw):
    """Normal compliance (Oden & Martins; formulation 1.5): ``F = c_n <g>^m_n``, ``P = c_n/(m_n+1) <g>^(m_n+1)``.

    ``c_n > 0`` in pressure per length^m_n, exponent ``m_n >= 1`` (``m_n = 1`` is the penalty law
    with ``K = c_n``, but with the tangent ``c_n`` at ``g = 0``: a body that only rests on the surface
    can start Newton from the touching state). The exponent is fixed for a run (part of the compiled form).

    Args:
        c_n: the compliance coefficient (pressure per length^m_n), > 0.
        m_n: the exponent, >= 1.
    """

    name = "compliance"

    def __init__(self, c_n: float, m_n: float = 1.0):
        self.scalars = {"c_n": _check_positive("normal compliance c_n", c_n)}
        self.m = _check_exponent("normal compliance exponent m_n", m_n)
        self.fields = {}

    def force(self, g, c, ops=NUMPY):
        if self.m == 1.0:
            # c_n g H(g) with H(0) = 1: the same values as c_n <g>, but the tangent at a touching point
            # (g = 0) is c_n, not 0, so a body resting on the surface has a regular first Jacobian.
            return c["c_n"] * g * _heaviside_closed(g, ops)
        return c["c_n"] * ops.max(g, 0.0) ** self.m

    def potential(self, g, c, ops=NUMPY):
        return c["c_n"] / (self.m + 1.0) * ops.max(g, 0.0) ** (self.m + 1.0)

    def stiffness(self, g, c, ops=NUMPY):
        if self.m == 1.0:
            return c["c_n"] * _heaviside_closed(g, ops)
        return self.m * c["c_n"] * ops.max(g, 0.0) ** (self.m - 1.0)


class SnesVI(Formulation):
    """Method ``vi``: exact nodal non-penetration (``g <= 0``) as bounds on the unknowns, solved by PETSc
    SNES VI (:mod:`fenics_contact.bounds`); the pressure is the nodal reaction. Flat, axis-aligned
    rigid obstacles only. No parameter."""

    name = "vi"

    def __init__(self):
        self.scalars, self.fields = {}, {}


def _check_exponent(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value >= 1.0):
        raise ValueError(f"{name} must be a finite number >= 1, got {value!r}")
    return value


class ExactCoulomb(Formulation):
    """Method ``coulomb``: exact Signorini contact with Coulomb friction (coefficient ``mu >= 0``), solved on
    the stiffness condensed onto the contact dofs (:mod:`fenics_contact.condensed`). Linear elasticity, nodal
    contact, 2D or 3D: a flat rigid obstacle, or two bodies in small sliding. No penalty parameter.

    Args:
        mu: the Coulomb friction coefficient, >= 0 (0: frictionless).
    """

    name = "coulomb"

    def __init__(self, mu: float = 0.0):
        self.mu = _check_nonnegative("friction coefficient mu", mu)
        self.scalars, self.fields = {}, {}

    @property
    def has_friction(self) -> bool:
        return self.mu > 0.0


def _heaviside_closed(x, ops):
    """1 for x >= 0, 0 otherwise (to round-off below 1e-300), without division."""
    return ops.min(ops.max(x * 1e300 + 1.0, 0.0), 1.0)


class LagrangeMultiplier(Formulation):
    """Method ``lagrange``: the contact pressure ``p`` is an unknown (:mod:`fenics_contact.multipliers`).

    Exact nodal Signorini conditions ``g <= 0, p >= 0, p g = 0`` through the
    complementarity function ``C(p, g) = p - max(0, p + c g)`` (zero iff they
    hold, for any ``c > 0``). ``c`` (pressure per length, like a penalty)
    only steers the semismooth Newton iterates, not the converged solution.

    Args:
        c: the complementarity parameter (pressure per length), > 0; steers the iterates only.
    """

    name = "lagrange"

    def __init__(self, c: float = 1.0):
        self.scalars = {"c": _check_positive("complementarity parameter c", c)}
        self.fields = {}

    def complementarity(self, p, g, c, ops=NUMPY):
        """``C(p, g) = p - max(0, p + c g)``; ``max(0, .)`` first so that UFL's generalized derivative
        counts the tie ``p + c g = 0`` as active."""
        return p - ops.max(0.0, p + c["c"] * g)


class PenaltyMultiplier(LagrangeMultiplier):
    """Penalty regularization of the multipliers (Papadopoulos & Solberg's ``p = eps <g>``): the
    pressure stays an unknown, now with ``p = eps <g>`` at the contact vertices instead of the exact
    complementarity, i.e. ``C(p, g) = p - eps max(0, g)``. ``eps`` (``K`` on the command line) in
    pressure per length; ``eps -> infinity`` gives the multipliers' solution.

    Args:
        K: the regularization ``eps`` (pressure per length), > 0.
    """

    name = "penalty_multiplier"

    def __init__(self, K: float):
        self.scalars = {"c": _check_positive("penalty eps (K)", K)}
        self.fields = {}

    def complementarity(self, p, g, c, ops=NUMPY):
        return p - c["c"] * ops.max(0.0, g)


class Nitsche(Formulation):
    """Method ``nitsche``: Nitsche's method (:mod:`fenics_contact.nitsche`). The pressure is
    ``<gamma g - sigma_n(u)>`` with ``gamma = gamma0 E / h``, not a law of the gap alone; ``gamma0``
    (dimensionless, > 0) and ``theta`` are its parameters. The surface needs the bulk material (for ``sigma_n``).

    Args:
        gamma0: the dimensionless Nitsche parameter, > 0 (``gamma = gamma0 E / h``).
        theta: in [-1, 1]: 1 symmetric, 0 incomplete, -1 skew-symmetric.
    """

    name = "nitsche"

    def __init__(self, gamma0: float = 10.0, theta: float = 1.0):
        theta = float(theta)
        if not (math.isfinite(theta) and -1.0 <= theta <= 1.0):
            raise ValueError(f"Nitsche theta must be a finite number in [-1, 1], got {theta!r}")
        self.scalars = {"gamma0": _check_positive("Nitsche gamma0", gamma0), "theta": theta}
        self.fields = {}


def _heaviside(x, ops):
    """1 for x > 0, 0 otherwise, without division: min(max(x * huge, 0), 1)."""
    return ops.min(ops.max(x * 1e300, 0.0), 1.0)
