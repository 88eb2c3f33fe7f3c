"""What a reproduction runs: one body, one start, the paper's friction settings.

The paper gives no body parameters; each :class:`Study` names a shipped body
(``docs/bodies.md``) and carries every setting of the three targets, so the
report can state exactly what was run. :func:`reduced` shortens a study for
tests (fewer and shorter runs, same physics).

A study carries its contact too: the paper's idealisation (a disk of fixed radius
ε = 1 mm, Zhuravlev's Padé law, no rolling resistance; :data:`STUDIES`) or a variant
such as the realistic contact of :data:`REALISTIC_STUDIES` (the elliptic Hertz
contact, the exact law, a rolling-friction length). :attr:`Study.key` names a study's
files and its column of the report: the body's name for the paper's contact,
``BODY+VARIANT`` otherwise.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from celtstone.bodies import Body, load_body
from celtstone.errors import ParameterError
from celtstone.simulation.integrate import DEFAULT_ATOL, DEFAULT_RTOL
from celtstone.simulation.models import CONTACTS, InitialState, RollingModel, SlidingModel
from celtstone.simulation.reversals import reversal_band

__all__ = [
    "PAPER_FRICTIONS",
    "REALISTIC_CONTACT",
    "REALISTIC_STUDIES",
    "STUDIES",
    "TARGETS",
    "Study",
    "realistic_study_for",
    "reduced",
    "study_for",
]

TARGETS = ("fig2", "fig3", "threshold")
"""The targets of one study: the paper's Figures 2 and 3 and the friction threshold."""
PAPER_FRICTIONS = (0.35, 0.25, 0.15)  # the paper's Figure 2
PAPER_CONTACT_RADIUS = 0.001  # eps [m], paper section 4


@dataclass(frozen=True)
class Study:
    """Settings of the reproduction for one body (SI units, angles in deg).

    Parameters
    ----------
    body : str
        Shipped body name or .toml path.
    omega : tuple of float
        Initial angular velocity in body axes [rad/s].
    euler_angles : tuple of float
        Initial Euler angles (α, β) [deg].
    contact_radius : float
        Contact radius ε [m] (paper: 1 mm).
    frictions : tuple of float
        Friction coefficients f of the Figure 2 analogue [1].
    fig2_t_end : float
        Length of the Figure 2 runs [s].
    fig3_t_end : float
        Length of the Figure 3 runs [s] (>= 3 reversals in rolling).
    fig3_friction : float
        Friction coefficient f of the long sliding run [1].
    threshold_grid : tuple of (float, float, int)
        (start, stop, count) of the f grid [1].
    threshold_t_end : float
        Length of each threshold run [s].
    bisection_tolerance : float
        Width of the final f bracket [1].
    rtol : float
        Relative tolerance of the integrator.
    atol : float
        Absolute tolerance of the integrator.
    reduced : bool
        True for the shortened form made by :func:`reduced` (tests, ``--quick``).
    variant : str
        Name of the contact variant, "" for the paper's idealisation (the disk of
        radius ε, Padé law, N = m g); it suffixes :attr:`key`.
    contact_shape : str
        "circle" (the paper's disk) or "ellipse" (the Hertz ellipse at the current
        contact point, docs/decisions.md §29).
    elastic_modulus : float or None
        E of stone and plane [Pa], or None for the fixed ε.
    poisson_ratio : float or None
        Poisson's ratio ν of stone and plane [1], or None (given with E).
    friction_law : str
        "pade" (paper eq. 10, 12) or "exact".
    friction_load : str
        The normal force of the friction law in the threshold and Figure 3 runs:
        "static" (N = m g, the paper's) or "dynamic"; Figure 2 runs both.
    rolling_resistance : float
        Rolling-friction length λ [m] of both models (0: none).
    fig2_loads : tuple of str
        The friction loads of the Figure 2 runs (the paper's: both), which include
        ``friction_load``.
    targets : tuple of str
        The targets this study runs (the paper's: all of :data:`TARGETS`).
    contact : str
        "sliding" (the paper's regularised sliding contact) or "hybrid" (the stick–slip
        contact, ``celtstone.solvers.phases``).
    ingredient_frictions : tuple of float
        The f [1] of the one-at-a-time runs of a paper-contact study's Figure 2 target
        (``reproduce.ingredients``): each ingredient of the realistic contact alone.
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
    variant: str = ""
    contact_shape: str = "circle"
    elastic_modulus: float | None = None
    poisson_ratio: float | None = None
    friction_law: str = "pade"
    friction_load: str = "static"
    rolling_resistance: float = 0.0
    fig2_loads: tuple[str, ...] = ("static", "dynamic")
    targets: tuple[str, ...] = TARGETS
    contact: str = "sliding"
    ingredient_frictions: tuple[float, ...] = (0.25, 0.35, 0.5)

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
        if not all(c.isalnum() or c in "_-" for c in self.variant):
            raise ParameterError("variant", self.variant, "letters, digits, _ and - (file names)")
        self.sliding(max(self.frictions, default=0.35))  # every contact setting checked once
        if self.friction_load not in self.fig2_loads:
            raise ParameterError(
                "fig2_loads",
                self.fig2_loads,
                f"loads that include friction_load {self.friction_load}",
            )

    @property
    def body_name(self) -> str:
        """The body's name as :func:`~celtstone.bodies.load_body` gives it (a file's stem)."""
        text = self.body
        return Path(text).stem if text.endswith(".toml") or Path(text).is_file() else text

    @property
    def key(self) -> str:
        """Name of the study's files and report column.

        The body, or ``BODY+VARIANT`` for a contact other than the paper's.
        """
        return f"{self.body_name}+{self.variant}" if self.variant else self.body_name

    @property
    def is_paper_contact(self) -> bool:
        """Whether the study uses the paper's idealised contact (no variant)."""
        return not self.variant

    @property
    def initial_state(self) -> InitialState:
        """The start shared by every run of the study."""
        return InitialState(omega=self.omega, euler_angles=self.euler_angles)

    def load_body(self) -> Body:
        """Load the study's body.

        Returns
        -------
        Body
            The body.
        """
        return load_body(self.body)

    @property
    def initial_spin(self) -> float:
        """The spin ω0·n0 of the shared start [rad/s]."""
        return float(np.dot(self.omega, self.initial_state.vertical))

    @property
    def band(self) -> float:
        """Hysteresis band of a reversal [rad/s] (``analysis.reversal_band``)."""
        return reversal_band(self.initial_spin)

    def friction_grid(self) -> np.ndarray:
        """Make the threshold's grid of f.

        Returns
        -------
        numpy.ndarray
            The friction coefficients [1], shape (count,).
        """
        start, stop, count = self.threshold_grid
        # the decimals a person writes (0.35, not linspace's 0.35000000000000003), so that
        # a grid point equal to a figure's f is the same run, computed once (SharedRuns)
        return np.round(np.linspace(start, stop, int(count)), 12)

    def sliding(self, friction: float, friction_load: str | None = None) -> SlidingModel:
        """Make the study's sliding model at one friction coefficient.

        Parameters
        ----------
        friction : float
            Friction coefficient f [1].
        friction_load : str, optional
            The friction load ("static" or "dynamic"); default the study's.

        Returns
        -------
        SlidingModel
            The model.
        """
        if self.contact not in CONTACTS:
            raise ParameterError("contact", self.contact, " or ".join(CONTACTS))
        return CONTACTS[self.contact](
            friction_coefficient=friction,
            contact_radius=self.contact_radius,
            friction_load=self.friction_load if friction_load is None else friction_load,
            friction_law=self.friction_law,
            contact_shape=self.contact_shape,
            elastic_modulus=self.elastic_modulus,
            poisson_ratio=self.poisson_ratio,
            rolling_resistance=self.rolling_resistance,
        )

    def rolling(self) -> RollingModel:
        """Make the rolling model without damping, with the study's rolling resistance.

        Returns
        -------
        RollingModel
            The model.
        """
        return RollingModel(rolling_resistance=self.rolling_resistance)

    def contact_words(self) -> str:
        """Say the contact in a few words (figure titles).

        Returns
        -------
        str
            "ε = 1 mm" for the paper's contact.
        """
        if self.contact_shape == "circle" and self.elastic_modulus is None:
            words = f"ε = {self.contact_radius * 1e3:g} mm"
        else:
            words = f"Hertz {self.contact_shape}, E = {self.elastic_modulus:g} Pa, ν = "
            words += f"{self.poisson_ratio:g}"
        if self.friction_law != "pade":
            words += f", {self.friction_law} law"
        if self.rolling_resistance:
            words += f", λ = {self.rolling_resistance:g} m"
        if self.contact == "hybrid":
            words += ", stick–slip"
        return words

    def contact_settings(self) -> dict[str, str | float]:
        """List the contact's settings for table headers.

        Returns
        -------
        dict of str to str or float
            The contact radius ε and the law for the paper's contact, every setting that
            differs from it for a variant.
        """
        if self.is_paper_contact:
            return {
                "contact_radius_m": self.contact_radius,
                "friction_law": "zhuravlev_pade (paper eq. 10, 12)",
            }
        model = self.sliding(max(self.frictions, default=0.35))
        return {
            "contact_variant": self.variant,
            "contact_shape": self.contact_shape,
            "contact_radius_m": "hertz" if model.is_hertz_radius else self.contact_radius,
            "elastic_modulus_Pa": "none" if self.elastic_modulus is None else self.elastic_modulus,
            "poisson_ratio": "none" if self.poisson_ratio is None else self.poisson_ratio,
            "friction_law": self.friction_law,
            "rolling_resistance_m": self.rolling_resistance,
            "contact": self.contact,
            "friction_load": self.friction_load,
        }

    def describe(self) -> str:
        """Say the study in one line for reports.

        Returns
        -------
        str
            Body, start, contact (and its variant's settings).
        """
        line = ("REDUCED (--quick) " if self.reduced else "") + (
            f"{self.body}, ω0 = {list(self.omega)} rad/s (body axes), Euler angles α, β = "
            f"{list(self.euler_angles)} deg, "
        )
        if self.is_paper_contact:
            return line + f"ε = {self.contact_radius * 1e3:g} mm"
        start, stop, count = self.threshold_grid
        load = "N = m g" if self.friction_load == "static" else "the dynamic N"
        return line + (
            f"contact {self.variant}: {self.contact_words()}, friction load {load} in the "
            f"threshold and Figure 3 runs, threshold grid f = {start:g} … {stop:g} "
            f"({int(count)} points)"
        )


PMMA_ON_GLASS_MODULUS = 5740609496.810772
"""E [Pa] of a model whose E* = E / (2(1 − ν²)) with ν = 0.35 is that of PMMA (E = 3 GPa,
ν = 0.35) on soda-lime glass (72 GPa, 0.22): ``celtstone.atlas.MaterialPair("pmma",
"glass").model_settings()`` (the atlas declares the materials; the layers keep it from
being imported here, and tests/test_atlas_family.py checks the two equal)."""
PMMA_POISSON_RATIO = 0.35  # ν of the stone, as the atlas's MaterialPair passes it

ATLAS_STONE_STUDY = Study(
    body="atlas_stone_25cm",
    variant="hertz-pmma-glass",
    contact="hybrid",
    elastic_modulus=PMMA_ON_GLASS_MODULUS,
    poisson_ratio=PMMA_POISSON_RATIO,
)
"""The atlas's stone (docs/bodies.md) in the contact it was found with: ε the Hertz radius
of PMMA on glass (circular), Zhuravlev's Padé law, N = m g, the stick–slip contact, as
the atlas's study (docs/decisions.md §32); start, lengths and grids the paper study's."""

STUDIES = (
    Study(body="kane_levinson_1982"),
    Study(body="toy_rattleback_10cm"),
    ATLAS_STONE_STUDY,
)
"""One study per reproduced body, in its own contact (the paper's unless it names a variant)."""

REALISTIC_ELASTIC_MODULUS = 3e9  # Pa, docs/decisions.md §29: a polymer stone on a polymer plate
REALISTIC_POISSON_RATIO = 0.35  # 1, with E: K&L's circular Hertz radius 1.09 mm ≈ the paper's ε
REALISTIC_ROLLING_RESISTANCE = 1e-5  # λ [m]: Cross 2016, an order of magnitude (see _realistic)


REALISTIC_CONTACT: dict[str, str | float] = {
    "contact_shape": "ellipse",
    "elastic_modulus": REALISTIC_ELASTIC_MODULUS,
    "poisson_ratio": REALISTIC_POISSON_RATIO,
    "friction_law": "exact",
    "rolling_resistance": REALISTIC_ROLLING_RESISTANCE,
    "friction_load": "dynamic",
    "contact": "hybrid",
}
"""The settings of :class:`Study` that the realistic contact changes (see ``_realistic``);
``reproduce.ingredients`` changes them one at a time."""


def _realistic(body: str) -> Study:
    """The realistic contact for ``body``: what changes against the paper's idealisation.

    * the elliptic Hertz contact at the current contact point (docs/decisions.md §29) of
      a polymer stone on a polymer plate, E = 3 GPa and ν = 0.35, chosen so that
      K&L's *circular* Hertz radius is 1.09 mm, the paper's ε: the comparison changes
      the contact's shape (an ellipse 3.1 mm × 0.28 mm for K&L at rest), not its size;
    * the exact Coulomb–Contensou law (the Padé law's own error is up to 0.39 f N,
      decisions §29);
    * a rolling-friction length λ = 1e-5 m for both bodies (docs/equations.md "Rolling
      resistance"). Coulomb's law of rolling friction (Cross 2016) makes λ a length
      independent of speed, of order 1e-6 m to 1e-3 m from hard to soft floors;
      Awrejcewicz & Kudra (2019) relate it to the contact's size. 1e-5 m, 1 % of K&L's
      Hertz radius (7 % of the toy's 0.14 mm), is an order-of-magnitude estimate for a
      hard polymer pair, not a measurement of any stone; decisions §25 measures that
      1e-5 m stops a rocking K&L in about 93 s and 1e-4 m in about 9 s;
    * the friction load: Figure 2 runs both loads, as the paper's study, and the
      one-at-a-time table (``reproduce.ingredients``) runs the consistent load (the true
      normal force N, "dynamic") alone and with everything else. The threshold and Figure 3
      runs keep the paper's N = m g ("static"), which lets the friction force exceed
      Coulomb's bound f N of the true N (by up to 21 % for K&L): with the consistent load
      and the stick–slip contact, the threshold's grid held runs that had not ended after
      40 minutes on two cores, against about a minute for the whole grid with N = m g;
    * the stick–slip contact (``celtstone.solvers.phases``): a real contact sticks, without the
      regularised law's creep. It is also what makes these runs affordable: once the
      spin has died, the regularised elliptic contact at rest is stiff (one K&L 20 s run
      at f = 0.15 did not end within 150 s), while in stick the stone rolls (1.7 s for
      the same run; decisions §30).

    Everything else (start, grids, run lengths) is the paper study's.
    """
    settings = {**REALISTIC_CONTACT, "friction_load": "static"}  # the cost: see above
    return Study(body=body, variant="realistic", **settings)  # type: ignore[arg-type]


REALISTIC_STUDIES = tuple(_realistic(study.body) for study in STUDIES if study.is_paper_contact)
"""The realistic contact for each body of a paper-contact study (the atlas's stone has its
own contact: no second variant of it)."""


def study_for(body: str) -> Study:
    """Find the shipped study of ``body``, or make a default study for any other body.

    Parameters
    ----------
    body : str
        Shipped body name or .toml path; a shipped study's body gets its settings.

    Returns
    -------
    Study
        The paper's contact on the body.
    """
    for study in STUDIES:
        if study.body == body:
            return study
    return Study(body=body)


def realistic_study_for(body: str) -> Study:
    """Make the realistic contact of :data:`REALISTIC_STUDIES` for any ``body``.

    Parameters
    ----------
    body : str
        Shipped body name or .toml path.

    Returns
    -------
    Study
        The study of variant "realistic" on the body.
    """
    return _realistic(body)


def reduced(study: Study, scale: float = 0.25, grid_count: int = 6) -> Study:
    """Shorten ``study`` for tests and smoke runs.

    The physics is unchanged; the statements about late times (Figure 3) may not hold
    in the shortened runs.

    Parameters
    ----------
    study : Study
        The study.
    scale : float, optional
        Length of the runs, as a fraction of the study's.
    grid_count : int, optional
        Points of the f grid.

    Returns
    -------
    Study
        The shortened study (``reduced`` True).
    """
    start, stop, _ = study.threshold_grid
    return dataclasses.replace(
        study,
        fig2_t_end=study.fig2_t_end * scale,
        fig3_t_end=study.fig3_t_end * scale,
        threshold_t_end=study.threshold_t_end * scale,
        threshold_grid=(start, stop, grid_count),
        ingredient_frictions=(0.35,),
        bisection_tolerance=max(study.bisection_tolerance, 0.02),
        reduced=True,
    )
