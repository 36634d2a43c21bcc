"""Contact laws: derivatives against UFL differentiation, continuity, limits, robustness, bad input."""
import numpy as np
import pytest
import ufl
from dolfinx import fem, mesh
from mpi4py import MPI

from fenics_contact.laws import NUMPY, AugmentedLagrangian, CrossConstraints, Penalty, ufl_ops
from fenics_contact.methods import make_law

G = np.concatenate([-np.logspace(-6, 0, 7), [0.0], np.logspace(-6, 0, 7)]) * 1e-3

LAWS = [Penalty(1e5), AugmentedLagrangian(1e5, lam0=50.0), CrossConstraints(1e5, 100.0),
        CrossConstraints(1e5, 170.0, a=0.05), CrossConstraints(1e5, 1e4, a=0.5)]


def _ufl_evaluator(law):
    """Compiled UFL P, F, K, dP/dg, dF/dg of ``law``, evaluated at one gap by assembly on a unit square."""
    m = mesh.create_unit_square(MPI.COMM_SELF, 1, 1)
    g = fem.Constant(m, 0.0)
    c = {k: fem.Constant(m, float(v)) for k, v in law.parameters().items()}
    gv = ufl.variable(g)
    ops = ufl_ops()
    P, F = law.potential(gv, c, ops), law.force(gv, c, ops)
    forms = [fem.form(e * ufl.dx) for e in (P, F, law.stiffness(gv, c, ops), ufl.diff(P, gv), ufl.diff(F, gv))]

    def evaluate(value):
        g.value = value
        return np.array([fem.assemble_scalar(f) for f in forms])

    return evaluate


@pytest.mark.parametrize("law", LAWS, ids=lambda law: f"{law.name}-{law.values()}")
def test_derivatives_match_ufl_differentiation(law):
    evaluate = _ufl_evaluator(law)
    c = law.values()
    for g in G[G != 0.0]:  # the kink of penalty-type laws at g = 0 has no derivative
        P, F, K, dP, dF = evaluate(g)
        assert np.isclose(F, dP, rtol=1e-12, atol=1e-12 * abs(F) + 1e-300)
        assert np.isclose(K, dF, rtol=1e-12, atol=1e-12 * abs(K) + 1e-300)
        # the NumPy form of the same law gives the same numbers
        assert np.allclose([law.potential(g, c), law.force(g, c), law.stiffness(g, c)], [P, F, K], rtol=1e-13)


@pytest.mark.parametrize("law", [law for law in LAWS if law.name == "cross"], ids=lambda law: str(law.values()))
def test_cross_constraints_continuous_at_zero(law):
    c = law.values()
    eps = 1e-13
    for f in (law.potential, law.force, law.stiffness):
        left, mid, right = (f(np.array(x), c, NUMPY) for x in (-eps, 0.0, eps))
        assert abs(left - mid) <= 1e-6 * max(abs(mid), 1) and abs(right - mid) <= 1e-6 * max(abs(mid), 1)
    assert np.isclose(law.force(0.0, c), c["F_hat"], rtol=1e-14)
    assert np.isclose(law.stiffness(0.0, c), c["K_hat"], rtol=1e-14)


@pytest.mark.parametrize("law", [law for law in LAWS if law.name == "cross"], ids=lambda law: str(law.values()))
def test_cross_constraints_ufl_tangent_at_exact_contact(law):
    """The Jacobian is UFL's derivative of the force: at g = 0 exactly (a point that touches in the initial
    configuration) it must be the law's stiffness K_hat, not the derivative of a constant branch (0)."""
    P, F, K, dP, dF = _ufl_evaluator(law)(0.0)
    assert np.isclose(dF, law.values()["K_hat"], rtol=1e-12) and np.isclose(K, dF, rtol=1e-12)


def test_cross_constraints_with_zero_target_is_penalty():
    g = np.linspace(-1e3, 1e3, 20001)
    pen, cc = Penalty(1e5), CrossConstraints(1e5, 0.0)
    for name in ("potential", "force", "stiffness"):
        assert np.array_equal(getattr(cc, name)(g, cc.values()), getattr(pen, name)(g, pen.values()))


@pytest.mark.parametrize("F_hat", [0.0, 1e-12, 1e4])
@pytest.mark.parametrize("a", [0.0, 0.05, 0.5])
def test_no_overflow(F_hat, a):
    law = CrossConstraints(1e5, F_hat, a=a)
    g = np.linspace(-1e3, 1e3, 200001)
    with np.errstate(over="raise", invalid="raise", divide="raise"):  # underflow to 0 is the law
        for f in (law.potential, law.force, law.stiffness):
            assert np.all(np.isfinite(f(g, law.values())))


def test_cross_constraints_monotone_for_recommended_a():
    law = CrossConstraints(1e5, 170.0, a=0.0)
    g = np.linspace(-0.1, 0.1, 10001)
    assert np.all(np.diff(law.force(g, law.values())) >= 0) and np.all(law.force(g, law.values()) >= 0)


def test_augmentation_update_is_current_force():
    law = CrossConstraints(1e5, 100.0, tau=2.0)
    c = law.values()
    assert np.isclose(law.augment_fields(1e-3, c)["F_hat"], 100.0 + 1e5 * 1e-3)
    assert law.augment_scalars(c) == {"K_hat": 2e5}
    al = AugmentedLagrangian(1e5, lam0=10.0)
    assert al.augment_fields(-1.0, al.values())["lam"] == 0.0


@pytest.mark.parametrize("method,params,name", [
    ("penalty", {"K": 0.0}, "penalty K"), ("penalty", {"K": -1.0}, "penalty K"),
    ("auglag", {"K": -5.0}, "penalty K"), ("cross", {"K_hat": 0.0}, "K_hat"),
    ("cross", {"K_hat": 1e5, "a": 1.0}, "shape parameter a"), ("cross", {"K_hat": 1e5, "a": -0.1}, "shape parameter a"),
    ("cross", {"K_hat": 1e5, "F_hat": -1.0}, "F_hat"), ("cross", {"K_hat": 1e5, "tau": 0.5}, "tau"),
    ("mortar", {}, "unknown contact method"),
])
def test_bad_input_names_the_parameter(method, params, name):
    with pytest.raises(ValueError, match=name):
        make_law(method, **params)
