"""Parametric scenes: every physical constant a keyword argument of its builder, range-checked before any work,
and a demo option through scenes.add_scene_options; a mesh size the memory cannot hold refused before any work,
with the range that fits; the gmsh builders' meshes made in a child process the same as in this one."""
import argparse
import importlib

import pytest

from fenics_contact.app.scenes import SizeError, add_scene_options, build, numeric_parameters, scene_arguments
from fenics_contact.methods import make_law

# scene -> its module constants that are now build arguments with those defaults
CONSTANTS = {"hertz": {"R": "R", "E": "E", "nu": "NU"},  # stabilisation, approach: None (by plate; APPROACH R)
             "sphere": {"R": "R", "E": "E", "nu": "NU"},
             "block": {"height": "HEIGHT", "E": "E", "nu": "NU", "displacement": "DISPLACEMENT"},
             "slab": {"width": "WIDTH", "height": "HEIGHT", "E": "E", "nu": "NU", "top_pressure": "TOP_PRESSURE",
                      "side_pressure": "SIDE_PRESSURE"},
             "pin": {"R": "R", "E": "E", "nu": "NU", "P0": "P0", "stabilisation": "STABILISATION"},  # plate: x R
             "ring": {"R_out": "R_OUT", "R_in": "R_IN", "E": "E", "nu": "NU"},  # approach: APPROACH R_out / R_OUT
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
    p.add_argument("--mu", type=float, default=0.0)  # an option the scene does not have
    names = add_scene_options(p, hertz.build)
    assert {"R", "E", "nu", "approach", "load", "plate_E", "plate_nu", "plate_width", "plate_depth",
            "contact_width", "stabilisation"} <= set(names)
    args = p.parse_args(["--E", "200", "--nu", "0.3", "--R", "8", "--load", "10", "--plate-E", "200"])
    kw = scene_arguments(args, names)
    assert kw["E"] == 200.0 and kw["R"] == 8.0 and kw["load"] == 10.0 and kw["plate_E"] == 200.0
    assert kw["plate_width"] is None and kw["approach"] is None  # force control: no approach


def test_a_scene_option_the_demo_already_has_is_refused_unless_shared():
    """A builder keyword whose flag the demo already has would be set by that other option: an error naming both,
    unless the demo declares it shared (the same quantity, given to the builder from its own option)."""
    from fenics_contact.app.scenes import hertz

    p = argparse.ArgumentParser()
    p.add_argument("--E", type=float, default=1.0, help="a demo's own E")
    with pytest.raises(ValueError, match=r"--E of fenics_contact.app.scenes.hertz is already an option"):
        add_scene_options(p, hertz.build)
    assert "E" not in add_scene_options(p, hertz.build, shared=("E",))


@pytest.mark.parametrize("scene, kw, match", [
    ("hertz", {"E": 0.0}, "E must be a finite number > 0"), ("hertz", {"nu": 0.5}, r"nu must be in \[0, 0.5\)"),
    ("block", {"height": -2.0}, "height must be"), ("slab", {"nu": -0.1}, "nu must be in"),
    ("pin", {"R": 6.0, "half_width": 5.0}, "hole"), ("ring", {"R_in": 9.0}, "R_in must be < R_out"),
    ("sphere", {"approach": float("inf")}, "approach must be"), ("seal", {"E": float("nan")}, "E must be"),
    ("compliance3d", {"press": 0.0}, "press must be"), ("cylinders", {"nu": 0.6}, "nu must be in"),
    ("sheet", {"R_in": 3.0}, "R_in must be < R"), ("sheet", {"lmbda": -1.0}, "lmbda must be"),
    ("sheet", {"thickness": float("nan")}, "thickness must be"), ("patch", {"width": 0.0}, "width must be"),
    ("patch", {"nu_upper": 0.5}, "nu_upper must be in"), ("patch", {"overlap": 0.5}, "overlap must be <"),
    ("compliance3d", {"law": "coulomb"}, "method coulomb is not offered on compliance3d")])
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
    if kw.get("law") == "coulomb":
        law = make_law("coulomb", mu=0.3)
        kw = {}
    args = {"law_factory": lambda: law} if scene == "cylinders" else {"law": law}
    with pytest.raises(ValueError, match=match):
        build(scene, **args, **kw)


class _MeshReached(Exception):
    pass


@pytest.mark.parametrize("scene,parameter,big", [("hertz", "refinement", 12), ("pin", "refinement", 30),
                                                 ("slab", "refinement", 20), ("sphere", "size", 1e-9)])
def test_a_size_the_memory_cannot_hold_is_refused_before_any_work(scene, parameter, big, monkeypatch):
    """Under a 2 GB cap: the size is refused naming the argument, the estimate and the cap, before any mesh is
    made; the accepted range it gives is right at its end (the last accepted value reaches the mesher, the next
    is refused). The command line says it with the option (--refinement)."""
    import fenics_contact.app.scenes as scenes
    from fenics_contact.app.cli import error_line

    def mesher(*a, **k):
        raise _MeshReached

    module = importlib.import_module(f"fenics_contact.app.scenes.{scene}")
    for name in ("hertz_quarter_disk", "rectangle", "pin_plate", "sphere_octant"):
        if hasattr(module, name):
            monkeypatch.setattr(module, name, mesher)
    monkeypatch.setattr(scenes, "available_memory", lambda: (2e9, "the 2 GB this process may use (ulimit -v)"))
    law = make_law("auglag", K=1e5)
    with pytest.raises(SizeError) as info:
        build(scene, law=law, **{parameter: big})
    e = info.value
    assert e.parameter == parameter and e.value == big and "unknowns" in e.reason and "ulimit -v" in e.reason
    line = error_line(e)
    assert line.startswith(f"--{parameter} {big:g}: about ") and f"accepted: --{parameter} " in line
    if parameter == "refinement":
        top = int(e.accepted.split(" to ")[1])
        assert 2 <= top < big
        with pytest.raises(_MeshReached):
            build(scene, law=law, refinement=top)
        with pytest.raises(SizeError):
            build(scene, law=law, refinement=top + 1)
    else:
        low = float(e.accepted.split(">= ")[1])
        with pytest.raises(_MeshReached):
            build(scene, law=law, size=1.05 * low)
        with pytest.raises(SizeError):
            build(scene, law=law, size=0.9 * low)


def test_mesh_from_a_child_process_is_the_same(monkeypatch):
    """gmsh in a forked child (the default: the mesher's memory out of this process) gives the mesh gmsh makes in
    this process, bit for bit (hertz's graded quarter disk, pin's plate with a hole)."""
    import numpy as np
    from mpi4py import MPI

    from fenics_contact.app.meshes import gmshutil, hertz, pin

    for module, make in ((hertz, lambda: hertz.hertz_quarter_disk(MPI.COMM_WORLD, 1.0, h_contact=1 / 200)),
                         (pin, lambda: pin.pin_plate(MPI.COMM_WORLD))):
        meshes = []
        for isolate in (False, True):
            monkeypatch.setattr(module, "_from_gmsh",
                                lambda *a, isolate=isolate, **k: gmshutil._from_gmsh(*a, **{**k, "isolate": isolate}))
            mesh, cells, facets = make()
            meshes.append((mesh.geometry.x, mesh.topology.connectivity(2, 0).array, facets.indices, facets.values,
                           cells.values, facets.names))
        assert all(np.array_equal(a, b) if isinstance(a, np.ndarray) else a == b for a, b in zip(*meshes))


MESHERS = ("cord_section", "hertz_quarter_disk", "two_half_disks", "disk_on_block", "cap_on_block", "punch_on_block",
           "ring_quarter", "concentric_rings", "sheet_over_cylinder", "pin_plate", "half_box")


@pytest.mark.parametrize("scene, kwargs, parameter", [
    ("oring", dict(h=1e-7), "h"),
    ("axisphere", dict(h_contact=1e-9), "h_contact"),
    ("mindlin3d", dict(h_contact=1e-9), "h_contact"),
    ("mindlin3d", dict(refinement=30), "refinement"),
    ("mindlin", dict(h_contact=1e-9), "h_contact"),
    ("cylinders", dict(h_contact=1e-9), "h_contact"),
    ("cylinders", dict(grading=1e-12), "grading"),
    ("seal", dict(h=1e-9), "h"),
    ("ironing", dict(h_arc=1e-12), "h_arc"),
    ("ring", dict(n_theta=10**7), "n_theta"),
    ("rings", dict(n=10**6), "n"),
    ("sheet", dict(n_arc=10**7), "n_arc"),
    ("compliance3d", dict(nx=1000, ny=1000, nz=1000), "mesh"),
    ("pin", dict(h_contact=1e-9), "h_contact"),
])
def test_every_size_option_is_refused_from_the_unknowns_it_implies(scene, kwargs, parameter, monkeypatch):
    """A mesh size or count far beyond the memory (gmsh would mesh for ever, or the run would end out of memory) is
    refused before any mesh is made, naming the argument (the demos' option) with the sizes that fit."""
    from mpi4py import MPI

    import fenics_contact.app.scenes as scenes
    from fenics_contact.app.cli import error_line
    from fenics_contact.friction import Friction

    module = importlib.import_module(f"fenics_contact.app.scenes.{scene}")

    def mesher(*a, **k):
        raise _MeshReached

    for name in MESHERS:
        if hasattr(module, name):
            monkeypatch.setattr(module, name, mesher)
    for shape in getattr(module, "SHAPES", {}):  # the seal's meshers by shape
        monkeypatch.setitem(module.SHAPES, shape, mesher)
    monkeypatch.setattr(scenes, "available_memory", lambda: (2e9, "the 2 GB this process may use (ulimit -v)"))
    law = make_law("penalty", K=1e5)
    friction = Friction(law, mu=0.3, omega_t=1e5)
    arguments = {"cylinders": dict(law_factory=lambda: law), "rings": dict(law_factory=lambda: law)}.get(
        scene, dict(law=friction if scene in ("mindlin", "mindlin3d", "ironing", "compliance3d") else law))
    with pytest.raises(SizeError) as info:
        build(scene, **arguments, **kwargs)
    assert info.value.parameter == parameter and "unknowns" in info.value.reason
    line = error_line(info.value)
    assert line.startswith(f"--{parameter.replace('_', '-')} ") and "accepted: " in line, line
    if MPI.COMM_WORLD.size == 1:  # a demo given it: one line, exit status 2 (a bad command line)
        from fenics_contact.app import cli

        with pytest.raises(SystemExit) as ended:
            cli.main(lambda argv: build(scene, **arguments, **kwargs), [])
        assert ended.value.code == cli.EXIT_USAGE


def test_gmsh_never_asks_a_question(monkeypatch):
    """gmsh asks on standard input before meshing a very large mesh ("Do you really want to continue?"): every gmsh
    session of the library sets the option that answers it (General.NoPopup)."""
    from mpi4py import MPI

    from fenics_contact.app.meshes import gmshutil, hertz

    seen = []
    setter = gmshutil.gmsh.option.setNumber
    monkeypatch.setattr(gmshutil.gmsh.option, "setNumber", lambda name, value: (seen.append((name, value)),
                                                                                setter(name, value)))
    monkeypatch.setattr(hertz, "_from_gmsh", lambda *a, **k: gmshutil._from_gmsh(*a, **{**k, "isolate": False}))
    hertz.hertz_quarter_disk(MPI.COMM_WORLD, 1.0, h_contact=1 / 50)
    assert ("General.NoPopup", 1) in seen
