"""The elliptic contact's table read at an address (``friction_ellipse``, the records'
``ellipse_table``).

The oracle of the interpolation is the tensor-product cubic B-spline of the table's
coefficients evaluated in NumPy by SciPy's ``BSpline.design_matrix`` at the coordinates
of the module docstring, written out here; the oracle of the batch's rebinding is the
same batch run with records made in this process.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import BSpline

import celtstone as cs
from celtstone.kernels import dynamics
from celtstone.kernels.friction_ellipse import (
    ASPECT_MIN,
    COEFFICIENTS,
    TABLE_ADDRESS,
    elliptic_contact_friction,
    elliptic_ratios,
)
from celtstone.kernels.layout import FrictionLaw, ModelCode, ellipse_table_address
from celtstone.kernels.stick_ellipse import elliptic_stick_margin
from celtstone.simulation.models import initial_vector, kernel_parameters
from celtstone.solvers.batch import FIELDS, run_batch
from celtstone.solvers.codes import STATUS_SUCCESS

NORMAL = (0.0, 0.0, 1.0)
MAJOR = (1.0, 0.0, 0.0)
# the Hertz ellipse of the Kane & Levinson stone on a plane of its own material
ELLIPSE = {"contact_shape": "ellipse", "elastic_modulus": 3e9, "poisson_ratio": 0.35}


def _basis(positions: np.ndarray, coefficients: int) -> np.ndarray:
    """Uniform cubic B-splines of unit knot spacing at ``positions`` in node units, one
    column per coefficient: the first centred at node −1, the last at node
    ``coefficients`` − 2 (the end rows outside the grid)."""
    knots = np.arange(-3.0, coefficients + 1.0)
    return BSpline.design_matrix(positions, knots, 3).toarray()


def _ratios_in_numpy(slip_major: float, slip_minor: float, pivot: float, aspect: float):
    """(d_par, r_perp, d_M) of the table at a slip state, in NumPy."""
    slips, directions, aspects, _ = COEFFICIENTS.shape
    speed = math.hypot(slip_major, slip_minor)
    s = (math.atan2(speed, aspect * pivot) + math.atan2(speed, pivot)) / math.pi
    along, across = abs(slip_major), abs(slip_minor)
    beta = 0.5 * (math.atan2(across, along) + math.atan2(aspect * across, along))
    q = math.log(aspect) / math.log(ASPECT_MIN)  # 1 at ASPECT_MIN, 0 at k = 1
    weights = (
        _basis(np.array([s * (slips - 3)]), slips)[0],
        _basis(np.array([beta / (0.5 * math.pi) * (directions - 3)]), directions)[0],
        _basis(np.array([(1.0 - q) * (aspects - 3)]), aspects)[0],
    )
    parallel, perpendicular, moment = np.einsum("i,j,k,ijkc->c", *weights, COEFFICIENTS)
    if slip_major * slip_minor < 0.0:  # r_perp is odd in the direction about both axes
        perpendicular = -perpendicular
    return parallel, perpendicular, moment


def _slip_states(count: int) -> list[tuple[float, float, float, float]]:
    """(V·a, V·(n × a), A|Ω_n|, k) off the grid's ends: u log-uniform in [1e-3, 1e3], the
    direction uniform, k log-uniform in [ASPECT_MIN, 1]."""
    rng = np.random.default_rng(43)
    states = []
    for _ in range(count):
        u = 10.0 ** rng.uniform(-3.0, 3.0)
        direction = rng.uniform(0.0, 2.0 * math.pi)
        aspect = math.exp(rng.uniform(math.log(ASPECT_MIN), 0.0))
        states.append((u * math.cos(direction), u * math.sin(direction), 1.0, aspect))
    return states


def test_the_ratios_read_at_the_address_are_the_tables_spline() -> None:
    """The kernel's B-spline through the address is SciPy's of the same coefficients, to
    the round-off of 64 terms of order one."""
    for state in _slip_states(200):
        kernel = elliptic_ratios(*state, TABLE_ADDRESS)
        expected = _ratios_in_numpy(*state)
        assert kernel == pytest.approx(expected, rel=1e-12, abs=1e-13)


def test_the_address_0_gives_nan_never_a_crash() -> None:
    """A record whose table was never set: the elliptic law has no value (the run then
    stops with ``RHS_CONTACT_RANGE``), the stick limit says no stick (−1)."""
    slip_major, slip_minor, pivot, aspect = _slip_states(1)[0]
    assert all(math.isnan(r) for r in elliptic_ratios(slip_major, slip_minor, pivot, aspect, 0))
    slip = (slip_major, slip_minor, 0.0)
    for semi_minor in (aspect, 1.0):  # B = A reads no table, and still refuses
        force, moment = elliptic_contact_friction(
            slip, 1.0, NORMAL, MAJOR, 1.0, semi_minor, 0.0, FrictionLaw.PADE.value, 0
        )
        assert all(math.isnan(value) for value in (*force, moment))
    margin = elliptic_stick_margin(
        (0.1, 0.0, 0.0), 1e-4, NORMAL, MAJOR, 1.0, aspect, 1.0, FrictionLaw.PADE.value, 0
    )
    assert margin == -1.0


def _ellipse_points() -> tuple[np.ndarray, np.ndarray]:
    """Two sliding points on the Hertz ellipse, made in this process."""
    body = cs.load_body("kane_levinson_1982")
    model = cs.SlidingModel(0.3, friction_load="dynamic", **ELLIPSE)
    params = np.array([kernel_parameters(model, body)] * 2)
    starts = [((0.0, 0.0, -5.0), (0.5, 0.5)), ((0.0, 0.0, 3.0), (0.3, -0.4))]
    y0 = np.array([initial_vector(cs.InitialState(*start)) for start in starts])
    return params, y0


def _batch(params: np.ndarray, y0: np.ndarray) -> np.ndarray:
    return run_batch(
        int(ModelCode.SLIDING),
        "dop853",
        params,
        y0,
        0.2,
        rtol=1e-8,
        atol=1e-10,
        sample_times=np.linspace(0.0, 0.2, 5),
        reversal_bands=np.full(len(params), 0.1),
    )


def test_a_batch_sets_the_records_table_to_its_own_process() -> None:
    """Records from another process (a Dask worker's pickle) hold an address of that
    process: the batch reads this process's table whatever the field holds, and leaves
    the caller's records as they were. Here the field holds 0 and the address of another
    array of the table's shape, which would give NaN and the disk law (all ratios 0)."""
    params, y0 = _ellipse_points()
    assert params["ellipse_table"].tolist() == [ellipse_table_address()] * 2
    expected = _batch(params, y0)
    assert np.all(expected[:, FIELDS.index("status")] == STATUS_SUCCESS)
    assert np.all(np.isfinite(expected[:, FIELDS.index("spin_final")]))
    other = np.zeros_like(COEFFICIENTS)
    n = tuple(float(component) for component in y0[0, :3])
    for stale in (0, other.ctypes.data):
        record = params[0].copy()
        record["ellipse_table"] = stale
        fresh = params[0]
        # what a kernel given the stale record computes: another law, or none
        stale_law = dynamics.friction_per_unit_load(n, (1e-3, 2e-3, 0.0), 4.0, 1.0, record)
        fresh_law = dynamics.friction_per_unit_load(n, (1e-3, 2e-3, 0.0), 4.0, 1.0, fresh)
        assert stale_law[1] != fresh_law[1]
        sent = params.copy()
        sent["ellipse_table"] = stale
        np.testing.assert_array_equal(_batch(sent, y0), expected)
        assert sent["ellipse_table"].tolist() == [stale] * 2
