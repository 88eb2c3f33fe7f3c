"""What a reproduction runs: one body, one start, the paper's friction settings.

The paper gives no body parameters; each :class:`Study` names a shipped body
(``docs/bodies.md``) and carries every setting of the three targets, so the
report can state exactly what was run. :func:`reduced` shortens a study for
tests (fewer and shorter runs, same physics).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from celtstone.analysis import reversal_band
from celtstone.bodies import Body, load_body
from celtstone.errors import ParameterError
from celtstone.integrate import DEFAULT_ATOL, DEFAULT_RTOL
from celtstone.models import InitialState, RollingModel, SlidingModel

__all__ = ["PAPER_FRICTIONS", "STUDIES", "TARGETS", "Study", "reduced", "study_for"]

TARGETS = ("fig2", "fig3", "threshold")
PAPER_FRICTIONS = (0.35, 0.25, 0.15)  # the paper's Figure 2
PAPER_CONTACT_RADIUS = 0.001  # eps [m], paper section 4


@dataclass(frozen=True)
class Study:
    """Settings of the reproduction for one body (SI units, angles in deg).

    Parameters
    ----------
    body : shipped body name or .toml path
    omega : initial angular velocity in body axes [rad/s]
    euler_angles : initial Euler angles (α, β) [deg]
    contact_radius : ε [m] (paper: 1 mm)
    frictions : f of the Figure 2 analogue [1]
    fig2_t_end : length of the Figure 2 runs [s]
    fig3_t_end : length of the Figure 3 runs [s] (>= 3 reversals in rolling)
    fig3_friction : f of the long sliding run [1]
    threshold_grid : (start, stop, count) of the f grid [1]
    threshold_t_end : length of each threshold run [s]
    bisection_tolerance : width of the final f bracket [1]
    rtol, atol : integrator tolerances
    reduced : True for the shortened form made by :func:`reduced` (tests, ``--quick``)
    """

    body: str
    omega: tuple[float, float, float] = (0.0, 0.0, -5.0)
    euler_angles: tuple[float, float] = (0.5, 0.5)
    contact_radius: float = PAPER_CONTACT_RADIUS
    frictions: tuple[float, ...] = PAPER_FRICTIONS
    fig2_t_end: float = 20.0
    fig3_t_end: float = 50.0
    fig3_friction: float = 0.35
    threshold_grid: tuple[float, float, int] = (0.02, 0.5, 49)
    threshold_t_end: float = 20.0
    bisection_tolerance: float = 0.005
    rtol: float = DEFAULT_RTOL
    atol: float = DEFAULT_ATOL
    reduced: bool = False

    def __post_init__(self) -> None:
        start, stop, count = self.threshold_grid
        if not (0.0 <= start < stop and int(count) >= 2):
            raise ParameterError(
                "threshold_grid",
                self.threshold_grid,
                "START:STOP:COUNT, 0 <= START < STOP, COUNT >= 2",
            )
        if not self.bisection_tolerance > 0.0:
            raise ParameterError("bisection_tolerance", self.bisection_tolerance, "a number > 0")

    @property
    def initial_state(self) -> InitialState:
        """The start shared by every run of the study."""
        return InitialState(omega=self.omega, euler_angles=self.euler_angles)

    def load_body(self) -> Body:
        """The study's body."""
        return load_body(self.body)

    @property
    def band(self) -> float:
        """Hysteresis band of a reversal [rad/s] (``analysis.reversal_band``)."""
        return reversal_band(float(np.dot(self.omega, self.initial_state.vertical)))

    def friction_grid(self) -> np.ndarray:
        """The threshold's grid of f [1]."""
        start, stop, count = self.threshold_grid
        return np.linspace(start, stop, int(count))

    def sliding(self, friction: float, friction_load: str = "static") -> SlidingModel:
        """The paper's sliding model at friction coefficient ``friction``."""
        return SlidingModel(
            friction_coefficient=friction,
            contact_radius=self.contact_radius,
            friction_load=friction_load,
        )

    @staticmethod
    def rolling() -> RollingModel:
        """The rolling model without damping."""
        return RollingModel()

    def describe(self) -> str:
        """One line for reports: body, start, contact radius."""
        return ("REDUCED (--quick) " if self.reduced else "") + (
            f"{self.body}, ω0 = {list(self.omega)} rad/s (body axes), Euler angles α, β = "
            f"{list(self.euler_angles)} deg, ε = {self.contact_radius * 1e3:g} mm"
        )


STUDIES = (
    Study(body="kane_levinson_1982"),
    Study(body="toy_rattleback_10cm"),
)


def study_for(body: str) -> Study:
    """The shipped study of ``body``, or a default study for any other body."""
    for study in STUDIES:
        if study.body == body:
            return study
    return Study(body=body)


def reduced(study: Study, scale: float = 0.25, grid_count: int = 6) -> Study:
    """``study`` with runs ``scale`` times as long and a ``grid_count``-point f grid.

    For tests and smoke runs: the physics is unchanged, the statements about
    late times (Figure 3) may not hold in the shortened runs.
    """
    start, stop, _ = study.threshold_grid
    return dataclasses.replace(
        study,
        fig2_t_end=study.fig2_t_end * scale,
        fig3_t_end=study.fig3_t_end * scale,
        threshold_t_end=study.threshold_t_end * scale,
        threshold_grid=(start, stop, grid_count),
        bisection_tolerance=max(study.bisection_tolerance, 0.02),
        reduced=True,
    )
