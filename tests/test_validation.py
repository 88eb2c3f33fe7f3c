"""Every bad input fails before integration with a ParameterError naming the parameter.

From Python: ``celtstone.ParameterError`` with ``name``, ``value`` and ``allowed``.
From the command line (``celtstone.cli.main.main`` in-process): exit status 2 and
exactly one line on standard error that names the parameter, the value and the
allowed range; no traceback, nothing on standard output.
"""

from __future__ import annotations

import math
import re
from importlib import resources
from pathlib import Path

import pytest

import celtstone as cs
import celtstone.simulation.integrate as integrate_module
from celtstone.cli.main import main

KL_NAME = "kane_levinson_1982"
_DATA = resources.files("celtstone.bodies") / "data"
ELLIPSOID_TOML = (_DATA / f"{KL_NAME}.toml").read_text(encoding="utf-8")
PARABOLOID_TOML = (_DATA / f"{KL_NAME}_paraboloid.toml").read_text(encoding="utf-8")

# Kane & Levinson (1982) numbers, ../shared/references.md
KL_INERTIA = ((2.0e-4, -2.0e-5, 0.0), (-2.0e-5, 1.6e-3, 0.0), (0.0, 0.0, 1.7e-3))
KL_AXES = (0.20, 0.03, 0.02)
KL_H = 0.01
KL_SHAPE = cs.Ellipsoid(KL_AXES, KL_H)


@pytest.fixture(autouse=True)
def no_integration(monkeypatch: pytest.MonkeyPatch) -> None:
    """Bad input must be refused before the integrator is ever called."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("the integrator was called although the input is invalid")

    monkeypatch.setattr(integrate_module.solvers, "solve", refuse)


def _body(**changes: object) -> cs.Body:
    fields: dict[str, object] = {
        "name": "test",
        "mass": 1.0,
        "inertia": KL_INERTIA,
        "shape": KL_SHAPE,
        "gravity": 9.81,
    }
    fields.update(changes)
    return cs.Body(**fields)  # type: ignore[arg-type]


def _same(a: object, b: object) -> bool:
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return a == b


# ---------------------------------------------------------------------------------------
# From Python
# ---------------------------------------------------------------------------------------

NAN = float("nan")
INF = float("inf")

# (id, callable building the object, parameter name, offending value, fragment of allowed)
PYTHON_CASES = [
    ("mass-zero", lambda: _body(mass=0.0), "mass", 0.0, "> 0"),
    ("mass-negative", lambda: _body(mass=-1.0), "mass", -1.0, "> 0"),
    ("mass-nan", lambda: _body(mass=NAN), "mass", NAN, "> 0"),
    ("mass-inf", lambda: _body(mass=INF), "mass", INF, "> 0"),
    ("mass-text", lambda: _body(mass="heavy"), "mass", "heavy", "> 0"),
    ("gravity-zero", lambda: _body(gravity=0.0), "gravity", 0.0, "> 0"),
    ("axis-a-zero", lambda: cs.Ellipsoid((0.0, 0.03, 0.02), 0.01), "semi_axes", 0.0, "> 0"),
    ("axis-b-negative", lambda: cs.Ellipsoid((0.2, -0.03, 0.02), 0.01), "semi_axes", -0.03, "> 0"),
    ("axis-c-inf", lambda: cs.Ellipsoid((0.2, 0.03, INF), 0.01), "semi_axes", INF, "> 0"),
    ("axis-c-nan", lambda: cs.Ellipsoid((0.2, 0.03, NAN), 0.01), "semi_axes", NAN, "> 0"),
    ("axes-two", lambda: cs.Ellipsoid((0.2, 0.03), 0.01), "semi_axes", (0.2, 0.03), "three"),
    ("h-at-bottom", lambda: cs.Ellipsoid(KL_AXES, 0.02), "com_offset", 0.02, "(-0.02, 0.02)"),
    ("h-at-top", lambda: cs.Ellipsoid(KL_AXES, -0.02), "com_offset", -0.02, "(-0.02, 0.02)"),
    ("h-outside", lambda: cs.Ellipsoid(KL_AXES, 0.05), "com_offset", 0.05, "(-0.02, 0.02)"),
    ("h-nan", lambda: cs.Ellipsoid(KL_AXES, NAN), "com_offset", NAN, "(-0.02, 0.02)"),
    ("h-text", lambda: cs.Ellipsoid(KL_AXES, "low"), "com_offset", "low", "(-0.02, 0.02)"),
    (
        "inertia-negative-eigenvalue",
        lambda: _body(inertia=((2e-4, 0, 0), (0, -1.6e-3, 0), (0, 0, 1.7e-3))),
        "inertia",
        None,
        "positive-definite",
    ),
    (
        "inertia-singular",
        lambda: _body(inertia=((0.0, 0, 0), (0, 1.6e-3, 0), (0, 0, 1.6e-3))),
        "inertia",
        None,
        "positive-definite",
    ),
    (
        # eigenvalues 1e-3 +- 2e-3: indefinite although the diagonal is positive
        "inertia-indefinite-positive-diagonal",
        lambda: _body(inertia=((1e-3, 2e-3, 0), (2e-3, 1e-3, 0), (0, 0, 1e-3))),
        "inertia",
        None,
        "positive-definite",
    ),
    (
        "inertia-not-symmetric",
        lambda: _body(inertia=((2e-4, -2e-5, 0), (2e-5, 1.6e-3, 0), (0, 0, 1.7e-3))),
        "inertia",
        None,
        "symmetric",
    ),
    (
        # principal moments 1e-4, 1e-4, 1e-3: A3 > A1 + A2, no real mass distribution
        "inertia-triangle",
        lambda: _body(inertia=((1e-4, 0, 0), (0, 1e-4, 0), (0, 0, 1e-3))),
        "inertia",
        None,
        "A3 <= A1 + A2",
    ),
    (
        "inertia-nan",
        lambda: _body(inertia=((NAN, 0, 0), (0, 1.6e-3, 0), (0, 0, 1.7e-3))),
        "inertia",
        None,
        "finite",
    ),
    (
        "inertia-2x2",
        lambda: _body(inertia=((2e-4, 0), (0, 1.6e-3))),
        "inertia",
        None,
        "3x3",
    ),
    (
        "radius-zero",
        lambda: cs.Paraboloid((0.0, 0.045), 0.01),
        "radii_of_curvature",
        0.0,
        "> 0",
    ),
    (
        "radius-count",
        lambda: cs.Paraboloid((2.0,), 0.01),
        "radii_of_curvature",
        (2.0,),
        "two",
    ),
    ("com-height-zero", lambda: cs.Paraboloid((2.0, 0.045), 0.0), "com_height", 0.0, "> 0"),
    (
        "f-negative",
        lambda: cs.SlidingModel(friction_coefficient=-0.01),
        "friction_coefficient",
        -0.01,
        ">= 0",
    ),
    (
        "f-nan",
        lambda: cs.SlidingModel(friction_coefficient=NAN),
        "friction_coefficient",
        NAN,
        ">= 0",
    ),
    (
        "f-inf",
        lambda: cs.SlidingModel(friction_coefficient=INF),
        "friction_coefficient",
        INF,
        ">= 0",
    ),
    ("eps-zero", lambda: cs.SlidingModel(contact_radius=0.0), "contact_radius", 0.0, "> 0"),
    ("eps-negative", lambda: cs.SlidingModel(contact_radius=-1e-3), "contact_radius", -1e-3, "> 0"),
    (
        "delta-zero",
        lambda: cs.SlidingModel(regularisation_speed=0.0),
        "regularisation_speed",
        0.0,
        "> 0",
    ),
    ("sliding-damping", lambda: cs.SlidingModel(damping=-1e-4), "damping", -1e-4, ">= 0"),
    ("rolling-damping", lambda: cs.RollingModel(damping=-1e-4), "damping", -1e-4, ">= 0"),
    (
        "friction-load",
        lambda: cs.SlidingModel(friction_load="dynamc"),
        "friction_load",
        "dynamc",
        "static, dynamic",
    ),
    ("model", lambda: cs.model_from_name("slidng"), "model", "slidng", "rolling, sliding"),
    (
        "rolling-refuses-friction",
        lambda: cs.model_from_name("rolling", friction_coefficient=0.3),
        "friction_coefficient",
        0.3,
        "no value with the rolling model",
    ),
    (
        "rolling-refuses-friction-load",
        lambda: cs.model_from_name("rolling", friction_load="dynamic"),
        "friction_load",
        "dynamic",
        "no value with the rolling model",
    ),
    (
        "sliding-refuses-capture-speed",
        lambda: cs.model_from_name("sliding", capture_speed=1e-9),
        "capture_speed",
        1e-9,
        "no value with the sliding contact",
    ),
    ("omega-nan", lambda: cs.InitialState(omega=(NAN, 0, -5)), "omega", NAN, "[-10000, 10000]"),
    ("omega-inf", lambda: cs.InitialState(omega=(0, 0, -INF)), "omega", -INF, "[-10000, 10000]"),
    (
        "omega-huge",
        lambda: cs.InitialState(omega=(0, 0, 1e300)),
        "omega",
        1e300,
        "[-10000, 10000]",
    ),
    ("omega-two", lambda: cs.InitialState(omega=(0, -5)), "omega", (0, -5), "three"),
    # booleans and text are not numbers (tests/test_api_validation.py has the variants)
    ("omega-bool", lambda: cs.InitialState(omega=True), "omega", True, "three"),
    ("omega-text", lambda: cs.InitialState(omega="005"), "omega", "005", "three"),
    (
        "f-text",
        lambda: cs.SlidingModel(friction_coefficient="0.3"),
        "friction_coefficient",
        "0.3",
        ">= 0",
    ),
    (
        "f-bool",
        lambda: cs.SlidingModel(friction_coefficient=True),
        "friction_coefficient",
        True,
        ">= 0",
    ),
    (
        # the Hertz radius replaces a fixed one: both given is a contradiction, not a choice
        "eps-with-hertz",
        lambda: cs.SlidingModel(contact_radius=2e-3, elastic_modulus=2e9, poisson_ratio=0.35),
        "contact_radius",
        2e-3,
        "no value with elastic_modulus",
    ),
    (
        "euler-90",
        lambda: cs.InitialState(euler_angles=(90.0, 0.0)),
        "euler_angles",
        90.0,
        "[-89, 89]",
    ),
    (
        "euler-minus-95",
        lambda: cs.InitialState(euler_angles=(0.0, -95.0)),
        "euler_angles",
        -95.0,
        "[-89, 89]",
    ),
    (
        "euler-nan",
        lambda: cs.InitialState(euler_angles=(0.0, NAN)),
        "euler_angles",
        NAN,
        "[-89, 89]",
    ),
    ("body-unknown", lambda: cs.load_body("cube"), "body", "cube", KL_NAME),
    ("body-missing-file", lambda: cs.load_body("missing.toml"), "body", "missing.toml", ".toml"),
]


@pytest.mark.parametrize(
    ("build", "name", "value", "allowed"),
    [case[1:] for case in PYTHON_CASES],
    ids=[case[0] for case in PYTHON_CASES],
)
def test_python_rejects(build, name: str, value: object, allowed: str) -> None:
    with pytest.raises(cs.ParameterError) as caught:
        build()
    error = caught.value
    assert error.name == name
    if value is not None:
        assert _same(error.value, value)
    assert allowed in error.allowed
    message = str(error)
    assert name in message
    assert allowed in message
    assert "\n" not in message


@pytest.mark.parametrize(
    ("keywords", "name", "value", "allowed"),
    [
        ({"t_end": 0.0}, "t_end", 0.0, "(0, 1e+06]"),
        ({"t_end": -1.0}, "t_end", -1.0, "(0, 1e+06]"),
        ({"t_end": NAN}, "t_end", NAN, "(0, 1e+06]"),
        ({"t_end": INF}, "t_end", INF, "(0, 1e+06]"),
        ({"t_end": 1e12}, "t_end", 1e12, "(0, 1e+06]"),
        ({"rtol": 0.0}, "rtol", 0.0, "[1e-14, 0.01]"),
        ({"rtol": 1e-15}, "rtol", 1e-15, "[1e-14, 0.01]"),
        ({"rtol": 0.02}, "rtol", 0.02, "[1e-14, 0.01]"),
        ({"rtol": NAN}, "rtol", NAN, "[1e-14, 0.01]"),
        ({"atol": 0.0}, "atol", 0.0, "(0, 0.001]"),
        ({"atol": -1e-12}, "atol", -1e-12, "(0, 0.001]"),
        ({"atol": 1e300}, "atol", 1e300, "(0, 0.001]"),
        ({"method": "rk45"}, "method", "rk45", "dop853"),
        ({"method": "rk45"}, "method", "rk45", "radau5"),
        ({"n_samples": 1}, "n_samples", 1, "[2, 1e+06]"),
        ({"n_samples": 10**12}, "n_samples", 10**12, "[2, 1e+06]"),
        ({"max_steps": 0}, "max_steps", 0, ">= 1"),
        ({"t_end": "5"}, "t_end", "5", "(0, 1e+06]"),
        ({"t_end": True}, "t_end", True, "(0, 1e+06]"),
        ({"n_samples": 2.5}, "n_samples", 2.5, "an integer in [2, 1e+06]"),
        ({"max_steps": 2.5}, "max_steps", 2.5, "an integer >= 1"),
    ],
    ids=lambda v: str(v) if not isinstance(v, dict) else "-".join(map(str, v.items())),
)
def test_simulate_rejects(
    kane_levinson: cs.Body, keywords: dict, name: str, value: object, allowed: str
) -> None:
    arguments = {"t_end": 1.0, **keywords}
    t_end = arguments.pop("t_end")
    with pytest.raises(cs.ParameterError) as caught:
        cs.simulate(cs.RollingModel(), kane_levinson, cs.InitialState(), t_end, **arguments)
    assert caught.value.name == name
    assert _same(caught.value.value, value)
    assert allowed in caught.value.allowed


def test_simulate_rejects_decreasing_sample_times(kane_levinson: cs.Body) -> None:
    with pytest.raises(cs.ParameterError) as caught:
        cs.simulate(
            cs.RollingModel(), kane_levinson, cs.InitialState(), 1.0, sample_times=[0.0, 0.5, 0.2]
        )
    assert caught.value.name == "sample_times"


@pytest.mark.parametrize(
    ("build", "suggestion"),
    [
        (lambda: cs.load_body("kane_levinson_1928"), KL_NAME),
        (lambda: cs.load_body("kane_levinson_1982_parabolid"), f"{KL_NAME}_paraboloid"),
        (lambda: cs.model_from_name("slidng"), "sliding"),
        (lambda: cs.model_from_name("Rolling"), "rolling"),
        (lambda: cs.SlidingModel(friction_load="dynamc"), "dynamic"),
    ],
    ids=["body", "body-paraboloid", "model", "model-capital", "friction-load"],
)
def test_unknown_names_suggest_the_closest(build, suggestion: str) -> None:
    with pytest.raises(cs.ParameterError) as caught:
        build()
    assert f"did you mean {suggestion!r}" in str(caught.value)


def test_unknown_method_suggests_the_closest(kane_levinson: cs.Body) -> None:
    with pytest.raises(cs.ParameterError, match="did you mean 'dop853'"):
        cs.simulate(cs.RollingModel(), kane_levinson, cs.InitialState(), 1.0, method="dop835")


def test_parameter_error_is_a_value_error_and_a_celtstone_error() -> None:
    with pytest.raises(ValueError):
        _body(mass=-1.0)
    with pytest.raises(cs.CeltstoneError):
        _body(mass=-1.0)


# ---------------------------------------------------------------------------------------
# From the command line
# ---------------------------------------------------------------------------------------


def _cli_error(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    """Run ``celtstone ARGV``; assert exit 2, one stderr line, no stdout; return the line."""
    status = main(argv)
    out, err = capsys.readouterr()
    assert status == 2, (out, err)
    assert out == ""
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert err.endswith("\n")
    return lines[0]


def _names(line: str, name: str) -> bool:
    """Whether ``line`` names the parameter, as schema spells it or as its CLI flag."""
    spellings = {name, "--" + name.replace("_", "-"), name.replace("_", "-")}
    return any(re.search(rf"(?<![\w-]){re.escape(s)}(?![\w-])", line) for s in spellings)


def _shows(line: str, values: tuple[str, ...]) -> bool:
    """Whether ``line`` shows one of the spellings of the value as a whole token."""
    return any(re.search(rf"(?<![\w.]){re.escape(v)}(?![\w.])", line) for v in values)


def _check_line(line: str, name: str, values: tuple[str, ...], allowed: tuple[str, ...]) -> None:
    assert _names(line, name), line
    assert _shows(line, values), line
    for fragment in allowed:
        assert fragment in line, line


# (extra argv, parameter, spellings of the value, fragments of the allowed range)
CLI_CASES = [
    (["--t-end", "-2.5"], "t_end", ("-2.5",), ("(0, 1e+06]",)),
    (["--t-end", "0"], "t_end", ("0", "0.0"), ("(0, 1e+06]",)),
    (["--t-end", "abc"], "t_end", ("abc",), ("(0, 1e+06]",)),
    (["--t-end", "nan"], "t_end", ("nan",), ("(0, 1e+06]",)),
    (["--t-end", "inf"], "t_end", ("inf",), ("(0, 1e+06]",)),
    (["--t-end", "1e12"], "t_end", ("1e12", "1000000000000.0"), ("(0, 1e+06]",)),
    (["--rtol", "0.5"], "rtol", ("0.5",), ("1e-14", "0.01")),
    (["--rtol", "1e-16"], "rtol", ("1e-16",), ("1e-14", "0.01")),
    (["--rtol", "tight"], "rtol", ("tight",), ("1e-14", "0.01")),
    (["--atol", "-1e-12"], "atol", ("-1e-12",), ("(0, 0.001]",)),
    (["--atol", "1e300"], "atol", ("1e300", "1e+300"), ("(0, 0.001]",)),
    (["--omega", "0,0,1e300"], "omega", ("1e+300",), ("[-10000, 10000]",)),
    (["--damping", "-0.0001"], "damping", ("-0.0001",), (">= 0",)),
    (
        ["--model", "sliding", "--friction-coefficient", "-0.1"],
        "friction_coefficient",
        ("-0.1",),
        (">= 0",),
    ),
    (
        ["--model", "sliding", "--friction-coefficient", "inf"],
        "friction_coefficient",
        ("inf",),
        (">= 0",),
    ),
    (
        ["--model", "sliding", "--friction-coefficient", "nan"],
        "friction_coefficient",
        ("nan",),
        (">= 0",),
    ),
    (
        ["--model", "sliding", "--contact-radius", "-0.001"],
        "contact_radius",
        ("-0.001",),
        ("> 0",),
    ),
    (["--model", "sliding", "--contact-radius", "0"], "contact_radius", ("0", "0.0"), ("> 0",)),
    # an option the rolling model does not use is refused, not silently ignored
    (
        ["--model", "rolling", "--contact-radius", "0.002"],
        "contact_radius",
        ("0.002",),
        ("rolling model", "'sliding'"),
    ),
    (
        ["--model", "rolling", "--friction-coefficient", "0.3"],
        "friction_coefficient",
        ("0.3",),
        ("rolling model", "'sliding'"),
    ),
    (
        ["--model", "rolling", "--friction-law", "exact"],
        "friction_law",
        ("exact",),
        ("rolling model", "'sliding'"),
    ),
    (
        ["--model", "rolling", "--elastic-modulus", "2e9", "--poisson-ratio", "0.35"],
        "elastic_modulus",
        ("2000000000.0",),
        ("rolling model", "'sliding'"),
    ),
    (
        ["--model", "sliding", "--capture-speed", "1e-9"],
        "capture_speed",
        ("1e-09",),
        ("sliding contact", "'hybrid'"),
    ),
    (
        ["--model", "sliding", "--regularisation-speed", "-1e-06"],
        "regularisation_speed",
        ("-1e-06",),
        ("> 0",),
    ),
    (
        ["--model", "sliding", "--friction-load", "dynamc"],
        "friction_load",
        ("dynamc",),
        ("static", "dynamic", "did you mean 'dynamic'"),
    ),
    (
        ["--model", "rolling", "--friction-load", "dynamic"],
        "friction_load",
        ("dynamic",),
        ("rolling model",),
    ),
    (
        ["--body", "kane_levinson_1928"],
        "body",
        ("kane_levinson_1928",),
        (KL_NAME, f"did you mean {KL_NAME!r}"),
    ),
    (["--body", "nowhere.toml"], "body", ("nowhere.toml",), (".toml",)),
    (["--model", "slidng"], "model", ("slidng",), ("rolling", "sliding", "did you mean 'sliding'")),
    (["--model", "stick"], "model", ("stick",), ("rolling", "sliding")),
    (["--method", "rk45"], "method", ("rk45",), ("dop853", "radau5")),
    (["--omega", "1,2"], "omega", ("1,2",), ("3",)),
    (["--omega", "a,b,c"], "omega", ("a,b,c",), ("3",)),
    (["--omega", "1,2,3,4"], "omega", ("1,2,3,4",), ("3",)),
    (["--omega", "nan,0,-5"], "omega", ("nan,0,-5",), ("finite",)),
    (["--omega", "0,0,inf"], "omega", ("0,0,inf",), ("finite",)),
    (["--omega", "0;0;-5"], "omega", ("0;0;-5",), ("3",)),
    (["--euler-angles", "95,0"], "euler_angles", ("95", "95.0"), ("-89", "89")),
    (["--euler-angles", "0,-90"], "euler_angles", ("-90", "-90.0"), ("-89", "89")),
    (["--euler-angles", "0.5"], "euler_angles", ("0.5",), ("2",)),
    (["--euler-angles", "0.5,nan"], "euler_angles", ("0.5,nan",), ("finite",)),
    (["--samples", "1"], "n_samples", ("1", "1.0"), ("[2, 1e+06]",)),
    (["--samples", "nan"], "n_samples", ("nan",), ("[2, 1e+06]",)),
    (["--samples", "inf"], "n_samples", ("inf",), ("[2, 1e+06]",)),
    (["--samples", "1e12"], "n_samples", ("1e12", "1000000000000.0"), ("[2, 1e+06]",)),
    # counts are integers, and Python's float() reads more than a command line should
    (["--samples", "2.5"], "n_samples", ("2.5",), ("an integer in [2, 1e+06]",)),
    (["--samples", "1_0"], "n_samples", ("1_0",), ("[2, 1e+06]",)),
    (["--t-end", "1_0"], "t_end", ("1_0",), ("(0, 1e+06]",)),
    (
        [
            "--model",
            "sliding",
            "--contact-radius",
            "0.002",
            "--elastic-modulus",
            "2e9",
            "--poisson-ratio",
            "0.35",
        ],
        "contact_radius",
        ("0.002",),
        ("no value with elastic_modulus",),
    ),
    (["--out", "file.txt"], "out", ("file.txt",), (".nc", ".csv")),
    (["--out", "file"], "out", ("file",), (".nc", ".csv")),
]


@pytest.mark.parametrize(
    ("argv", "name", "values", "allowed"),
    CLI_CASES,
    ids=[" ".join(case[0]) for case in CLI_CASES],
)
def test_cli_rejects(
    capsys: pytest.CaptureFixture[str],
    argv: list[str],
    name: str,
    values: tuple[str, ...],
    allowed: tuple[str, ...],
) -> None:
    line = _cli_error(capsys, ["run", "--t-end", "1", *argv])
    _check_line(line, name, values, allowed)


def test_cli_rejects_out_in_missing_directory(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    target = tmp_path / "missing" / "run.nc"
    line = _cli_error(capsys, ["run", "--t-end", "1", "--out", str(target)])
    _check_line(line, "out", (str(target),), ("existing directory",))
    assert not target.parent.exists()
    assert list(tmp_path.iterdir()) == []


def test_cli_negative_first_component_is_a_number_not_an_option(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """``--omega -5,0,0`` and ``--euler-angles -95,0`` are values: the range check, not argparse,
    must answer."""
    line = _cli_error(capsys, ["run", "--euler-angles", "-95,0"])
    _check_line(line, "euler_angles", ("-95", "-95.0"), ("-89", "89"))
    line = _cli_error(capsys, ["run", "--omega", "-nan,0,0"])
    _check_line(line, "omega", ("-nan,0,0",), ("finite",))


def test_cli_usage_errors_are_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    for argv in (["run", "--no-such-option"], ["fly"], ["run", "--omega"]):
        status = main(argv)
        out, err = capsys.readouterr()
        assert status == 2, argv
        assert out == ""
        assert len(err.splitlines()) == 1, (argv, err)
        assert "Traceback" not in err


# ---------------------------------------------------------------------------------------
# Body files with errors, loaded with --body PATH.toml
# ---------------------------------------------------------------------------------------


def _edit(template: str, key: str, value: str) -> str:
    """Replace the line ``key = ...`` of the template with ``key = value``."""
    pattern = re.compile(rf"^{re.escape(key)} = .*$", re.MULTILINE)
    assert len(pattern.findall(template)) == 1, key
    return pattern.sub(lambda _: f"{key} = {value}", template)


# (id, template, key, new TOML value, parameter, value spellings, allowed fragments)
BODY_FILE_CASES = [
    ("mass-zero", ELLIPSOID_TOML, "mass", "0.0", "mass", ("0.0",), ("> 0",)),
    ("mass-negative", ELLIPSOID_TOML, "mass", "-1.5", "mass", ("-1.5",), ("> 0",)),
    ("mass-nan", ELLIPSOID_TOML, "mass", "nan", "mass", ("nan",), ("> 0",)),
    ("mass-text", ELLIPSOID_TOML, "mass", '"heavy"', "mass", ("heavy",), ("> 0",)),
    ("gravity-negative", ELLIPSOID_TOML, "gravity", "-9.81", "gravity", ("-9.81",), ("> 0",)),
    (
        "semi-axis-zero",
        ELLIPSOID_TOML,
        "semi_axes",
        "[0.20, 0.0, 0.02]",
        "semi_axes",
        ("0.0",),
        ("> 0",),
    ),
    (
        "semi-axis-negative",
        ELLIPSOID_TOML,
        "semi_axes",
        "[-0.20, 0.03, 0.02]",
        "semi_axes",
        ("-0.2",),
        ("> 0",),
    ),
    (
        "semi-axis-inf",
        ELLIPSOID_TOML,
        "semi_axes",
        "[0.20, 0.03, inf]",
        "semi_axes",
        ("inf",),
        ("> 0",),
    ),
    (
        "h-equal-c",
        ELLIPSOID_TOML,
        "com_offset",
        "0.02",
        "com_offset",
        ("0.02",),
        ("(-0.02, 0.02)",),
    ),
    (
        "h-above-top",
        ELLIPSOID_TOML,
        "com_offset",
        "-0.025",
        "com_offset",
        ("-0.025",),
        ("(-0.02, 0.02)",),
    ),
    (
        "h-nan",
        ELLIPSOID_TOML,
        "com_offset",
        "nan",
        "com_offset",
        ("nan",),
        ("(-0.02, 0.02)",),
    ),
    (
        "h-text",
        ELLIPSOID_TOML,
        "com_offset",
        '"low"',
        "com_offset",
        ("low",),
        ("(-0.02, 0.02)",),
    ),
    (
        "inertia-not-positive-definite",
        ELLIPSOID_TOML,
        "inertia",
        "[[2.0e-4, -2.0e-5, 0.0], [-2.0e-5, -1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]",
        "inertia",
        ("-0.0016",),
        ("positive-definite",),
    ),
    (
        "inertia-not-symmetric",
        ELLIPSOID_TOML,
        "inertia",
        "[[2.0e-4, -2.0e-5, 0.0], [2.0e-5, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]",
        "inertia",
        ("2e-05",),
        ("symmetric",),
    ),
    (
        "inertia-triangle",
        ELLIPSOID_TOML,
        "inertia",
        "[[1.0e-4, 0.0, 0.0], [0.0, 1.0e-4, 0.0], [0.0, 0.0, 1.0e-3]]",
        "inertia",
        ("0.001",),
        ("A3 <= A1 + A2",),
    ),
    (
        "inertia-inf",
        ELLIPSOID_TOML,
        "inertia",
        "[[inf, 0.0, 0.0], [0.0, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]",
        "inertia",
        ("inf",),
        ("finite",),
    ),
    (
        "inertia-ragged",
        ELLIPSOID_TOML,
        "inertia",
        "[[2.0e-4, 0.0], [0.0, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]",
        "inertia",
        ("0.0002",),
        ("3x3",),
    ),
    (
        "shape-kind",
        ELLIPSOID_TOML,
        "kind",
        '"cube"',
        "shape.kind",
        ("cube",),
        ("ellipsoid", "paraboloid"),
    ),
    (
        "paraboloid-radius-negative",
        PARABOLOID_TOML,
        "radii_of_curvature",
        "[2.0, -0.045]",
        "radii_of_curvature",
        ("-0.045",),
        ("> 0",),
    ),
    (
        "paraboloid-height-zero",
        PARABOLOID_TOML,
        "com_height",
        "0.0",
        "com_height",
        ("0.0",),
        ("> 0",),
    ),
]


@pytest.mark.parametrize(
    ("template", "key", "toml_value", "name", "values", "allowed"),
    [case[1:] for case in BODY_FILE_CASES],
    ids=[case[0] for case in BODY_FILE_CASES],
)
def test_body_file_errors(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    template: str,
    key: str,
    toml_value: str,
    name: str,
    values: tuple[str, ...],
    allowed: tuple[str, ...],
) -> None:
    path = tmp_path / "bad_body.toml"
    path.write_text(_edit(template, key, toml_value), encoding="utf-8")
    with pytest.raises(cs.ParameterError) as caught:
        cs.load_body(path)
    assert caught.value.name == name
    line = _cli_error(capsys, ["run", "--t-end", "1", "--body", str(path)])
    _check_line(line, name, values, allowed)


def test_the_template_itself_loads(tmp_path: Path) -> None:
    """The edits above are the only fault: the unedited copy is a valid body."""
    for text in (ELLIPSOID_TOML, PARABOLOID_TOML):
        path = tmp_path / "good.toml"
        path.write_text(text, encoding="utf-8")
        body = cs.load_body(path)
        assert body.mass == 1.0
        assert body.name == "good"


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        (ELLIPSOID_TOML.replace("[shape]", "[form]"), "[shape]"),
        (ELLIPSOID_TOML.replace("mass = 1.0", "weight = 1.0"), "mass"),
        (ELLIPSOID_TOML.replace("[body]", "[body"), "TOML"),
        (_edit(ELLIPSOID_TOML, "semi_axes", "0.2"), "number"),
    ],
    ids=["no-shape-table", "no-mass", "bad-toml", "scalar-semi-axes"],
)
def test_malformed_body_files(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, text: str, fragment: str
) -> None:
    path = tmp_path / "broken.toml"
    path.write_text(text, encoding="utf-8")
    line = _cli_error(capsys, ["run", "--t-end", "1", "--body", str(path)])
    assert "body" in line
    assert str(path) in line or "broken" in line
    assert fragment in line
