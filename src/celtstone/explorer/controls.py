"""The explorer's controls made from the declarations: a model setting's control from
its ``models.SETTINGS`` row, its label from ``schema.PARAMETERS``, its tooltip from the
words of ``celtstone run --help``; and the design form's sliders."""

from __future__ import annotations

from typing import Any

import panel as pn

from celtstone.simulation import schema
from celtstone.simulation.models import SETTINGS, setting_defaults

__all__ = ["DESIGN_LABELS", "DESIGN_TRAVEL", "noted", "parameter_label", "setting_widget"]


def parameter_label(name: str) -> str:
    """A control's label from ``schema.PARAMETERS``: "symbol: description [unit]"."""
    quantity = schema.PARAMETERS[name]
    unit = f" [{quantity.unit}]" if quantity.unit else ""
    return f"{quantity.symbol}: {quantity.description}{unit}"


def setting_widget(name: str) -> Any:
    """A control of model setting ``name``, from its ``models.SETTINGS`` row; its help
    text (unit, range, meaning: the CLI's ``--help``) is the control's tooltip."""
    setting = SETTINGS[name]
    default = next(iter(setting_defaults(name).values()))
    words = setting.help()
    if setting.choices is not None:
        return pn.widgets.Select(
            label=name.replace("_", " "),
            options=list(setting.choices),
            value=default,
            description=words,
        )
    if name == "friction_coefficient":  # the slider of the paper's Figure 2 (f = 0.35, 0.15)
        return pn.widgets.EditableFloatSlider(
            label=parameter_label(name),
            start=0.0,
            end=1.0,
            step=0.01,
            value=default,
            css_classes=[f"cs-{name}"],
        )
    return pn.widgets.FloatInput(
        label=parameter_label(name),
        value=default,
        format="0[.]000000",
        css_classes=[f"cs-{name}"],
        description=words,
    )


def noted(widget: Any, words: str) -> Any:
    """``widget`` with ``words`` as its tooltip: its own where it has one, else an icon
    beside it (sliders have none)."""
    if "description" in widget.param:
        return widget
    return pn.Row(widget, pn.widgets.TooltipIcon(value=words), sizing_mode="stretch_width")


# the design sliders' travel [m, m, m, deg, kg]: where a student drags, not what is
# allowed; a typed number beyond it is checked by ``Design`` as any other
DESIGN_TRAVEL: dict[str, tuple[float, float, float]] = {
    "length": (0.02, 0.4, 0.001),
    "width": (0.005, 0.1, 0.0005),
    "height": (0.002, 0.05, 0.0005),
    "misalignment": (-44.0, 44.0, 0.5),
    "mass": (0.002, 1.0, 0.001),
}
DESIGN_LABELS = {
    "length": "length L = 2a [m]",
    "width": "width W = 2b [m]",
    "height": "height H = c [m]",
    "misalignment": "misalignment δ [deg]",
    "mass": "mass m [kg]",
}
