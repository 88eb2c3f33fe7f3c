"""The Python API and the command line refuse the same bad input by one path, and no
input gives a silent wrong answer.

One validation path: ``schema.check`` (numbers), ``schema.check_count`` (counts) and
``schema.check_components`` (vectors) raise ``ParameterError`` with the same words from
Python as from the command line; the command line turns text into numbers first
(``schema.parse_number``, ``schema.parse_count``). Booleans, text and None are not
numbers; a count is an integer; NumPy scalars are numbers.

Silent answers: the friction law at huge slip ratios (the pure-sliding limit F -> f N of
``../shared/references.md``), a contact radius that the Hertz contact overrides, and a
sweep of a number that has no effect.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import celtstone as cs
import celtstone.simulation.integrate as integrate_module
from celtstone.cli.main import main
from celtstone.contact import friction_functions, friction_integrals
from celtstone.contact.ellipse import elliptic_friction_functions
from celtstone.contact.ellipse_table import fast_friction_functions
from celtstone.simulation import schema
from celtstone.sweep import Sweep

NAN = float("nan")


class Reached(Exception):
    """Raised by the stand-in solver: the arguments passed validation."""

    def __init__(self, kwargs: dict) -> None:
        super().__init__("the solver was reached")
        self.kwargs = kwargs


@pytest.fixture(autouse=True)
def no_integration(monkeypatch: pytest.MonkeyPatch) -> None:
    """Input that passes validation reaches this stand-in, never a real run."""

    def reached(*args: object, **kwargs: object) -> None:
        raise Reached(kwargs)

    monkeypatch.setattr(integrate_module.solvers, "solve", reached)


def _refused(build: Callable[[], object], name: str) -> cs.ParameterError:
    """``build()`` raises a one-line ParameterError naming ``name``; return it."""
    with pytest.raises(cs.ParameterError) as caught:
        build()
    error = caught.value
    assert error.name == name, str(error)
    message = str(error)
    assert message.startswith(f"{name} = ") and "\n" not in message
    assert error.allowed in message
    return error


def _cli_line(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    """Run ``celtstone ARGV`` in-process: exit 2, one line on stderr, nothing on stdout."""
    status = main(argv)
    out, err = capsys.readouterr()
    assert status == 2, (out, err)
    assert out == ""
    assert "Traceback" not in err
    assert len(err.splitlines()) == 1, err
    return err


# ---------------------------------------------------------------------------------------
# simulate's objects
# ---------------------------------------------------------------------------------------

NOT_OBJECTS = [None, "kane_levinson_1982", (0.0, 0.0, -5.0), [1, 2], 3.0, True]


@pytest.mark.parametrize("value", NOT_OBJECTS, ids=repr)
def test_simulate_refuses_a_model_that_is_no_model(kane_levinson: cs.Body, value) -> None:
    _refused(lambda: cs.simulate(value, kane_levinson, cs.InitialState(), 1.0), "model")


@pytest.mark.parametrize("value", NOT_OBJECTS, ids=repr)
def test_simulate_refuses_a_body_that_is_no_body(value) -> None:
    error = _refused(lambda: cs.simulate(cs.RollingModel(), value, cs.InitialState(), 1.0), "body")
    assert "load_body" in error.hint


@pytest.mark.parametrize("value", NOT_OBJECTS, ids=repr)
def test_simulate_refuses_a_state_that_is_no_state(kane_levinson: cs.Body, value) -> None:
    _refused(lambda: cs.simulate(cs.RollingModel(), kane_levinson, value, 1.0), "initial_state")


def test_simulate_refuses_a_model_class_and_says_to_make_one(kane_levinson: cs.Body) -> None:
    error = _refused(
        lambda: cs.simulate(cs.SlidingModel, kane_levinson, cs.InitialState(), 1.0), "model"
    )
    assert "SlidingModel()" in error.hint


# ---------------------------------------------------------------------------------------
# Numbers: booleans, text and None are not numbers; NumPy scalars are
# ---------------------------------------------------------------------------------------

NOT_NUMBERS = ["5", "0.3", True, False, np.True_, None, [5.0], b"5", 1j]


@pytest.mark.parametrize("value", NOT_NUMBERS, ids=repr)
@pytest.mark.parametrize("name", ["t_end", "rtol", "atol"])
def test_simulate_refuses_numbers_that_are_not_numbers(
    kane_levinson: cs.Body, name: str, value
) -> None:
    arguments = {"t_end": 1.0, name: value}
    t_end = arguments.pop("t_end")
    error = _refused(
        lambda: cs.simulate(
            cs.RollingModel(), kane_levinson, cs.InitialState(), t_end, **arguments
        ),
        name,
    )
    assert error.allowed == schema.PARAMETERS[name].allowed  # the CLI's words


@pytest.mark.parametrize("value", NOT_NUMBERS, ids=repr)
@pytest.mark.parametrize(
    "name", ["friction_coefficient", "contact_radius", "damping", "regularisation_speed"]
)
def test_models_refuse_settings_that_are_not_numbers(name: str, value) -> None:
    _refused(lambda: cs.SlidingModel(**{name: value}), name)
    if value is not None:  # model_from_name reads None as "the default"
        _refused(lambda: cs.model_from_name("sliding", **{name: value}), name)


@pytest.mark.parametrize(
    ("name", "value", "expected"),
    [
        ("friction_coefficient", np.float32(0.25), 0.25),  # exact in binary
        ("friction_coefficient", np.float64(0.3), 0.3),
        ("friction_coefficient", np.int64(1), 1.0),
        ("friction_coefficient", np.array(0.5), 0.5),  # 0-d array
        ("friction_coefficient", -0.0, 0.0),  # >= 0 holds for negative zero
        ("contact_radius", np.float64(2e-3), 2e-3),
        ("damping", 0, 0.0),
    ],
    ids=repr,
)
def test_models_take_numpy_scalars_as_python_floats(name: str, value, expected: float) -> None:
    stored = getattr(cs.SlidingModel(**{name: value}), name)
    assert type(stored) is float
    assert stored == expected


@pytest.mark.parametrize("value", [-0.0, 0.0, -1e-300], ids=repr)
def test_a_positive_quantity_refuses_zero_of_either_sign(value: float) -> None:
    _refused(lambda: cs.SlidingModel(contact_radius=value), "contact_radius")


def test_simulate_takes_numpy_scalars(kane_levinson: cs.Body) -> None:
    with pytest.raises(Reached) as reached:
        cs.simulate(
            cs.RollingModel(),
            kane_levinson,
            cs.InitialState(omega=np.array([0.0, 0.0, -5.0])),
            np.float64(2.0),
            rtol=np.float32(1e-6),
            n_samples=np.int64(11),
            max_steps=np.int32(1000),
        )
    kwargs = reached.value.kwargs
    assert kwargs["max_steps"] == 1000
    np.testing.assert_array_equal(kwargs["sample_times"], np.linspace(0.0, 2.0, 11))


# ---------------------------------------------------------------------------------------
# Counts are integers
# ---------------------------------------------------------------------------------------

NOT_COUNTS = [2.5, 10.0, "10", True, np.True_, np.float64(10.0), [10]]  # None: the default


@pytest.mark.parametrize("value", NOT_COUNTS, ids=repr)
@pytest.mark.parametrize("name", ["n_samples", "max_steps", "max_crossings"])
def test_simulate_refuses_counts_that_are_not_integers(
    kane_levinson: cs.Body, name: str, value
) -> None:
    error = _refused(
        lambda: cs.simulate(
            cs.RollingModel(), kane_levinson, cs.InitialState(), 1.0, **{name: value}
        ),
        name,
    )
    assert error.allowed.startswith("an integer")


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("n_samples", 1),
        ("n_samples", 10**12),
        ("max_steps", 0),
        ("max_steps", None),
        ("max_crossings", 0),
        ("max_crossings", None),
    ],
)
def test_simulate_refuses_counts_out_of_range(kane_levinson: cs.Body, name: str, value) -> None:
    _refused(
        lambda: cs.simulate(
            cs.RollingModel(), kane_levinson, cs.InitialState(), 1.0, **{name: value}
        ),
        name,
    )


@pytest.mark.parametrize("value", [0, -1, 1.5, True, "4", None], ids=repr)
def test_the_workers_count_refuses_what_is_not_a_positive_integer(value) -> None:
    _refused(lambda: schema.check_count("workers", value), "workers")


@pytest.mark.parametrize("value", [1, np.int64(3), np.array(8), np.uint8(2)], ids=repr)
def test_a_count_takes_numpy_integers_as_ints(value) -> None:
    count = schema.check_count("workers", value)
    assert type(count) is int and count == int(value)


def test_simulate_refuses_a_progress_that_cannot_be_called(kane_levinson: cs.Body) -> None:
    _refused(
        lambda: cs.simulate(cs.RollingModel(), kane_levinson, cs.InitialState(), 1.0, progress=1),
        "progress",
    )


@pytest.mark.parametrize(
    "times",
    ["abc", "0.5", [True, False], [None, 0.5], [[0.0, 0.5]], [[0.0], [0.1, 0.2]], []],
    ids=repr,
)
def test_simulate_refuses_sample_times_that_are_not_times(kane_levinson: cs.Body, times) -> None:
    _refused(
        lambda: cs.simulate(
            cs.RollingModel(), kane_levinson, cs.InitialState(), 1.0, sample_times=times
        ),
        "sample_times",
    )


# ---------------------------------------------------------------------------------------
# The initial state: three and two numbers
# ---------------------------------------------------------------------------------------

BAD_OMEGAS = [
    True,
    None,
    5.0,
    "005",
    "0,0,-5",
    (True, 0.0, -5.0),
    ("0", 0.0, -5.0),
    (0.0, -5.0),
    (0.0, 0.0, -5.0, 1.0),
    {0.0, 1.0, -5.0},
    {"x": 0.0, "y": 0.0, "z": -5.0},
    np.zeros((3, 3)),
    np.array([[0.0, 0.0, -5.0]]),
    (0.0, 0.0, NAN),
]


@pytest.mark.parametrize("omega", BAD_OMEGAS, ids=repr)
def test_initial_state_refuses_an_omega_that_is_not_three_numbers(omega) -> None:
    _refused(lambda: cs.InitialState(omega=omega), "omega")


@pytest.mark.parametrize(
    "angles", [True, None, "12", (0.5,), (0.5, 0.5, 0.5), (0.5, False), ("1", 0.5)], ids=repr
)
def test_initial_state_refuses_euler_angles_that_are_not_two_numbers(angles) -> None:
    _refused(lambda: cs.InitialState(euler_angles=angles), "euler_angles")


@pytest.mark.parametrize(
    "omega",
    [[0, 0, -5], np.array([0.0, 0.0, -5.0]), (np.float32(0.0), np.int64(0), -5.0), (0, -0.0, -5)],
    ids=repr,
)
def test_initial_state_takes_sequences_and_arrays_of_numbers(omega) -> None:
    state = cs.InitialState(omega=omega)
    assert state.omega == (0.0, 0.0, -5.0)
    assert all(type(w) is float for w in state.omega)


# ---------------------------------------------------------------------------------------
# The command line reads text strictly, then takes the same path
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (["--samples", "2.5"], "n_samples"),
        (["--samples", "1_0"], "n_samples"),
        (["--samples", "0x10"], "n_samples"),
        (["--samples", "1e400"], "n_samples"),
        (["--samples", "9" * 5000], "n_samples"),
        (["--t-end", "1_0"], "t_end"),
        (["--t-end", "\u0663"], "t_end"),  # ARABIC-INDIC DIGIT THREE: float() reads it
        (["--t-end", "5s"], "t_end"),
        (["--rtol", "1e-1_0"], "rtol"),
        (["--omega", "0,0,-5_0"], "omega"),
        (["--euler-angles", "0.5,0_5"], "euler_angles"),
        (["--model", "sliding", "--friction-coefficient", "0_3"], "friction_coefficient"),
        (["--model", "sliding", "--contact-radius", "1e-3_0"], "contact_radius"),
    ],
    ids=lambda v: " ".join(v) if isinstance(v, list) else v,
)
def test_cli_run_refuses_numbers_python_would_read(
    capsys: pytest.CaptureFixture[str], argv: list[str], name: str
) -> None:
    line = _cli_line(capsys, ["run", *argv])
    assert f"{name} = " in line
    assert schema.PARAMETERS[name].allowed in line or "comma-separated" in line


@pytest.mark.parametrize(
    ("text", "count"), [("200", 200), ("1e3", 1000), ("+3", 3), (" 7 ", 7), ("2e0", 2)]
)
def test_a_count_on_the_command_line_is_any_whole_decimal(text: str, count: int) -> None:
    assert schema.parse_count("n_samples", text) == count


@pytest.mark.parametrize(
    ("text", "number"), [("5", 5.0), ("-0.5", -0.5), ("1e-3", 1e-3), (".5", 0.5), ("5.", 5.0)]
)
def test_a_number_on_the_command_line_is_a_plain_decimal(text: str, number: float) -> None:
    assert schema.parse_number("t_end", text) == number


@pytest.mark.parametrize(
    "argv",
    [
        ["--vary", "friction_coefficient=0_1,0.2"],
        ["--vary", "friction_coefficient=0.1:0.2:2.5"],
        ["--vary", "friction_coefficient=0.1:0.2:1_0"],
        ["--vary", "friction_coefficient=0.1,0.2", "--t-end", "1_0"],
        ["--vary", "friction_coefficient=0.1,0.2", "--set", "damping=1e-4_0"],
    ],
    ids=" ".join,
)
def test_cli_sweep_refuses_numbers_python_would_read(
    capsys: pytest.CaptureFixture[str], tmp_path, argv: list[str]
) -> None:
    _cli_line(capsys, ["sweep", *argv, "--out", str(tmp_path / "s.zarr"), "--no-progress"])
    assert not (tmp_path / "s.zarr").exists()


@pytest.mark.parametrize(
    ("keywords", "name"),
    [
        ({"vary": {"friction_coefficient": "0.1,0.2"}}, "friction_coefficient"),
        ({"vary": {"friction_coefficient": [0.1, True]}}, "friction_coefficient"),
        ({"vary": {"friction_coefficient": ["0.1", "0.2"]}}, "friction_coefficient"),
        ({"points": {"friction_coefficient": ["0.1", "0.2"]}}, "friction_coefficient"),
        ({"fixed": {"friction_coefficient": "0.3"}}, "friction_coefficient"),
        ({"fixed": {"damping": True}}, "damping"),
        ({"t_end": "5"}, "t_end"),
        ({"max_steps": 2.5}, "max_steps"),
    ],
    ids=repr,
)
def test_python_sweep_refuses_text_and_booleans(keywords: dict, name: str) -> None:
    arguments = {"vary": {"friction_coefficient": [0.1, 0.2]}, **keywords}
    if "points" in arguments:
        arguments.pop("vary")
    _refused(lambda: Sweep(**arguments), name)


# ---------------------------------------------------------------------------------------
# Silent answers: a contact radius the Hertz contact overrides
# ---------------------------------------------------------------------------------------

ELASTIC = {"elastic_modulus": 2e9, "poisson_ratio": 0.35}


@pytest.mark.parametrize("cls", [cs.SlidingModel, cs.HybridModel])
def test_a_fixed_contact_radius_with_hertz_is_refused_from_python(cls) -> None:
    error = _refused(lambda: cls(contact_radius=2e-3, **ELASTIC), "contact_radius")
    assert "elastic_modulus" in error.allowed and "no effect" in error.hint
    # the Hertz contact alone, and the fixed radius alone, are taken
    assert cls(**ELASTIC).is_hertz_radius
    assert cls(contact_radius=2e-3).contact_radius == 2e-3


def test_a_contact_radius_given_at_its_default_with_hertz_is_refused_by_name() -> None:
    default = cs.SlidingModel().contact_radius
    _refused(
        lambda: cs.model_from_name("sliding", contact_radius=default, **ELASTIC),
        "contact_radius",
    )
    hybrid = cs.model_from_name("sliding", contact="hybrid", **ELASTIC)
    assert hybrid.is_hertz_radius


@pytest.mark.parametrize("radius", ["0.005", "0.001"])
def test_cli_run_refuses_contact_radius_with_hertz(
    capsys: pytest.CaptureFixture[str], radius: str
) -> None:
    argv = ["run", "--model", "sliding", "--contact-radius", radius,
            "--elastic-modulus", "2e9", "--poisson-ratio", "0.35", "--json"]  # fmt: skip
    line = _cli_line(capsys, argv)
    assert "contact_radius" in line and "elastic_modulus" in line and "no effect" in line


CONTACT_RADIUS_SWEEPS = [
    "--vary contact_radius=0.001:0.003:3 --set contact_shape=ellipse "
    "--set elastic_modulus=2e9 --set poisson_ratio=0.35",
    "--vary contact_radius=0.001:0.003:3 --set contact_shape=ellipse",
    "--vary contact_radius=0.001,0.002 --set elastic_modulus=2e9 --set poisson_ratio=0.35",
    "--vary elastic_modulus=1e9,2e9 --set contact_radius=0.002 --set poisson_ratio=0.35",
]


@pytest.mark.parametrize("arguments", CONTACT_RADIUS_SWEEPS)
def test_cli_sweep_refuses_a_contact_radius_without_effect(
    capsys: pytest.CaptureFixture[str], tmp_path, arguments: str
) -> None:
    out = tmp_path / "s.zarr"
    argv = ["sweep", *arguments.split(), "--out", str(out), "--no-progress"]
    line = _cli_line(capsys, argv)
    assert "contact_radius" in line and "no effect" in line
    assert not out.exists()


def test_a_contact_radius_varied_without_hertz_is_swept() -> None:
    """With the fixed-radius contact a varied contact_radius takes effect: no refusal."""
    sweep = Sweep({"contact_radius": [1e-3, 2e-3]}, t_end=1.0)
    assert sweep.size == 2


# ---------------------------------------------------------------------------------------
# Silent answers: the friction law at huge slip ratios
# ---------------------------------------------------------------------------------------

# u = |V1| / (ε |Ω_n|): 1e155 is where |V1|² overflowed to a zero force
HUGE_U = [1e3, 1e100, 1e154, 1e155, 1e200, 1e300, 1.7976931348623157e308]
# u M/(f N ε) at large u: ∫σ r² dS / (2 N ε²), 1/5 for the Hertz pressure (references.md,
# M ≈ f N ε/(5u)) and 1/4 for the uniform one (∫σ r² dS = N ε²/2)
MOMENT_LIMIT = {"hertz": 0.2, "uniform": 0.25}


@pytest.mark.parametrize("pressure", ["hertz", "uniform"])
@pytest.mark.parametrize("law", ["pade", "exact"])
def test_friction_tends_to_pure_sliding_as_u_grows(law: str, pressure: str) -> None:
    """F -> f N as u -> ∞ (references.md), with 1 - F = O(1/u) for the Padé law (b/u)
    and O(1/u²) for the exact law; u M -> the pressure's ∫σ r² dS / (2 N ε²)."""
    u = np.array(HUGE_U)
    force, moment = friction_functions(u, law, pressure)
    assert np.all(np.abs(1.0 - force) <= 1.0 / u + 1e-15)
    np.testing.assert_allclose(u * moment, MOMENT_LIMIT[pressure], rtol=1.5 / u[0] + 1e-12)


@settings(deadline=None)  # tests bound work, not wall time
@given(st.floats(min_value=0.0, max_value=1.7976931348623157e308, allow_subnormal=True))
def test_friction_is_bounded_and_monotone_in_u_for_every_finite_u(u: float) -> None:
    """0 <= F <= f N for every finite u (Coulomb's bound), and F grows with u: no u
    loses the force to an overflow."""
    for law in ("pade", "exact"):
        force, moment = friction_functions([u, 2.0 * u if u < 8e307 else u, 1.0], law)
        assert 0.0 <= force[0] <= force[1] <= 1.0 + 1e-15
        if u >= 1.0:
            assert force[0] >= force[2]
        assert math.isfinite(moment[0]) and moment[0] >= 0.0


@pytest.mark.parametrize("direction", [0.0, 0.7, math.pi / 2])
@pytest.mark.parametrize("u", [1e155, 1e300])
def test_elliptic_friction_tends_to_pure_sliding_as_u_grows(direction: float, u: float) -> None:
    """|F| -> f N antiparallel to the slip, for the exact elliptic law and the fast form
    a run uses (``ellipse_table`` notes: d_par = r_perp = 0 at u = ∞)."""
    aspect = 0.5
    slip = np.array([math.cos(direction), math.sin(direction)])
    for law in ("pade", "exact"):
        force, _ = fast_friction_functions(u, direction, aspect, law)
        np.testing.assert_allclose(force, -slip, atol=1e-12)
    force, moment = elliptic_friction_functions(u, direction, aspect)
    np.testing.assert_allclose(force, -slip, atol=1e-12)
    # M/(f N A) ≈ (cos²α + k² sin²α) / (5u), ∫ p x² dA = N A²/5 (ellipse_table notes)
    expected = (math.cos(direction) ** 2 + aspect**2 * math.sin(direction) ** 2) / 5.0
    assert -moment * u == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize(
    "extra",
    [
        ["--law", "pade"],
        ["--law", "exact"],
        ["--law", "pade", "--pressure", "uniform"],
        ["--law", "exact", "--pressure", "uniform"],
        ["--law", "pade", "--ellipse", "0.002,0.001"],
        ["--law", "exact", "--ellipse", "0.002,0.001"],
        ["--law", "exact", "--ellipse", "0.002,0.0001", "--direction", "40"],
        ["--law", "pade", "--ellipse", "0.002,0.001", "--direction", "40"],
    ],
    ids=" ".join,
)
def test_cli_friction_prints_pure_sliding_at_huge_u(
    capsys: pytest.CaptureFixture[str], extra: list[str]
) -> None:
    status = main(["friction", "--u", "1e155,1e300,1.7e308", "--json", *extra])
    out, err = capsys.readouterr()
    assert status == 0, err
    force = json.loads(out)["force"]
    assert force == pytest.approx([1.0, 1.0, 1.0], abs=1e-12)


@pytest.mark.parametrize("u", [True, "0.5", None, NAN, -1.0, ["1"]], ids=repr)
def test_friction_functions_refuse_ratios_that_are_not_numbers(u) -> None:
    _refused(lambda: friction_functions(u), "slip_ratio")


@pytest.mark.parametrize("u", [True, "0.5", None, NAN, -1.0, 1e5, 1e155], ids=repr)
def test_the_reference_quadrature_refuses_what_it_cannot_answer(u) -> None:
    """Beyond u = 1e4 the quadrature loses accuracy (a zero force at 1e155): refused,
    not answered wrongly."""
    _refused(lambda: friction_integrals(u), "slip_ratio")


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (["--u", "1_0"], "u"),
        (["--u", "0.5,\u0663"], "u"),
        (["--u", "1e400"], "u"),
        (["--u", "0.5", "--ellipse", "0.002,0.001", "--direction", "4_0"], "direction"),
        (["--u", "0.5", "--ellipse", "0.002,0.00_1"], "ellipse"),
    ],
    ids=lambda v: " ".join(v) if isinstance(v, list) else v,
)
def test_cli_friction_refuses_numbers_python_would_read(
    capsys: pytest.CaptureFixture[str], argv: list[str], name: str
) -> None:
    line = _cli_line(capsys, ["friction", *argv])
    assert f"{name} = " in line


@pytest.mark.parametrize("value", [None, 1, True, ["pade"], np.array([1.0, 2.0]), "Pade"], ids=repr)
@pytest.mark.parametrize("name", ["friction_law", "friction_load", "contact_shape"])
def test_models_refuse_choices_that_are_not_a_choice(name: str, value) -> None:
    _refused(lambda: cs.SlidingModel(**{name: value}), name)
