"""The demos' options: every option's help says what it is and its default; every scene parameter has a help text
declared with its scene; a bad number for any numeric option of any demo, contradictory options and an option
given without the one it needs are refused while parsing (exit 2, one line naming the option given, before any
work); the meshed Hertz plate's default size follows the contact half-width (the two-body peer case within 1 %
of Hertz)."""
import argparse
import importlib
import math
import re
import runpy
import sys

import pytest
from mpi4py import MPI

from fenics_contact.app import cli
from fenics_contact.app.__main__ import demo_names
from fenics_contact.app.scenes import Option, numeric_parameters, scene_names, scene_options

serial = pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="command lines of one process")
DEMOS = demo_names()
PLACEHOLDERS = ("scene parameter", "derived from the others", "todo", "xxx")


class _Parsed(Exception):
    """Raised in place of a demo's work once its command line parsed."""


def _run(name: str, argv: list[str], monkeypatch):
    """Run demo ``name`` with ``argv`` as ``python -m fenics_contact.app`` does; its work is never reached (a
    command line that parses raises :class:`_Parsed`). Returns the ``SystemExit``."""
    original = cli.StrictParser.parse_known_args

    def parse_only(self, args=None, namespace=None):
        out = original(self, args, namespace)
        if not any(a in ("-h", "--help") for a in (args or [])):
            raise _Parsed(" ".join(argv))
        return out

    monkeypatch.setattr(cli.StrictParser, "parse_known_args", parse_only)
    monkeypatch.setattr(sys, "argv", [f"{name}.py", *argv])
    with pytest.raises(SystemExit) as exc:
        runpy.run_module(f"fenics_contact.app.demos.{name}", run_name="__main__")
    return exc.value


def _parser(name: str, monkeypatch) -> argparse.ArgumentParser:
    """The parser of demo ``name`` (caught when it prints its ``--help``)."""
    caught = []

    def grab(self, file=None):
        caught.append(self)
        raise SystemExit(0)

    monkeypatch.setattr(argparse.ArgumentParser, "print_help", grab)
    _run(name, ["--help"], monkeypatch)
    monkeypatch.undo()
    return caught[0]


def _help(parser: argparse.ArgumentParser, action: argparse.Action) -> str:
    return " ".join(parser._get_formatter()._expand_help(action).split())


@serial
@pytest.mark.parametrize("name", DEMOS)
def test_every_option_says_what_it_is_and_its_default(name, monkeypatch):
    parser = _parser(name, monkeypatch)
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction):
            continue
        flag = (action.option_strings or [action.dest])[0]
        text = _help(parser, action)
        what = re.sub(r"\(default: [^)]*\)$", "", text).strip()
        assert len(what) >= 8 and not any(w in text.lower() for w in PLACEHOLDERS), (name, flag, text)
        assert "default" in text, (name, flag, text)
        if isinstance(action.default, (int, float, str)) and not isinstance(action.default, bool):
            shown = re.search(r"default: ([^)]*)", text).group(1)
            values = {str(action.default)} | ({f"{action.default:g}"} if isinstance(action.default, float) else set())
            assert any(v in shown for v in values) or not re.match(r"[-+.\d]", shown), (name, flag, text)


@pytest.mark.parametrize("scene", scene_names())
def test_every_scene_parameter_has_a_help_text(scene):
    module = importlib.import_module(f"fenics_contact.app.scenes.{scene}")
    options = scene_options(module.build)
    assert set(options) == set(numeric_parameters(module.build))
    for name, option in options.items():
        assert isinstance(option, Option) and "(" in option.help or option.range == "poisson", (scene, name)


def test_a_parameter_without_a_help_text_is_an_error(monkeypatch):
    from fenics_contact.app.scenes import block

    monkeypatch.setattr(block, "OPTIONS", {k: v for k, v in block.OPTIONS.items() if k != "E"})
    with pytest.raises(ValueError, match="no help text for E"):
        scene_options(block.build)


def _bad_values(convert) -> list[str]:
    """Values outside the range of an option's type (``cli.number``: its ``range``)."""
    if convert is None or not hasattr(convert, "range"):
        return ["nan", "x"] if convert in (int, float) else []
    kind, low, high, low_open, high_open = convert.range
    bad = ["nan"]
    if low is not None:
        bad.append(f"{low if low_open else low - 1:g}")
    elif high is not None:
        bad.append(f"{high if high_open else high + 1:g}")
    if kind is int:
        bad.append("1.5")
    return bad


def _numeric_options(name: str, monkeypatch) -> list[tuple[str, str, int]]:
    parser = _parser(name, monkeypatch)
    return [(a.option_strings[0], v, a.nargs if isinstance(a.nargs, int) else 1) for a in parser._actions
            if a.option_strings for v in _bad_values(a.type)]


@serial
@pytest.mark.parametrize("name", DEMOS)
def test_a_bad_number_is_one_line_naming_the_option(name, monkeypatch, capsys):
    """Every numeric option of every demo: a value out of its range exits 2 with one line naming the option."""
    cases = _numeric_options(name, monkeypatch)
    assert cases or name == "table", name  # every demo but the table has numeric options
    for flag, value, nargs in cases:
        end = _run(name, [flag, value, *["1"] * (nargs - 1)], monkeypatch)
        monkeypatch.undo()
        lines = [s for s in capsys.readouterr().err.splitlines() if s.strip()]
        assert end.code == cli.EXIT_USAGE and len(lines) == 1, (flag, value, end.code, lines)
        assert re.search(rf"(?<![\w-]){re.escape(flag)}(?![\w-])", lines[0]), (flag, value, lines[0])


@serial
@pytest.mark.parametrize("name, argv, named", [
    ("hertz", ["--E", "-1"], "--E must be a finite number > 0, got -1"),
    ("hertz", ["--E", "nan"], "--E must be a finite number > 0, got nan"),
    ("hertz", ["--approach", "0.001", "--load", "1"], "--load contradicts --approach"),
    ("sphere", ["--load", "1", "--approach", "0.001"], "--approach contradicts --load"),
    ("hertz", ["--plate-width", "16"], "--plate-width is used only with --plate meshed"),
    ("hertz", ["--stabilisation", "0.5"], "--stabilisation is used only with --load"),
    ("sphere", ["--plate-E", "5"], "--plate-E is used only with --plate meshed"),
    ("rings", ["--nu-outer", "0.5"], "--nu-outer must be a finite number in [0, 0.5)"),
    ("ironing", ["--theta", "0"], "--theta must be a finite number in (0, 90]"),
    ("ring", ["--R-in", "9"], "--R-in must be < --R-out (8), got 9"),
    ("rings", ["--a", "0.2", "--b", "1.5"], "--b must be < --c (1), got 1.5"),
    ("pin", ["--R", "2", "--above", "1.5"], "--R must be < --above (1.5), got 2"),
    ("hertz", ["--load", "1", "--symmetry", "half"], "--load is used only with --symmetry quarter"),
    ("sphere", ["--load", "1", "--plate", "meshed"], "--load is used only with --plate rigid (got --plate meshed)"),
    ("hertz", ["--contact-width", "2"], "--contact-width must be < --R (1), got 2"),
    ("block", ["--height", "1e-300"], "--height 1e-300: underflow: a length beyond floating point's range"),
    ("block", ["--width", "1e300"], "--width 1e+300: overflow: a length beyond floating point's range"),
    ("hertz", ["--R", "1e-300"], "--R 1e-300: underflow: a length"),
    ("oring", ["--E", "1e60"], "--E 1e+60: overflow: a stress beyond floating point's range for the scene's products "
                               "of it (areas, volumes, stiffnesses); accepted: --E of magnitude in [1e-50, 1e+50]"),
])
def test_contradictions_and_ranges_refused_while_parsing(name, argv, named, monkeypatch, capsys):
    end = _run(name, argv, monkeypatch)
    lines = [s for s in capsys.readouterr().err.splitlines() if s.strip()]
    assert end.code == cli.EXIT_USAGE and len(lines) == 1 and named in lines[0], lines


@serial
def test_options_that_agree_parse(monkeypatch):
    """The refusals above are of the contradiction, not of the options: each parses alone or with what it needs."""
    for argv in (["--load", "1", "--stabilisation", "0.5"], ["--plate", "meshed", "--plate-width", "16"],
                 ["--approach", "0.002"]):
        with pytest.raises(_Parsed):
            _run("hertz", argv, monkeypatch)
        monkeypatch.undo()


def test_approach_half_width_inverts_johnsons_approach():
    """``approach = (a^2 / 4R) (2 ln(4R/a) - 1)`` solved for ``a``; scales with ``R`` (lengths x 1e-3 alike)."""
    from fenics_contact.app.scenes.hertz import approach_half_width

    for R, a in ((1.0, 0.02), (8.0, 0.9), (1e-3, 3e-5)):
        approach = a * a / (4 * R) * (2 * math.log(4 * R / a) - 1)
        assert approach_half_width(approach, R) == pytest.approx(a, rel=1e-9)
    assert approach_half_width(10.0, 1.0) == 1.0  # past the formula's range: the radius


@serial
def test_two_identical_bodies_from_options_alone_within_1_percent():
    """The peer case with no plate size given: the plate follows the contact half-width a (PLATE_HALF_WIDTHS a
    wide and deep), p0 within 1 % of Hertz for two identical bodies (a 4 x 2 plate: 3.3 %); and the default
    approach's a against the disk's own estimate (Johnson's approach, used for the plate under displacement
    control)."""
    from fenics_contact.app.scenes import build, hertz
    from fenics_contact.methods import make_law
    from fenics_contact.solver import Solver

    setup = build("hertz", law=make_law("lagrange", c=2.5e4), plate="meshed", R=8.0, E=200.0, nu=0.3, load=10.0,
                  plate_E=200.0)
    a = hertz.hertz(10.0, 8.0, 200.0, 0.3, "strain", 200.0, 0.3)[0]
    assert setup.parameters["plate_width"] == pytest.approx(hertz.PLATE_HALF_WIDTHS * a)
    assert setup.parameters["plate_depth"] == pytest.approx(hertz.PLATE_HALF_WIDTHS * a)
    Solver(setup.problem, quiet=True).run(setup.loads)
    f = setup.figures()
    assert f["load_error"] < 1e-8 and f["p0_error"] < 0.01, f
    rigid = build("hertz", law=make_law("lagrange", c=1e6))
    Solver(rigid.problem, quiet=True).run(rigid.loads)
    g = rigid.figures()
    assert hertz.approach_half_width(hertz.APPROACH) == pytest.approx(g["a_hertz"], rel=0.02)


def test_a_scene_mesh_its_lengths_make_degenerate_names_them_not_a_mesh():
    """Lengths far apart (a block 1e20 wide and 2 high: cells of aspect ratio 1e20, degenerate in floating point)
    are named as the options given, not as a mesh to fix that the user never gave."""
    from fenics_contact.app.scenes import build
    from fenics_contact.laws import Penalty

    with pytest.raises(ValueError, match=r"^the scene's mesh made from --width 1e\+20 has 64 degenerate \(zero area or "
                                         r"volume\) cells of 64 .*: lengths that far apart .* give them closer"):
        build("block", law=Penalty(1e5), width=1e20)
