"""Parametric scenes: every physical constant a keyword argument of its builder, range-checked before any work,
and a demo option through scenes.add_scene_options."""
import argparse
import importlib

import pytest

from fenics_contact.app.scenes import add_scene_options, build, numeric_parameters, scene_arguments
from fenics_contact.methods import make_law

# scene -> its module constants that are now build arguments with those defaults
CONSTANTS = {"hertz": {"R": "R", "E": "E", "nu": "NU", "approach": "APPROACH"},  # stabilisation: None (by plate)
             "sphere": {"R": "R", "E": "E", "nu": "NU", "approach": "APPROACH"},
             "block": {"height": "HEIGHT", "E": "E", "nu": "NU", "displacement": "DISPLACEMENT"},
             "slab": {"width": "WIDTH", "height": "HEIGHT", "E": "E", "nu": "NU", "top_pressure": "TOP_PRESSURE",
                      "side_pressure": "SIDE_PRESSURE"},
             "pin": {"R": "R", "half_width": "HALF_WIDTH", "below": "BELOW", "above": "ABOVE", "E": "E", "nu": "NU",
                     "P0": "P0", "stabilisation": "STABILISATION"},
             "ring": {"R_out": "R_OUT", "R_in": "R_IN", "E": "E", "nu": "NU", "approach": "APPROACH"},
             "compliance3d": {"lx": "LX", "ly": "LY", "height": "H", "E": "E", "nu": "NU", "press": "PRESS",
                              "drag": "DRAG"},
             "cylinders": {"R_lower": "R_LOWER", "R_upper": "R_UPPER"},
             "seal": {"E": "E", "nu": "NU", "R_out": "R_OUT", "R_in": "R_IN", "plate_distance": "GAP"},
             "sheet": {"R": "R", "thickness": "THICKNESS", "leg": "LEG", "R_in": "R_IN", "lmbda": "LMBDA", "mu": "MU",
                       "ratio": "RATIO", "radius": "RADIUS", "pull": "PULL"},
             "patch": {"E_lower": "E_LOWER", "E_upper": "E_UPPER", "nu_lower": "NU", "nu_upper": "NU",
                       "pressure": "PRESSURE", "width": "WIDTH", "h_lower": "H_LOWER", "h_upper": "H_UPPER",
                       "overlap": "OVERLAP"}}


@pytest.mark.parametrize("scene", sorted(CONSTANTS))
def test_constants_are_build_arguments(scene):
    module = importlib.import_module(f"fenics_contact.app.scenes.{scene}")
    params = numeric_parameters(module.build)
    for arg, constant in CONSTANTS[scene].items():
        assert params[arg] == getattr(module, constant), (scene, arg)


def test_demo_options_from_the_builder():
    from fenics_contact.app.scenes import hertz

    p = argparse.ArgumentParser()
    p.add_argument("--mu", type=float, default=0.0)  # a shared option of the same name is left alone
    names = add_scene_options(p, hertz.build)
    assert {"R", "E", "nu", "approach", "load", "plate_E", "plate_nu", "plate_width", "plate_depth",
            "contact_width", "stabilisation"} <= set(names)
    args = p.parse_args(["--E", "200", "--nu", "0.3", "--R", "8", "--load", "10", "--plate-E", "200"])
    kw = scene_arguments(args, names)
    assert kw["E"] == 200.0 and kw["R"] == 8.0 and kw["load"] == 10.0 and kw["plate_E"] == 200.0
    assert kw["plate_width"] is None and kw["approach"] == hertz.APPROACH


@pytest.mark.parametrize("scene, kw, match", [
    ("hertz", {"E": 0.0}, "E must be a finite number > 0"), ("hertz", {"nu": 0.5}, r"nu must be in \[0, 0.5\)"),
    ("block", {"height": -2.0}, "height must be"), ("slab", {"nu": -0.1}, "nu must be in"),
    ("pin", {"R": 6.0}, "hole"), ("ring", {"R_in": 9.0}, "R_in must be < R_out"),
    ("sphere", {"approach": float("inf")}, "approach must be"), ("seal", {"E": float("nan")}, "E must be"),
    ("compliance3d", {"press": 0.0}, "press must be"), ("cylinders", {"nu": 0.6}, "nu must be in"),
    ("sheet", {"R_in": 3.0}, "R_in must be < R"), ("sheet", {"lmbda": -1.0}, "lmbda must be"),
    ("sheet", {"thickness": float("nan")}, "thickness must be"), ("patch", {"width": 0.0}, "width must be"),
    ("patch", {"nu_upper": 0.5}, "nu_upper must be in"), ("patch", {"overlap": 0.5}, "overlap must be <")])
def test_bad_parameters_are_refused_before_any_work(scene, kw, match, monkeypatch):
    import fenics_contact.app.meshes as meshes

    def no_mesh(*a, **k):  # any mesh built means the check came too late
        raise AssertionError("a mesh was built before the parameters were checked")

    for name in ("hertz_quarter_disk", "rectangle", "pin_plate", "ring_quarter", "sphere_octant", "two_half_disks",
                 "sheet_over_cylinder", "stacked_blocks"):
        monkeypatch.setattr(meshes, name, no_mesh)
    module = importlib.import_module(f"fenics_contact.app.scenes.{scene}")
    for name in ("hertz_quarter_disk", "rectangle", "pin_plate", "ring_quarter", "sphere_octant", "two_half_disks",
                 "half_box", "sheet_over_cylinder", "stacked_blocks"):
        if hasattr(module, name):
            monkeypatch.setattr(module, name, no_mesh)
    if scene == "seal":
        monkeypatch.setattr(module, "SHAPES", {k: no_mesh for k in module.SHAPES})
    law = make_law("auglag", K=1e5)
    if scene == "compliance3d":
        law = None
    args = {"law_factory": lambda: law} if scene == "cylinders" else {"law": law}
    with pytest.raises(ValueError, match=match):
        build(scene, **args, **kw)
