"""The outcome of a fit: best values, uncertainties, the starts, and the fitted run."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from celtstone.fitting.intervals import ProfiledInterval
from celtstone.fitting.nuisance import NUISANCES, bias_name, is_nuisance, scale_name
from celtstone.fitting.problem import Problem, current_values
from celtstone.fitting.profile import Profile
from celtstone.fitting.series import SERIES
from celtstone.fitting.uncertainty import JointRegion, Uncertainty
from celtstone.simulation.trajectory import Trajectory
from celtstone.sweep.spec import PARAMETERS

if TYPE_CHECKING:
    from celtstone.bodies import Body
    from celtstone.fitting.assess import Assessment
    from celtstone.simulation.models import Model

__all__ = ["FORMAT", "FitResult", "StartOutcome"]

FORMAT = "celtstone-fit-1"  # the summary's "format": what `fit --overwrite` may replace
Z_95 = 1.959963984540054  # the normal distribution's 97.5 % quantile


@dataclass(frozen=True)
class StartOutcome:
    """One start of the optimiser: where it began and ended [units of the parameters],
    its cost [1], whether least_squares reported convergence, its message, its runs, and
    whether it reached the best start's minimum (within half the residual variance)."""

    start: np.ndarray
    end: np.ndarray
    cost: float
    converged: bool
    message: str
    runs: int
    reached_best: bool

    def summary(self, names: tuple[str, ...]) -> dict[str, Any]:
        return {
            "start": dict(zip(names, self.start.tolist(), strict=True)),
            "end": dict(zip(names, self.end.tolist(), strict=True)),
            "cost": self.cost,
            "converged": self.converged,
            "reached_best": self.reached_best,
            "message": self.message,
            "runs": self.runs,
        }


def hertz_radii(model: Model, body: Body, trajectory: Trajectory) -> np.ndarray:
    """The Hertz contact radius ε [m] the run used at each of its samples: the kernel's
    own ``contact_radius`` of the vertical n and the friction law's load (m g, or the true
    N with ``friction_load="dynamic"``), shape (samples reached,)."""
    from celtstone.kernels.dynamics import contact_radius
    from celtstone.simulation.models import kernel_parameters

    params = kernel_parameters(model, body)
    vertical = trajectory.samples.values("n")
    if getattr(model, "friction_load", "static") == "dynamic":
        loads = trajectory.samples.values("normal_force")
    else:
        loads = np.full(len(vertical), body.mass * body.gravity)
    return np.array(
        [
            contact_radius((float(n[0]), float(n[1]), float(n[2])), float(load), params)
            for n, load in zip(vertical, loads, strict=True)
        ]
    )


def _number(value: float) -> float | None:
    """JSON's number, or null for inf and NaN."""
    return float(value) if math.isfinite(value) else None


@dataclass(frozen=True)
class FitResult:
    """A finished fit.

    Parameters
    ----------
    problem : Problem
        What was fitted (record, body, model, free and fixed numbers, weights).
    values : numpy.ndarray
        Best values [units of ``problem.free``], shape (p,).
    cost : float
        ½ Σ r² at the best values [1].
    residuals : numpy.ndarray
        Weighted residuals there [1], shape (m,).
    uncertainty : Uncertainty
        Standard errors, correlation, rank.
    starts : tuple of StartOutcome
        Each start's outcome, the user's (or default) start first.
    runs : int
        Simulations made.
    failed_runs : int
        Those of the runs that stopped early or raised.
    runs_by_stage : mapping of str to int
        Those of each stage of the fit, in order: the screening of the global search,
        the local fits from the starts, a refit with each series weighted by its
        residuals' noise, the checks and profiles of the intervals
        (``fitting.intervals``), ``--profile``, the fitted run and its integration check.
    speculative_runs_wasted : int
        Those of the runs that were Jacobian columns started beside a residual
        (``fitting.runs``) at a point whose Jacobian was never asked for (a step the
        optimiser rejected, a start's last trial).
    wall_time : float
        Time the fit took [s].
    trajectory : Trajectory
        The run at the best values, sampled at the record's times.
    profile : Profile or None
        The profile likelihood of one parameter, if asked for.
    intervals : tuple of ProfiledInterval
        The profile-likelihood 95 % intervals of the physical numbers whose cost is not
        quadratic about the optimum, or of every record of one series
        (``fitting.intervals``); their standard errors are widened to hold them, and the
        joint region to hold their crossings of its level.
    moved_by_profile : tuple of float
        The costs [1] of the optima a profile's walk moved away from, having found a lower
        cost beside them (the fit was made again from there); empty when none.
    warnings : tuple of str
        The warnings issued (identifiability and fit quality).
    assessment : Assessment or None
        Whether to believe it (``fitting.assess``): ``converged``, goodness of fit,
        whiteness, information criteria.
    device : str
        Where the fit's batches of runs went: "cpu", or the GPU's name ("NVIDIA H200";
        ``fit(device=...)``); the fitted run and its integration check run on the CPU.
    """

    problem: Problem
    values: np.ndarray
    cost: float
    residuals: np.ndarray
    uncertainty: Uncertainty
    starts: tuple[StartOutcome, ...]
    runs: int
    failed_runs: int
    runs_by_stage: Mapping[str, int]
    speculative_runs_wasted: int
    wall_time: float
    trajectory: Trajectory
    profile: Profile | None = None
    intervals: tuple[ProfiledInterval, ...] = ()
    moved_by_profile: tuple[float, ...] = ()
    warnings: tuple[str, ...] = ()
    assessment: Assessment | None = None
    device: str = "cpu"

    @property
    def converged(self) -> bool:
        """Whether the values are a minimum of the cost inside the bounds."""
        return self.assessment.converged if self.assessment is not None else True

    @property
    def names(self) -> tuple[str, ...]:
        """Names of the free numbers, in the order of :attr:`values`."""
        return self.problem.names

    @property
    def standard_errors(self) -> np.ndarray:
        """Standard errors of :attr:`values` [their units]; inf where undetermined."""
        return self.uncertainty.standard_errors

    @property
    def correlation(self) -> np.ndarray:
        """Correlation matrix of the free numbers [1], shape (p, p)."""
        return self.uncertainty.correlation

    @property
    def joint_region(self) -> JointRegion:
        """The joint 95 % region of the physical numbers (``Problem.physical_columns``).

        It holds all their true values together in 95 % of records, where each one's
        95 % interval holds its own (``uncertainty.JointRegion``); where profiles were
        walked, widened to hold their crossings of its level.
        """
        columns = self.problem.physical_columns
        u = self.uncertainty
        covariance = u.covariance if u.joint_covariance is None else u.joint_covariance
        return JointRegion(
            tuple(self.names[j] for j in columns),
            self.values[columns],
            covariance[np.ix_(columns, columns)],
        )

    def series_residuals(self) -> dict[str, np.ndarray]:
        """Split the residuals by series, unweighted.

        Returns
        -------
        dict of str to numpy.ndarray
            Series name -> model − data at the best values [unit of the series].
        """
        sigma = self.problem.sigma
        parts, start = {}, 0
        for name, measured in self.problem.record.series.items():
            parts[name] = self.residuals[start : start + measured.size] * sigma[name]
            start += measured.size
        return parts

    def noise_estimates(self) -> dict[str, float]:
        """Estimate each series' noise from its residuals.

        Returns
        -------
        dict of str to float
            Series name -> the noise σ the residuals imply [unit of the series]: their
            RMS corrected for the fitted degrees of freedom, RMS · sqrt(m / (m − p)).
        """
        ratio = self.problem.n_residuals / self.problem.degrees_of_freedom
        return {
            name: float(np.sqrt(np.mean(r**2) * ratio))
            for name, r in self.series_residuals().items()
        }

    def held(self) -> dict[str, dict[str, Any]]:
        """Every number the fit held fixed, with where it came from.

        Returns
        -------
        dict of str to dict
            Name -> value [SI], unit and source: "set" (given), "record's first sample",
            "default" (the model's, body's or initial state's; a gyroscope's scale error:
            0), a Hertz contact's computed radius, or a bias not fitted.
        """
        problem = self.problem
        model, body, state = problem.configuration(self.values)
        held: dict[str, dict[str, Any]] = {}
        for name, value in current_values(model, body, state).items():
            if name in problem.names or (name == "initial_spin" and "omega3" in problem.names):
                continue
            source = problem.fixed_source.get(name, "default")
            unit = PARAMETERS[name].unit
            if name == "contact_radius" and getattr(model, "is_hertz_radius", False):
                radii = hertz_radii(model, body, self.trajectory)
                held[name] = {
                    "value": _number(float(np.mean(radii))) if radii.size else None,
                    "range": [_number(float(radii.min())), _number(float(radii.max()))]
                    if radii.size
                    else None,
                    "unit": unit,
                    "source": "Hertz contact: computed at each sample of the fitted run from "
                    "elastic_modulus, poisson_ratio, the friction's normal load and the "
                    "curvature at the contact point; value: their mean, range: least and "
                    "largest (the default is not used)",
                }
                continue
            held[name] = {"value": value, "unit": unit, "source": source}
        for name, value in problem.fixed.items():
            if is_nuisance(name):
                held[name] = {"value": value, "unit": NUISANCES[name].unit, "source": "set"}
        for series in problem.record.series:
            if not SERIES[series].is_gyroscope_rate:
                continue
            for name, source in (
                (bias_name(series), "not fitted"),
                (scale_name(series), "default"),
            ):
                if name not in {*problem.names, *held}:
                    held[name] = {"value": 0.0, "unit": NUISANCES[name].unit, "source": source}
        return held

    def summary(self) -> dict[str, Any]:
        """Summarise the fit for ``summary.json``.

        Returns
        -------
        dict
            The JSON summary (SI units; inf and NaN as null).
        """
        problem, u, checks = self.problem, self.uncertainty, self.assessment
        names = problem.names
        units = {p.name: p.unit for p in problem.free}
        parameters = {
            name: {
                "value": float(value),
                "standard_error": _number(error),
                "unit": units[name],
                "interval_95": [_number(value - Z_95 * error), _number(value + Z_95 * error)],
                "lower_bound": p.lower,
                "upper_bound": p.upper,
                "at_bound": bool(checks is not None and name in checks.at_bound),
                "start": p.start,
                "kind": "sensor or record" if is_nuisance(name) else "physical",
            }
            for name, value, error, p in zip(
                names, self.values, u.standard_errors, problem.free, strict=True
            )
        }
        return {
            "format": FORMAT,
            "converged": self.converged,
            "warnings": list(self.warnings),
            "body": problem.body.name,
            "model": problem.model_name,
            "options": dict(problem.choices),
            "fixed": dict(problem.fixed),
            "held": self.held(),
            "free": list(names),
            "parameters": parameters,
            "correlation": [[_number(c) for c in row] for row in u.correlation],
            "strongly_correlated": [
                {"parameters": [a, b], "correlation": c} for a, b, c in u.strongly_correlated
            ],
            "jacobian_rank": u.rank,
            "condition_number": _number(u.condition_number),
            "joint_region_95": self.joint_region.summary() if problem.physical_columns else None,
            "standard_errors_widened_by": dict(zip(names, u.widened_by_profile, strict=True))
            if u.widened_by_profile
            else {},
            "cost": self.cost,
            "residual_variance": u.residual_variance,
            "degrees_of_freedom": problem.degrees_of_freedom,
            "series": {
                name: {
                    "unit": SERIES[name].unit,
                    "sigma": problem.sigma[name],
                    "sigma_source": problem.sigma_source.get(name, "given"),
                    "residual_rms": float(np.sqrt(np.mean(r**2))),
                    "noise_estimate": self.noise_estimates()[name],
                }
                for name, r in self.series_residuals().items()
            },
            "record": problem.record.describe(),
            "runs": self.runs,
            "runs_by_stage": dict(self.runs_by_stage),
            "failed_runs": self.failed_runs,
            "speculative_runs_wasted": self.speculative_runs_wasted,
            "wall_time": self.wall_time,
            "device": self.device,
            "starts": [s.summary(names) for s in self.starts],
            "starts_converged": sum(s.converged for s in self.starts),
            "starts_reaching_best": sum(s.reached_best for s in self.starts),
            "fitted_run_status": self.trajectory.status,
            "rtol": problem.rtol,
            "atol": problem.atol,
            "profile": None if self.profile is None else self.profile.summary(),
            "profile_intervals": {i.name: i.summary() for i in self.intervals},
            "optimum_moved_by_profile": [
                {"from_cost": c, "to_cost": self.cost} for c in self.moved_by_profile
            ],
            **({} if checks is None else checks.summary()),
        }
