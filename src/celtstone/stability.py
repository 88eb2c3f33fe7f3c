"""Linear stability of steady spin in the rolling model.

Steady spin about the vertical at the rest contact, n = e3 and ω = s e3 in body
axes, is a relative equilibrium of the rolling model (paper eq. 3–5) whenever the
rest contact lies below G on body axis 3 and I13 = I23 = 0. Linearised in the
tilt and rocking rates x = (n1, n2, ω1, ω2) it reads ẋ = J(s) x. The spin
perturbation δω3 and the normal perturbation δn3 decouple at first order: they add
two zero eigenvalues (the family of steady spins and |n| = 1), which are left out,
so each spin has the four eigenvalues of the pitch and roll dynamics.

J is the Jacobian of the compiled right-hand side itself (``kernels.system.rhs``),
taken by central differences with one Richardson extrapolation; at an equilibrium
the differences carry no cancellation, so the entries are accurate to a few
rounding errors. The test suite checks the eigenvalues against the exact
characteristic quartic of ``../shared/references.md``.

Mode names: *pitch* is rocking about body axis 2 (the long axis tips, n1 changes),
*roll* rocking about the long axis 1 (n2 changes). Each eigenvector is assigned by
its share |δn1|² / (|δn1|² + |δn2|²): the two eigenvalues with the larger share
are the pitch mode.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone.bodies import Body
from celtstone.errors import ParameterError
from celtstone.kernels import layout
from celtstone.kernels import system as kernel_system
from celtstone.simulation import schema
from celtstone.simulation.models import RollingModel, kernel_parameters

if TYPE_CHECKING:
    import xarray as xr


__all__ = [
    "MAX_SPIN_COUNT",
    "MODE_NAMES",
    "SpinStability",
    "linearised_matrix",
    "parse_spin_range",
    "spin_stability",
]

MODE_NAMES = ("pitch", "pitch", "roll", "roll")  # order of the four eigenvalues per spin
MAX_SPIN_COUNT = 100_000
PROGRESS_EVERY = 100  # spin rates between progress reports
# relative finite-difference step; the contact point r(n) of a body of aspect ratio
# c/a varies on the scale δn ~ c/a, so the extrapolated truncation error is
# ~ (STEP a/c)^4, far below rounding for any body short of 1e-3 aspect ratio
FINITE_DIFFERENCE_STEP = 1e-5
# a growth rate counts as zero if below this fraction of the largest |λ| at that spin
GROWTH_TOLERANCE = 1e-9

_UNITS = {"spin": "rad/s", "growth_rate": "1/s", "frequency": "rad/s"}


def _steady_state(spin_rate: float) -> np.ndarray:
    y = np.zeros(layout.N_STATE)
    y[layout.Y_N + 2] = 1.0
    y[layout.Y_OMEGA + 2] = spin_rate
    y[layout.Y_QUAT] = 1.0
    return y


def _check_body(body: Body) -> None:
    radii = getattr(body.shape, "radii_of_curvature", (0.0, 0.0))
    if not all(math.isfinite(radius) for radius in radii):
        raise ParameterError(
            "body",
            body.name,
            "a shape with finite radii of curvature at the rest contact",
            "a superellipsoid with exponent > 2 is flat there and has no linearisation",
        )
    inertia = body.inertia
    if inertia[0][2] != 0.0 or inertia[1][2] != 0.0:
        raise ParameterError(
            "body",
            body.name,
            "a body with I13 = I23 = 0",
            "otherwise steady spin about axis 3 is not a relative equilibrium",
        )


def _rates(
    params: np.record, base: np.ndarray, x: np.ndarray, work: np.ndarray, state: np.ndarray
) -> np.ndarray:
    """(ṅ1, ṅ2, ω̇1, ω̇2) at n = (x0, x1, √(1 − x0² − x1²)), ω = (x2, x3, s)."""
    state[:] = base
    state[layout.Y_N] = x[0]
    state[layout.Y_N + 1] = x[1]
    state[layout.Y_N + 2] = math.sqrt(1.0 - x[0] * x[0] - x[1] * x[1])
    state[layout.Y_OMEGA] = x[2]
    state[layout.Y_OMEGA + 1] = x[3]
    kernel_system.rhs(layout.ModelCode.ROLLING.value, 0.0, state, params, work)
    return np.array(
        [work[layout.Y_N], work[layout.Y_N + 1], work[layout.Y_OMEGA], work[layout.Y_OMEGA + 1]]
    )


def linearised_matrix(
    body: Body, spin_rate: float, model: RollingModel | None = None
) -> np.ndarray:
    """Jacobian J of (ṅ1, ṅ2, ω̇1, ω̇2) about steady spin, shape (4, 4) [1/s and 1/s²].

    Parameters
    ----------
    body : Body
        A body with I13 = I23 = 0 (rest contact below G on axis 3).
    spin_rate : float
        The rate s = ω · n of the steady spin [rad/s].
    model : RollingModel, optional
        The rolling model (its viscous damping σ enters J); default σ = 0.

    Returns
    -------
    numpy.ndarray
        J, shape (4, 4), rows and columns (n1, n2, ω1, ω2).

    Notes
    -----
    Columns by central differences of the rolling right-hand side (paper eq. 3–5)
    with steps h and h/2 combined as (4 D(h/2) − D(h))/3 (error O(h⁴)). The
    right-hand side is quadratic in ω, so the ω columns are exact; the n columns
    move n on the unit sphere.
    """
    model = _rolling(model)
    _check_body(body)
    spin_rate = _finite_spin(spin_rate)
    return _jacobian(kernel_parameters(model, body), spin_rate)


def _rolling(model: RollingModel | None) -> RollingModel:
    model = RollingModel() if model is None else model
    if not isinstance(model, RollingModel):
        raise ParameterError("model", getattr(model, "name", model), "the rolling model")
    return model


def _finite_spin(spin_rate: float) -> float:
    spin_rate = float(spin_rate)
    if not math.isfinite(spin_rate):
        raise ParameterError("spin", spin_rate, "a finite number in rad/s")
    return spin_rate


def _jacobian(params: np.record, spin_rate: float) -> np.ndarray:
    """J at ``spin_rate`` for the kernel parameters ``params`` (see
    :func:`linearised_matrix`, which checks what this takes as given)."""
    base = _steady_state(spin_rate)
    work = np.zeros(layout.N_STATE)
    state = np.zeros(layout.N_STATE)
    scales = (1.0, 1.0, max(1.0, abs(spin_rate)), max(1.0, abs(spin_rate)))
    jacobian = np.empty((4, 4))
    for column, scale in enumerate(scales):

        def difference(step: float, column: int = column) -> np.ndarray:
            x = np.zeros(4)
            x[column] = step
            forward = _rates(params, base, x, work, state)
            x[column] = -step
            backward = _rates(params, base, x, work, state)
            return (forward - backward) / (2.0 * step)

        step = FINITE_DIFFERENCE_STEP * scale
        jacobian[:, column] = (4.0 * difference(step / 2) - difference(step)) / 3.0
    return jacobian


def _ordered_eigenvalues(jacobian: np.ndarray) -> np.ndarray:
    """Eigenvalues ordered pitch, pitch, roll, roll; each pair by imaginary part, descending."""
    values, vectors = np.linalg.eig(jacobian)
    tilt_n1 = np.abs(vectors[0]) ** 2
    tilt_n2 = np.abs(vectors[1]) ** 2
    share = tilt_n1 / np.maximum(tilt_n1 + tilt_n2, np.finfo(float).tiny)
    order = np.argsort(-share, kind="stable")
    pitch, roll = values[order[:2]], values[order[2:]]

    def by_imaginary(pair: np.ndarray) -> np.ndarray:
        return pair[np.lexsort((-pair.real, -pair.imag))]

    return np.concatenate([by_imaginary(pitch), by_imaginary(roll)])


def _max_growth(eigenvalues: np.ndarray) -> np.ndarray:
    """Largest real part per row, with |Re λ| below the tolerance set to zero [1/s]."""
    growth = np.max(eigenvalues.real, axis=-1)
    scale = np.max(np.abs(eigenvalues), axis=-1)
    return np.where(np.abs(growth) <= GROWTH_TOLERANCE * scale, 0.0, growth)


@dataclass(frozen=True)
class SpinStability:
    """Eigenvalues of the linearised rolling model against steady spin.

    Made by :func:`spin_stability`.

    Parameters
    ----------
    body : Body
        The body.
    model : RollingModel
        The rolling model (damping σ).
    spin : numpy.ndarray
        Spin rates s [rad/s], shape (k,).
    eigenvalues : numpy.ndarray
        Complex eigenvalues λ [1/s], shape (k, 4), ordered as ``MODE_NAMES`` (pitch,
        pitch, roll, roll; each pair by Im λ descending).
    mirror_eigenvalues : numpy.ndarray
        The same at −spin, shape (k, 4), for the spin preference.
    """

    body: Body
    model: RollingModel
    spin: np.ndarray
    eigenvalues: np.ndarray
    mirror_eigenvalues: np.ndarray = field(repr=False)

    @cached_property
    def growth_rate_pitch(self) -> np.ndarray:
        """Growth rate of the pitch mode, max Re λ of its pair [1/s], shape (k,)."""
        return _max_growth(self.eigenvalues[:, :2])

    @cached_property
    def growth_rate_roll(self) -> np.ndarray:
        """Growth rate of the roll mode, max Re λ of its pair [1/s], shape (k,)."""
        return _max_growth(self.eigenvalues[:, 2:])

    @cached_property
    def frequency_pitch(self) -> np.ndarray:
        """Angular frequency of the pitch mode, max |Im λ| of its pair [rad/s], shape (k,)."""
        return np.max(np.abs(self.eigenvalues[:, :2].imag), axis=1)

    @cached_property
    def frequency_roll(self) -> np.ndarray:
        """Angular frequency of the roll mode, max |Im λ| of its pair [rad/s], shape (k,)."""
        return np.max(np.abs(self.eigenvalues[:, 2:].imag), axis=1)

    def _growth_by_sense(self) -> tuple[np.ndarray, np.ndarray]:
        """Largest growth rate at +|s| and at −|s| for each non-zero |s| of the grid."""
        here = _max_growth(self.eigenvalues)
        mirror = _max_growth(self.mirror_eigenvalues)
        nonzero = self.spin != 0.0
        positive = np.where(self.spin > 0, here, mirror)[nonzero]
        negative = np.where(self.spin > 0, mirror, here)[nonzero]
        return positive, negative

    @property
    def preferred_direction(self) -> int:
        """+1 or −1 if that sense of spin grows more slowly at every |s| of the grid, else 0.

        At each |s| the largest growth rate over both modes is compared between
        s = +|s| and s = −|s|; differences within the growth tolerance are ties.
        With D = I12 = 0 the spectrum is symmetric in s and the answer is 0.
        """
        positive, negative = self._growth_by_sense()
        if positive.size == 0:
            return 0
        scale = np.max(np.abs(np.concatenate([self.eigenvalues, self.mirror_eigenvalues])))
        margin = GROWTH_TOLERANCE * scale
        if np.all(positive < negative - margin):
            return 1
        if np.all(negative < positive - margin):
            return -1
        return 0

    @property
    def max_growth_rate_positive(self) -> float:
        """Largest growth rate over all modes and spins s = +|s| [1/s] (0 if none grows)."""
        positive, _ = self._growth_by_sense()
        return float(max(0.0, np.max(positive, initial=0.0)))

    @property
    def max_growth_rate_negative(self) -> float:
        """Largest growth rate over all modes and spins s = −|s| [1/s] (0 if none grows)."""
        _, negative = self._growth_by_sense()
        return float(max(0.0, np.max(negative, initial=0.0)))

    @property
    def preferred_direction_is_stable(self) -> bool:
        """Whether no mode grows at any |s| of the grid in the preferred sense."""
        if self.preferred_direction == 1:
            return self.max_growth_rate_positive == 0.0
        if self.preferred_direction == -1:
            return self.max_growth_rate_negative == 0.0
        return False

    def options(self) -> dict[str, Any]:
        """Give the settings of this analysis, for JSON summaries and NetCDF attributes.

        Returns
        -------
        dict of str to object
            Body, model, damping [N m s], spin grid [rad/s] and finite-difference step.
        """
        return {
            "body": self.body.name,
            "body_source": self.body.source,
            "model": self.model.name,
            "damping": self.model.damping,
            "spin_start": float(self.spin[0]),
            "spin_stop": float(self.spin[-1]),
            "spin_count": int(self.spin.size),
            "finite_difference_step": FINITE_DIFFERENCE_STEP,
        }

    def table(self) -> dict[str, tuple[str, np.ndarray]]:
        """Tabulate the result, one row per spin.

        Returns
        -------
        dict of str to (str, numpy.ndarray)
            Columns by name: (unit, values of shape (k,)).
        """
        columns: dict[str, tuple[str, np.ndarray]] = {
            "spin": (_UNITS["spin"], self.spin),
            "growth_rate_pitch": (_UNITS["growth_rate"], self.growth_rate_pitch),
            "growth_rate_roll": (_UNITS["growth_rate"], self.growth_rate_roll),
            "frequency_pitch": (_UNITS["frequency"], self.frequency_pitch),
            "frequency_roll": (_UNITS["frequency"], self.frequency_roll),
        }
        for index, mode in enumerate(MODE_NAMES):
            label = f"{mode}_{index % 2 + 1}"
            columns[f"{label}_real"] = (_UNITS["growth_rate"], self.eigenvalues[:, index].real)
            columns[f"{label}_imag"] = (_UNITS["frequency"], self.eigenvalues[:, index].imag)
        return columns

    def summary(self) -> dict[str, Any]:
        """Summarise the result for JSON.

        Returns
        -------
        dict of str to object
            Options, spins, eigenvalues [[re, im] × 4] per spin, the preferred sense.
        """
        direction = {1: "positive", -1: "negative", 0: "none"}[self.preferred_direction]
        return {
            **self.options(),
            "modes": list(MODE_NAMES),
            "spin": [float(s) for s in self.spin],
            "eigenvalues": [
                [[float(value.real), float(value.imag)] for value in row]
                for row in self.eigenvalues
            ],
            "growth_rate_pitch": [float(v) for v in self.growth_rate_pitch],
            "growth_rate_roll": [float(v) for v in self.growth_rate_roll],
            "preferred_spin_direction": direction,
            "preferred_direction_is_stable": self.preferred_direction_is_stable,
            "max_growth_rate_positive_spin": self.max_growth_rate_positive,
            "max_growth_rate_negative_spin": self.max_growth_rate_negative,
        }

    def to_dataset(self) -> xr.Dataset:
        """Convert the result to a dataset over ``spin``; options as attributes.

        Returns
        -------
        xarray.Dataset
            The columns of :meth:`table` with their units.
        """
        import xarray as xr

        variables = {}
        for name, (unit, values) in self.table().items():
            if name != "spin":
                variables[name] = xr.Variable(("spin",), values, attrs={"units": unit})
        direction = {1: "positive", -1: "negative", 0: "none"}[self.preferred_direction]
        attrs: dict[str, str | float | int] = {
            "title": f"celtstone linear stability of steady spin, {self.body.name}",
            **self.options(),
            "modes": ", ".join(MODE_NAMES),
            "preferred_spin_direction": direction,
            "preferred_direction_is_stable": int(self.preferred_direction_is_stable),
        }
        return xr.Dataset(
            variables,
            coords={"spin": ("spin", self.spin, {"units": _UNITS["spin"]})},
            attrs=attrs,
        )


def spin_stability(
    body: Body,
    spin_rates: np.ndarray | list[float],
    model: RollingModel | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> SpinStability:
    """Linearise the rolling model about steady spin and find its eigenvalues.

    The Jacobian is the kernel's own, by central differences (docs/decisions.md §12).

    Parameters
    ----------
    body : Body
        A body with I13 = I23 = 0.
    spin_rates : array_like
        Spin rates s = ω · n [rad/s], shape (k,), finite, 1 <= k <= MAX_SPIN_COUNT.
    model : RollingModel, optional
        The rolling model (damping σ); default σ = 0.
    progress : callable, optional
        Called with the number of spin rates done so far and their total, every
        ``PROGRESS_EVERY`` of them and at the end (a progress bar).

    Returns
    -------
    SpinStability
        Eigenvalues for each spin rate and at its mirror image.
    """
    model = _rolling(model)
    spins = np.asarray(spin_rates, dtype=float)
    if spins.ndim != 1 or not 1 <= spins.size <= MAX_SPIN_COUNT:
        raise ParameterError("spin", spin_rates, f"1 to {MAX_SPIN_COUNT} spin rates in rad/s")
    if not np.all(np.abs(spins) <= schema.MAX_ANGULAR_SPEED):  # NaN fails too
        raise ParameterError(
            "spin",
            spin_rates,
            f"finite spin rates in [-{schema.MAX_ANGULAR_SPEED:g}, {schema.MAX_ANGULAR_SPEED:g}] "
            "rad/s",
        )
    _check_body(body)
    params = kernel_parameters(model, body)  # once: each spin costs two Jacobians only
    eigenvalues = np.empty((spins.size, 4), dtype=complex)
    mirror = np.empty((spins.size, 4), dtype=complex)
    for index, spin_rate in enumerate(spins):
        eigenvalues[index] = _ordered_eigenvalues(_jacobian(params, float(spin_rate)))
        mirror[index] = _ordered_eigenvalues(_jacobian(params, -float(spin_rate)))
        if progress is not None and (index + 1) % PROGRESS_EVERY == 0:
            progress(index + 1, spins.size)
    if progress is not None and spins.size % PROGRESS_EVERY:
        progress(spins.size, spins.size)
    return SpinStability(body, model, spins, eigenvalues, mirror)


def parse_spin_range(text: str) -> np.ndarray:
    """Spin rates from ``"START:STOP:COUNT"`` (like ``numpy.linspace``) [rad/s].

    Parameters
    ----------
    text : str
        ``"START:STOP:COUNT"``: COUNT is an integer in [1, MAX_SPIN_COUNT]; COUNT = 1
        needs START = STOP.

    Returns
    -------
    numpy.ndarray
        The COUNT spin rates [rad/s].

    Raises
    ------
    ParameterError
        For text of another form, or numbers out of range.
    """
    allowed = (
        f"START:STOP:COUNT with START <= STOP in [-{schema.MAX_ANGULAR_SPEED:g}, "
        f"{schema.MAX_ANGULAR_SPEED:g}] rad/s and an integer COUNT "
        f"in [1, {MAX_SPIN_COUNT}], e.g. -10:10:201"
    )
    parts = str(text).split(":")
    if len(parts) != 3:
        raise ParameterError("spin", text, allowed)
    try:
        start, stop = float(parts[0]), float(parts[1])
        count = int(parts[2])
    except ValueError:
        raise ParameterError("spin", text, allowed) from None
    in_range = abs(start) <= schema.MAX_ANGULAR_SPEED and abs(stop) <= schema.MAX_ANGULAR_SPEED
    if not in_range or not 1 <= count <= MAX_SPIN_COUNT:
        raise ParameterError("spin", text, allowed)
    if start > stop or (count == 1 and start != stop) or (count > 1 and start == stop):
        raise ParameterError("spin", text, allowed, "START < STOP, or START = STOP with COUNT 1")
    return np.linspace(start, stop, count)
