"""A fit at a glance: each measured series with the fitted model against time, and the
residuals beneath it; the fitted values with their uncertainties in the title."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from celtstone.plotting.labels import axis_label, title_characters, wrapped_title
from celtstone.plotting.legible import make_legible

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["FitPanel", "FittedValue", "fit_title", "plot_fit"]

_SEPARATOR = ",   "
_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


@dataclass(frozen=True)
class FitPanel:
    """One series of a fit, as drawn.

    Parameters
    ----------
    label : str
        The series' name with its plotted unit.
    measured : numpy.ndarray
        Measured values in that unit, shape (m,).
    fitted : numpy.ndarray
        Fitted model's values in that unit, shape (m,).
    """

    label: str
    measured: np.ndarray
    fitted: np.ndarray


@dataclass(frozen=True)
class FittedValue:
    """A fitted number as the title shows it: ``friction_coefficient = 0.351 ± 0.002``.

    Parameters
    ----------
    name : str
        The free number's name.
    value : float
        Its best value [unit].
    standard_error : float
        Its standard error [unit]; inf or NaN where the data do not determine it.
    unit : str, optional
        Its unit ("" or "1": none).
    """

    name: str
    value: float
    standard_error: float
    unit: str = ""

    def words(self) -> str:
        """The value in words: ``"name = value ± error unit"``.

        Returns
        -------
        str
            The error to two significant digits and the value to the same decimal place.
        """
        unit = f" {self.unit}" if self.unit not in ("", "1") else ""
        return f"{self.name} = {value_with_error(self.value, self.standard_error)}{unit}"


def value_with_error(value: float, error: float) -> str:
    """``"0.3512 ± 0.0021"`` or ``"(1.010 ± 0.021)×10⁻³"``: the error rounded to two
    significant digits, the value to the same place; an undetermined error (inf, NaN)
    is said in words, a zero error leaves the value at four significant digits."""
    if not math.isfinite(value):
        return str(value)
    if not math.isfinite(error) or error < 0.0:
        return f"{value:.4g} (undetermined)"
    if error == 0.0:
        return f"{value:.4g} ± 0"
    place = math.floor(math.log10(error)) - 1  # of the error's second digit
    size = max(abs(value), error)
    power = math.floor(math.log10(size))
    if -3 <= power < 5:
        decimals = max(0, -place)
        return f"{value:.{decimals}f} ± {error:.{decimals}f}"
    decimals = max(0, power - place)
    scale = 10.0**power
    factor = f"×10{str(power).translate(_SUPERSCRIPT)}"
    return f"({value / scale:.{decimals}f} ± {error / scale:.{decimals}f}){factor}"


def fit_title(subject: str, values: Sequence[FittedValue], width: float) -> str:
    """``subject`` on its own line(s), then the fitted values, as many to a line as fit
    ``width`` [inch] at the figure title's size: a line breaks between two values,
    never inside one."""
    lines = wrapped_title(subject, width).splitlines() if subject else []
    characters = title_characters(width)
    current = ""
    for item in (value.words() for value in values):
        joined = f"{current}{_SEPARATOR}{item}" if current else item
        if current and len(joined) > characters:
            lines.append(current)
            joined = item
        current = joined
    if current:
        lines.append(current)
    return "\n".join(lines)


def plot_fit(
    times: np.ndarray,
    panels: Sequence[FitPanel],
    title: str = "",
    values: Sequence[FittedValue] = (),
) -> Figure:
    """Draw data (dots) and fitted model (line) against time, residuals beneath each series.

    Parameters
    ----------
    times : numpy.ndarray
        Sample times [s], shape (m,).
    panels : sequence of FitPanel
        The series, one panel each; residuals are model − data.
    title : str, optional
        What was fitted (the body, the model), the title's first line.
    values : sequence of FittedValue, optional
        The fitted numbers with their uncertainties, written under ``title``.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(10.0, 1.0 + 3.6 * len(panels)), layout="constrained")
    ratios = [3, 1] * len(panels)
    grid = figure.subplots(2 * len(panels), 1, sharex=True, height_ratios=ratios, squeeze=False)
    for index, panel in enumerate(panels):
        measured, residual = grid[2 * index, 0], grid[2 * index + 1, 0]
        measured.plot(times, panel.measured, ".", markersize=2.0, color="0.5", label="data")
        measured.plot(times, panel.fitted, color="tab:blue", linewidth=1.2, label="fitted model")
        measured.set_ylabel(panel.label)
        measured.legend(fontsize="small")
        residual.plot(times, panel.fitted - panel.measured, ".", markersize=2.0, color="tab:red")
        residual.axhline(0.0, color="black", linewidth=0.5)
        residual.set_ylabel("model − data")
        for axes in (measured, residual):
            axes.grid(alpha=0.3)
    grid[-1, 0].set_xlabel(axis_label("time"))
    if title or values:
        figure.suptitle(fit_title(title, values, figure.get_figwidth()))
    return make_legible(figure)
