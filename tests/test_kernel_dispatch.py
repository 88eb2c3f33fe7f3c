"""The kernel parameter record and every compiled dispatch on a code.

The record is declared once (``kernels.layout.PARAMETER_FIELDS``); its units must be
those of the ``schema`` entries it carries. Every code is an IntEnum numbered from 0;
each dispatch has a branch per member and none by default: a known code gives finite
physics, an unknown one NaN there and the status ``RHS_UNKNOWN_CODE`` from the
right-hand side, so a run stops instead of computing another case's physics.
"""

from __future__ import annotations

import enum
import math
from dataclasses import replace

import numpy as np
import pytest

import celtstone as cs
from celtstone import solvers
from celtstone.kernels import (
    dynamics,
    friction,
    friction_ellipse,
    friction_exact,
    geometry,
    hertz,
    layout,
    stick,
    stick_ellipse,
    system,
)
from celtstone.kernels.layout import (
    ContactPressure,
    FrictionLaw,
    FrictionLoad,
    ModelCode,
    ShapeCode,
)
from celtstone.simulation import schema
from celtstone.simulation.models import initial_vector, kernel_parameters
from celtstone.solvers.derived import derived_series

CODES: list[type[enum.IntEnum]] = [ModelCode, ShapeCode, FrictionLoad, FrictionLaw, ContactPressure]
UNKNOWN = [-1, 99]  # codes no enum has
STATE = cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5))
N = (0.1, -0.2, 0.97)  # a tilted upward vertical [1]
N_RATE = (0.3, 0.1, 0.05)  # [1/s]
SLIP = (1e-3, -2e-3, 0.0)  # [m/s]
TABLE = friction_ellipse.TABLE_ADDRESS  # the elliptic law's table in this process


def _bodies() -> dict[ShapeCode, cs.Body]:
    """One runnable body per shape code (the Kane & Levinson ellipsoid in each form)."""
    kane_levinson = cs.load_body("kane_levinson_1982")
    a, b, c = kane_levinson.shape.semi_axes
    h = kane_levinson.shape.com_offset
    terms = [(1 / a**2, 2, 0, 0), (1 / b**2, 0, 2, 0), (1 / c**2, 0, 0, 2)]
    shapes = [
        kane_levinson.shape,
        cs.load_body("kane_levinson_1982_paraboloid").shape,
        cs.Superellipsoid((a, b, c), h, 2.0),
        cs.ImplicitPolynomial(terms=terms, com_offset=h),
    ]
    return {shape.code: replace(kane_levinson, shape=shape) for shape in shapes}


BODIES = _bodies()


ELLIPTIC_CONTACT = cs.SlidingModel(contact_shape="ellipse", elastic_modulus=3e9, poisson_ratio=0.35)
ELLIPSE = ((0.0, 0.0, 1.0), (1.0, 0.0, 0.0), 3e-3, 1e-3)  # n, the major axis a ⊥ n, A, B [m]


def _record(
    body_shape: ShapeCode = ShapeCode.ELLIPSOID, model: cs.SlidingModel | None = None, **codes: int
) -> np.record:
    """The record of ``model`` (default the sliding model) for the body of ``body_shape``,
    ``codes`` overwritten."""
    model = cs.SlidingModel() if model is None else model
    params = kernel_parameters(model, BODIES[body_shape]).copy()
    for name, value in codes.items():
        params[name] = value
    return params


def _numbers(values: object) -> list[float]:
    """Every number in nested tuples and arrays."""
    if isinstance(values, tuple | list):
        return [x for value in values for x in _numbers(value)]
    return [float(x) for x in np.ravel(values)]


def _finite(*values: object) -> bool:
    return all(math.isfinite(x) for x in _numbers(values))


def _all_nan(*values: object) -> bool:
    return all(math.isnan(x) for x in _numbers(values))


# --- the declaration ------------------------------------------------------------------


@pytest.mark.parametrize("codes", CODES, ids=lambda codes: codes.__name__)
def test_codes_are_numbered_from_zero(codes: type[enum.IntEnum]) -> None:
    """``system.code_status`` accepts 0 .. len - 1: the members must be exactly those."""
    assert sorted(member.value for member in codes) == list(range(len(codes)))


def test_record_fields_are_the_table() -> None:
    """One field per table row, in order, of the row's type and shape; the integer
    fields are the codes (with their enum) and the counts, exponents and address."""
    fields = layout.PARAMETER_FIELDS
    names = [f.name for f in fields]
    assert list(layout.PARAMETERS.names) == names and len(set(names)) == len(names)
    integer_data = {"term_count", "term_exponents", "level_function", "ellipse_table"}
    for f in fields:
        dtype = layout.PARAMETERS.fields[f.name][0]
        assert (dtype.base, dtype.shape) == (np.dtype(f.kind), f.shape)
        assert (f.kind == "i8") == (f.codes is not None or f.name in integer_data)


def test_field_names_are_not_numpy_attributes() -> None:
    """``params.<name>`` must reach the field in Python too (kernels under
    NUMBA_DISABLE_JIT, tests): a name such as ``shape`` would read the scalar's own."""
    assert not set(layout.PARAMETERS.names) & set(dir(np.record))


@pytest.mark.parametrize(
    "field",
    [f for f in layout.PARAMETER_FIELDS if f.quantity is not None],
    ids=lambda f: f.name,
)
def test_record_units_are_the_schemas(field: layout.ParameterField) -> None:
    """A field that carries a validated input has that input's unit (schema.py)."""
    assert field.quantity is not None
    assert field.unit == schema.PARAMETERS[field.quantity].unit


def test_every_shape_code_has_a_test_body() -> None:
    assert set(BODIES) == set(ShapeCode)


@pytest.mark.parametrize("shape", list(ShapeCode), ids=lambda code: code.name.lower())
def test_kernel_parameters_carry_the_inputs(shape: ShapeCode) -> None:
    body = BODIES[shape]
    model = cs.SlidingModel(0.2, 2e-3, "dynamic", 1e-4, 1e-7, "exact", "uniform")
    params = kernel_parameters(model, body)
    assert params.dtype == layout.PARAMETERS
    assert (params.mass, params.gravity) == (body.mass, body.gravity)
    assert np.array_equal(params.inertia, body.inertia)
    assert (params.shape_code, params.damping) == (shape, 1e-4)
    assert (params.friction_coefficient, params.contact_radius) == (0.2, 2e-3)
    assert (params.friction_load, params.regularisation_speed) == (FrictionLoad.DYNAMIC, 1e-7)
    assert (params.friction_law, params.contact_pressure) == (
        FrictionLaw.EXACT,
        ContactPressure.UNIFORM,
    )
    assert params.effective_modulus == 0.0
    for name, value in body.shape.kernel_fields().items():
        assert np.array_equal(params[name], value)


def test_records_stack_into_an_array_of_points() -> None:
    """``np.array`` of records is what the batch driver indexes, one point per row."""
    body = BODIES[ShapeCode.ELLIPSOID]
    points = [kernel_parameters(cs.SlidingModel(f), body) for f in (0.1, 0.2, 0.3)]
    stacked = np.array(points)
    assert stacked.shape == (3,) and stacked.dtype == layout.PARAMETERS
    assert [stacked[i].friction_coefficient for i in range(3)] == [0.1, 0.2, 0.3]


def test_polynomial_terms_fill_the_fixed_capacity() -> None:
    shape = BODIES[ShapeCode.IMPLICIT].shape
    assert isinstance(shape, cs.ImplicitPolynomial)
    params = shape.kernel_record()
    count = len(shape.terms)
    assert params.term_count == count and params.level_function == 0
    assert np.array_equal(params.term_coefficients[:count], [t[0] for t in shape.terms])
    assert np.array_equal(params.term_exponents[:count], [t[1:] for t in shape.terms])
    assert not params.term_coefficients[count:].any() and not params.term_exponents[count:].any()


# --- every known code gives finite physics --------------------------------------------


@pytest.mark.parametrize("shape", list(ShapeCode), ids=lambda code: code.name.lower())
def test_every_shape_has_geometry(shape: ShapeCode) -> None:
    params = _record(shape)
    r, r_rate = geometry.contact(N, N_RATE, params)
    assert _finite(r, r_rate, hertz.equivalent_radius(N, params))
    assert geometry.contact_status(N, r, params) == layout.RHS_OK


@pytest.mark.parametrize("pressure", list(ContactPressure), ids=lambda code: code.name.lower())
@pytest.mark.parametrize("law", list(FrictionLaw), ids=lambda code: code.name.lower())
def test_every_law_and_pressure_has_friction(law: FrictionLaw, pressure: ContactPressure) -> None:
    force, moment = friction.contact_friction(SLIP, 2.0, 1e-3, 1e-6, law.value, pressure.value)
    assert _finite(force, moment) and moment < 0.0
    assert _finite(stick.limit_moment(0.5, law.value, pressure.value))


@pytest.mark.parametrize("law", list(FrictionLaw), ids=lambda code: code.name.lower())
def test_every_law_has_an_elliptic_contact_and_its_stick_limit(law: FrictionLaw) -> None:
    """The elliptic contact reads the law through the disk's dispatch: every law has it."""
    assert friction.has_friction_law(law.value)
    n, axis, semi_major, semi_minor = ELLIPSE
    force, moment = friction_ellipse.elliptic_contact_friction(
        SLIP, 2.0, n, axis, semi_major, semi_minor, 1e-6, law.value, TABLE
    )
    assert _finite(force, moment) and moment < 0.0
    margin = stick_ellipse.elliptic_stick_margin(
        (0.1, 0.0, 0.0), 1e-4, n, axis, semi_major, semi_minor, 1.0, law.value, TABLE
    )
    assert _finite(margin)


@pytest.mark.parametrize("option", list(FrictionLoad), ids=lambda code: code.name.lower())
def test_every_friction_load_has_dynamics(option: FrictionLoad) -> None:
    params = _record(friction_load=option.value)
    omega = (0.1, 0.2, -5.0)
    r, r_rate = geometry.contact(N, N_RATE, params)
    assert _finite(dynamics.sliding_acceleration(N, omega, SLIP, r, r_rate, params))
    assert _finite(stick.stick_margin(N, omega, r, r_rate, params))


@pytest.mark.parametrize("shape", list(ShapeCode), ids=lambda code: code.name.lower())
@pytest.mark.parametrize("model", list(ModelCode), ids=lambda code: code.name.lower())
def test_every_model_and_shape_has_a_right_hand_side(model: ModelCode, shape: ShapeCode) -> None:
    params = _record(shape)
    y, dy = initial_vector(STATE), np.empty(layout.N_STATE)
    status, normal_force = system.rhs(model.value, 0.0, y, params, dy)
    assert status == layout.RHS_OK
    assert _finite(dy, normal_force, system.energy(model.value, y, params))
    assert _finite(system.phase_value(model.value, y, params, 1e-6))


# --- an unknown code is refused, never computed as another -----------------------------


@pytest.mark.parametrize("code", UNKNOWN)
def test_unknown_shape_is_nan_in_geometry(code: int) -> None:
    params = _record(shape_code=code)
    r, r_rate = geometry.contact(N, N_RATE, params)
    assert _all_nan(r, r_rate, hertz.equivalent_radius(N, params))


@pytest.mark.parametrize("code", UNKNOWN)
def test_unknown_law_or_pressure_is_nan_in_friction(code: int) -> None:
    pade, exact = FrictionLaw.PADE.value, FrictionLaw.EXACT.value
    hertz_pressure = ContactPressure.HERTZ.value
    for law, pressure in [(code, hertz_pressure), (pade, code), (exact, code)]:
        assert _all_nan(*friction.contact_friction(SLIP, 2.0, 1e-3, 1e-6, law, pressure))
        assert _all_nan(stick.limit_moment(0.5, law, pressure))
        assert _all_nan(stick.stick_margin_of(1.0, 1e-3, 9.81, 0.3, 1e-3, law, pressure))
    for speeds in [(1.0, 2.0), (2.0, 1.0)]:
        assert _all_nan(friction_exact.exact_friction_functions(*speeds, code))
    assert not friction.has_friction_law(code)
    assert _all_nan(friction.law_functions(code, 1.0, 2.0, hertz_pressure))


@pytest.mark.parametrize("code", UNKNOWN)
def test_unknown_law_is_nan_in_the_elliptic_contact(code: int) -> None:
    """The elliptic contact has no branch of its own: an unknown law is NaN there as on the
    disk, never another law corrected; its stick margin is -1, no stick (the slip's
    right-hand side then reports the code)."""
    n, axis, semi_major, semi_minor = ELLIPSE
    for semi_minor_axis in (semi_minor, semi_major):  # an ellipse, and the disk A = B
        assert _all_nan(
            *friction_ellipse.elliptic_contact_friction(
                SLIP, 2.0, n, axis, semi_major, semi_minor_axis, 1e-6, code, TABLE
            )
        )
    margin = stick_ellipse.elliptic_stick_margin(
        (0.1, 0.0, 0.0), 1e-4, n, axis, semi_major, semi_minor, 1.0, code, TABLE
    )
    assert margin == -1.0


@pytest.mark.parametrize("code", UNKNOWN)
def test_unknown_friction_load_is_nan_in_dynamics(code: int) -> None:
    params = _record(friction_load=code)
    omega = (0.1, 0.2, -5.0)
    r, r_rate = geometry.contact(N, N_RATE, params)
    assert _all_nan(dynamics.sliding_acceleration(N, omega, SLIP, r, r_rate, params))
    assert _all_nan(stick.stick_margin(N, omega, r, r_rate, params))


@pytest.mark.parametrize("code", UNKNOWN)
def test_unknown_model_is_nan_in_the_system(code: int) -> None:
    params = _record()
    y = initial_vector(STATE)
    assert _all_nan(system.energy(code, y, params), system.phase_value(code, y, params, 1e-6))


@pytest.mark.parametrize("code", UNKNOWN)
@pytest.mark.parametrize(
    "name", ["model", "shape_code", "friction_load", "friction_law", "contact_pressure"]
)
def test_unknown_code_is_the_right_hand_sides_status(name: str, code: int) -> None:
    model = code if name == "model" else ModelCode.SLIDING.value
    params = _record() if name == "model" else _record(**{name: code})
    y, dy = initial_vector(STATE), np.zeros(layout.N_STATE)
    assert system.rhs(model, 0.0, y, params, dy)[0] == layout.RHS_UNKNOWN_CODE
    derived = np.empty((1, system.N_DIAGNOSTICS))
    derived_series(model, y[None, :], params, derived)
    assert derived[0, system.D_STATUS] == layout.RHS_UNKNOWN_CODE
    (message,) = layout.unknown_codes(model, params)
    assert message.startswith(f"{name} code {code} (known: ") and "\n" not in message


@pytest.mark.parametrize("code", UNKNOWN)
@pytest.mark.parametrize("model", [ModelCode.SLIDING, ModelCode.STICK], ids=["sliding", "stick"])
def test_unknown_law_is_the_elliptic_contacts_status(model: ModelCode, code: int) -> None:
    """With the elliptic contact too an unknown law is ``RHS_UNKNOWN_CODE``, not the
    ``RHS_CONTACT_RANGE`` of an ellipse outside its table."""
    params = _record(model=ELLIPTIC_CONTACT, friction_law=code)
    y, dy = initial_vector(STATE), np.zeros(layout.N_STATE)
    assert system.rhs(model.value, 0.0, y, params, dy)[0] == layout.RHS_UNKNOWN_CODE
    known = _record(model=ELLIPTIC_CONTACT)
    assert system.rhs(model.value, 0.0, y, known, dy)[0] == layout.RHS_OK


def test_known_codes_have_no_message() -> None:
    assert layout.unknown_codes(ModelCode.STICK.value, _record(ShapeCode.IMPLICIT)) == []


@pytest.mark.parametrize("method", ["dop853", "radau5"])
@pytest.mark.parametrize("name", ["model", "shape_code", "friction_law"])
def test_a_run_with_an_unknown_code_stops_at_once(name: str, method: str) -> None:
    """The integrator reads the status of its first right-hand side and stops there."""
    model = 7 if name == "model" else ModelCode.SLIDING.value
    params = _record() if name == "model" else _record(**{name: 7})
    y0 = initial_vector(STATE)
    times = np.array([0.5, 1.0])
    raw = solvers.solve(model, method, params, y0, 1.0, rtol=1e-8, atol=1e-12, sample_times=times)
    assert raw.status == solvers.STATUS_UNKNOWN_CODE and raw.t_stop == 0.0
    assert raw.samples.shape[0] == 0 and raw.n_accepted == 0
