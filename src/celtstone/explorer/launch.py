"""Opening the explorer: in a notebook (:func:`explore`), and the check that Panel (the
``explore`` extra) is installed, which ``celtstone serve`` makes first."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from celtstone.explorer.inputs import Inputs

if TYPE_CHECKING:
    from celtstone.explorer.app import Explorer

__all__ = ["EXTRA_HINT", "explore", "require_panel"]

EXTRA_HINT = "install the explorer's extra: pip install 'celtstone[explore]'"


def require_panel() -> None:
    """Raise ``ParameterError`` naming the extra to install when Panel is missing."""
    import importlib.util

    from celtstone.errors import ParameterError

    if importlib.util.find_spec("panel") is None:
        raise ParameterError("explore", "panel", "Panel installed (it is not)", EXTRA_HINT)


def explore(**inputs: Any) -> Explorer:
    """The live explorer, shown inline when it is a notebook cell's value.

    Parameters
    ----------
    **inputs
        First values of the controls, as :class:`Inputs`' fields (``kind="sliding"``,
        ``settings={"friction_coefficient": 0.15}``, ``t_end=20.0``, ...).

    Returns
    -------
    Explorer
        Its ``layout`` is the Panel object; ``servable()`` serves it with ``panel serve``.

    Raises
    ------
    ParameterError
        When Panel is not installed (the ``explore`` extra), or for a first input out of
        range.
    """
    require_panel()
    import panel as pn

    from celtstone.explorer.app import Explorer

    pn.extension()  # a notebook shows Panel objects only once its extension is loaded

    first = Inputs(**inputs)
    return Explorer(first)
