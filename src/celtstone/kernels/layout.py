"""What the kernels read: the typed parameter record, the codes, and the state array.

Parameters
----------
One NumPy structured dtype, :data:`PARAMETERS`, declared once from the table
:data:`PARAMETER_FIELDS` (name, type, shape, unit, the ``schema.PARAMETERS`` entry it
carries where one exists, and meaning). ``celtstone.simulation.models.kernel_parameters`` fills
one record per run from validated objects; numba compiles ``params.mass`` or
``params.inertia[i, j]`` to a load at a fixed offset and caches the kernels on the
dtype (docs/decisions.md, "Typed kernel parameters"). A sweep stacks the records of
its points into a 1-d array of this dtype, whose ``[i]`` is one point's record.

Codes
-----
Model, shape, friction load, friction law and contact pressure are
``enum.IntEnum``s, used by name in the kernels (numba folds a member to its integer)
and from Python. Each is numbered 0, 1, ...; every dispatch on one has a branch per
member and no default: an unknown code gives NaN there, and the right-hand side
reports ``RHS_UNKNOWN_CODE`` (``system.code_status``). A code passed from Python as
a kernel *argument* is a plain int (``.value``): numba would compile another
specialisation for an IntEnum argument.

State (all in body axes unless said otherwise)
----------------------------------------------
``y[0:3]``    n, upward vertical unit vector [1]
``y[3:6]``    omega, angular velocity [rad/s]
``y[6:9]``    V1, sliding velocity of the contact point [m/s] (zero in rolling)
``y[9:13]``   attitude quaternion (w, x, y, z), body -> space [1]
``y[13:15]``  horizontal position of the centre of mass in space axes [m]
``y[15]``     work dissipated by friction and damping since t = 0 [J]
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "MAX_TERMS",
    "PARAMETERS",
    "PARAMETER_FIELDS",
    "ContactPressure",
    "ContactShape",
    "FrictionLaw",
    "FrictionLoad",
    "ModelCode",
    "ParameterField",
    "ShapeCode",
    "ellipse_table_address",
    "parameter_record",
    "unknown_codes",
]


class ModelCode(enum.IntEnum):
    """Which equations ``system.rhs`` integrates."""

    ROLLING = 0  # rolling without sliding, paper eq. (3)-(5)
    SLIDING = 1  # rolling with sliding and pivoting friction, paper eq. (6)-(12)
    STICK = 2  # hybrid contact, stick phase: no slip, no pivoting (kernels/stick.py)


class ShapeCode(enum.IntEnum):
    """The body's surface; the shape fields it reads are listed in PARAMETER_FIELDS."""

    ELLIPSOID = 0  # semi_axes, com_offset
    PARABOLOID = 1  # radii_of_curvature, com_height
    SUPERELLIPSOID = 2  # |x/a|^p + |y/b|^p + |z/c|^p = 1: semi_axes, com_offset, exponent
    IMPLICIT = 3  # F(x) = 1: start_*, com_offset, the terms or level_function (§17, §18)


class FrictionLoad(enum.IntEnum):
    """The normal force that loads the friction law of the sliding model
    (``friction_load``, docs/decisions.md §5)."""

    STATIC = 0  # N = m g, the paper's first approximation
    DYNAMIC = 1  # the consistent normal force


class FrictionLaw(enum.IntEnum):
    """Coulomb–Contensou friction law of the sliding model."""

    PADE = 0  # Zhuravlev's Padé approximation, paper eq. (10)
    EXACT = 1  # the integrals of paper section 2, in closed form


class ContactPressure(enum.IntEnum):
    """Pressure distribution on the contact disk."""

    HERTZ = 0  # sigma ∝ sqrt(eps² − r²), paper eq. (2)
    UNIFORM = 1  # sigma = N / (pi eps²)


class ContactShape(enum.IntEnum):
    """Shape of the contact patch that the sliding model's friction acts over."""

    CIRCLE = 0  # a disk of radius epsilon (fixed, or Hertz's for R_eq), paper eq. (2)
    ELLIPSE = 1  # the Hertz ellipse of the two principal curvatures (docs/decisions.md §29)


# plain-int model codes for Python callers that pass one as a kernel argument
MODEL_ROLLING = ModelCode.ROLLING.value
MODEL_SLIDING = ModelCode.SLIDING.value
MODEL_STICK = ModelCode.STICK.value

MAX_TERMS = 64  # capacity of an implicit polynomial's terms (bodies.polynomial)


@dataclass(frozen=True)
class ParameterField:
    """One field of the kernel parameter record.

    Parameters
    ----------
    name : the field's name, read in the kernels as ``params.<name>``
    kind : NumPy scalar type code, "f8" (float64) or "i8" (int64)
    shape : () for a scalar, else the subarray's shape
    unit : SI unit ("" for a dimensionless number or a code)
    quantity : the ``schema.PARAMETERS`` entry validating the value, or None when
        the value is derived or a code (tests/test_kernel_dispatch.py checks the units)
    codes : the IntEnum of a code field, else None
    meaning : what it holds, with the paper's symbol
    """

    name: str
    kind: str
    shape: tuple[int, ...]
    unit: str
    quantity: str | None
    codes: type[enum.IntEnum] | None
    meaning: str


def _field(
    name: str,
    unit: str,
    meaning: str,
    *,
    shape: tuple[int, ...] = (),
    kind: str = "f8",
    quantity: str | None = None,
    codes: type[enum.IntEnum] | None = None,
) -> ParameterField:
    return ParameterField(name, kind, shape, unit, quantity, codes, meaning)


PARAMETER_FIELDS: tuple[ParameterField, ...] = (
    _field("mass", "kg", "m, mass of the body", quantity="mass"),
    _field("gravity", "m/s^2", "g, gravitational acceleration", quantity="gravity"),
    _field("inertia", "kg m^2", "A, central inertia tensor", shape=(3, 3), quantity="inertia"),
    _field("shape_code", "", "the body's surface", kind="i8", codes=ShapeCode),
    _field(
        "semi_axes",
        "m",
        "(a, b, c) along body axes 1, 2, 3: ellipsoid, superellipsoid",
        shape=(3,),
        quantity="semi_axes",
    ),
    _field(
        "com_offset",
        "m",
        "h, G below the centre O along axis 3: ellipsoid, superellipsoid, implicit",
        quantity="com_offset",
    ),
    _field(
        "radii_of_curvature",
        "m",
        "(rho1, rho2) at the rest contact: paraboloid",
        shape=(2,),
        quantity="radii_of_curvature",
    ),
    _field("com_height", "m", "l, G above the rest contact: paraboloid", quantity="com_height"),
    _field("exponent", "", "p >= 2: superellipsoid"),
    _field("start_centre", "m", "centre of the start ellipsoid about O: implicit", shape=(3,)),
    _field("start_semi_axes", "m", "semi-axes of the start ellipsoid: implicit", shape=(3,)),
    _field("term_count", "", "number of polynomial terms in use: implicit", kind="i8"),
    _field(
        "term_coefficients",
        "m^-(i+j+k)",
        "c of each term c x^i y^j z^k; rows past term_count are 0: implicit",
        shape=(MAX_TERMS,),
    ),
    _field(
        "term_exponents", "", "(i, j, k) of each term: implicit", shape=(MAX_TERMS, 3), kind="i8"
    ),
    _field(
        "level_function",
        "",
        "C address of a compiled F, ∇F, H callback (§18), 0 for a polynomial: implicit",
        kind="i8",
    ),
    _field("damping", "N m s", "sigma, viscous torque coefficient", quantity="damping"),
    _field("friction_coefficient", "", "f", quantity="friction_coefficient"),
    _field("contact_radius", "m", "epsilon, fixed contact radius", quantity="contact_radius"),
    _field("friction_load", "", "normal force in the friction law", kind="i8", codes=FrictionLoad),
    _field(
        "regularisation_speed",
        "m/s",
        "delta, |V1| -> sqrt(|V1|² + delta²)",
        quantity="regularisation_speed",
    ),
    _field("friction_law", "", "friction-law code", kind="i8", codes=FrictionLaw),
    _field("contact_pressure", "", "contact-pressure code", kind="i8", codes=ContactPressure),
    _field("contact_shape", "", "contact-patch shape code", kind="i8", codes=ContactShape),
    _field(
        "rolling_resistance",
        "m",
        "lambda, rolling-friction length: moment -lambda N omega_t / |omega_t|",
        quantity="rolling_resistance",
    ),
    _field(
        "rolling_resistance_rate",
        "rad/s",
        "omega_0, |omega_t| -> sqrt(|omega_t|² + omega_0²) in the rolling resistance",
        quantity="rolling_resistance_rate",
    ),
    _field(
        "effective_modulus",
        "Pa",
        "E* of the Hertz contact radius; 0: the fixed contact_radius",
    ),
    _field(
        "ellipse_table",
        "",
        "address of the elliptic contact's spline coefficients (friction_ellipse; a device "
        "copy on a GPU), valid in one process only (ellipse_table_address); 0: none",
        kind="i8",
    ),
)

# aligned struct (np.dtype((np.record, ...), align=True) would drop the flag, and numba
# would then treat every record as unaligned)
PARAMETERS = np.dtype(
    (np.record, np.dtype([(f.name, f.kind, f.shape) for f in PARAMETER_FIELDS], align=True))
)


def ellipse_table_address() -> int:
    """The address of the elliptic contact's table in this process
    (``friction_ellipse.TABLE_ADDRESS``), for the records' ``ellipse_table``.

    An address means nothing in another process: whatever runs records that it did not
    make in this process (a sweep's batch, from a Dask worker's pickle) sets the field
    again first."""
    from celtstone.kernels.friction_ellipse import TABLE_ADDRESS  # it imports this module

    return TABLE_ADDRESS


def parameter_record(**values: Any) -> np.record:
    """A parameter record with the given fields set, ``ellipse_table`` at this process's
    table (:func:`ellipse_table_address`) unless given, all others zero.

    Subarray fields take anything that broadcasts to their shape. The record is a
    view of a fresh one-element array, so it can be modified and passed to kernels.
    """
    records = np.zeros(1, dtype=PARAMETERS)
    records["ellipse_table"] = ellipse_table_address()
    for name, value in values.items():
        records[name][0] = value
    record: np.record = records[0]
    return record


def unknown_codes(model: int, params: np.record) -> list[str]:
    """Each code of a run that no kernel branch handles, in words (empty if none)."""
    coded: list[tuple[str, int, type[enum.IntEnum]]] = [("model", int(model), ModelCode)]
    coded += [(f.name, int(params[f.name]), f.codes) for f in PARAMETER_FIELDS if f.codes]
    return [
        f"{name} code {value} (known: "
        + ", ".join(f"{member.name.lower()} {member.value}" for member in codes)
        + ")"
        for name, value, codes in coded
        if value not in {member.value for member in codes}
    ]


# state indices
Y_N = 0
Y_OMEGA = 3
Y_SLIP = 6
Y_QUAT = 9
Y_POSITION = 13
Y_WORK = 15
N_STATE = 16
# The dynamics are the first N_DYNAMIC components (n, ω, V1): their rates never read the
# driven ones after them (attitude, position, work), and no rate reads the components from
# Y_POSITION on (position, work). The Radau Jacobian and its LU use this structure
# (``solvers._radau``); tests/test_kernel_structure.py checks it for every model.
N_DYNAMIC = Y_QUAT
N_READ = Y_POSITION

# status codes returned by the right-hand side
RHS_OK = 0
RHS_SINGULAR = 1  # the linear system for the angular acceleration is singular
RHS_OFF_SHAPE = 2  # the contact point left the shape's domain (paraboloid n3 <= 0)
RHS_NON_CONVEX = 3  # implicit shape: no contact point found, or the surface is not convex there
RHS_CONTACT_RANGE = 5  # the elliptic contact left its law's range (B/A < 0.02, flat or saddle)
RHS_UNKNOWN_CODE = 4  # a model, shape, friction-load, friction-law or pressure code no branch has
