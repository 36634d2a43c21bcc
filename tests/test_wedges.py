"""wedges: a block pushed up an elastic incline with node-to-segment Coulomb friction between the two bodies."""
import pytest

import fenics_contact as fc
import fenics_contact.app as app
from fenics_contact.app.scenes import wedges


@pytest.mark.parametrize("mu,alpha", [(0.3, 20.0), (0.2, 0.0)])
def test_force_ratio_of_a_block_sliding_up_a_wedge(mu, alpha):
    """Once the whole interface slides, H / N = (mu + tan alpha) / (1 - mu tan alpha) within 1 %; the vertical
    equilibrium of the block holds to 1e-8."""
    law = fc.Friction(fc.make_law("penalty", K=wedges.DEFAULT_K), mu=mu, omega_t=wedges.DEFAULT_OMEGA_T)
    setup = app.build("wedges", law=law, alpha=alpha)
    solver = fc.Solver(setup.problem, quiet=True, predictor=wedges.PREDICTOR)
    solver.run(setup.loads)
    f = setup.figures()
    print(f"wedges mu={mu} alpha={alpha}: H/N = {f['ratio']:.6g}, formula {f['ratio_reference']:.6g}, "
          f"error {f['ratio_error']:.2e}")
    assert f["slip_fraction"] == 1.0
    assert f["ratio_error"] <= 0.01, f
    assert f["vertical_equilibrium_error"] <= 1e-8
    # the scene's load steps and predictor: no failed Newton attempt, at most 5 iterations per step on average
    summary = solver.summary()
    assert not summary["failures"], summary["failures"]
    assert summary["newton_iterations"] <= 5 * summary["load_steps"], summary["newton_iterations"]


def test_bad_input():
    with pytest.raises(ValueError, match="method coulomb is refused on wedges"):
        app.build("wedges", law=fc.make_law("coulomb", mu=0.3))
    law = fc.Friction(fc.make_law("penalty", K=1e6), mu=0.3, omega_t=1e4)
    with pytest.raises(ValueError, match="alpha must be in"):
        app.build("wedges", law=law, alpha=75.0)
    with pytest.raises(ValueError, match="self-locking"):
        app.build("wedges", law=fc.Friction(fc.make_law("penalty", K=1e6), mu=2.0, omega_t=1e4), alpha=60.0)
    with pytest.raises(ValueError, match=r"needs a Coulomb \(mu > 0.*or Tresca \(tresca > 0\) friction law"):
        app.build("wedges", law=fc.make_law("penalty", K=1e6))
