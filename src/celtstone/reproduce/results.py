"""Reading back the numbers of earlier targets (``out/data/*.json``) for the report.

``out/data`` is a folder a user may put files in: a JSON file that is not a target's
result (any content: a list, a number, text that is not JSON, a folder named ``x.json``)
is left out of the report with a one-line warning, never a traceback.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path
from typing import Any

from celtstone.errors import CeltstoneWarning
from celtstone.reproduce.study import TARGETS
from celtstone.simulation.outcome import current_outcomes

__all__ = ["RESULT_TARGETS", "read_result"]

RESULT_TARGETS = (*TARGETS, "atlas")  # the targets that write out/data/TARGET_KEY.json
# what the report reads of every result, whatever its target
_TEXT_FIELDS = ("target", "body", "study")


def _why_not_a_result(result: Any) -> str | None:
    """Why ``result`` (parsed JSON) is not a target's result, or None if it is one."""
    if not isinstance(result, dict):
        return f"it holds a {type(result).__name__}, not a target's result"
    if result.get("target") not in RESULT_TARGETS:
        return f"its target is not one of {', '.join(RESULT_TARGETS)}"
    for field in _TEXT_FIELDS:
        if not isinstance(result.get(field), str):
            return f"it has no {field} in words"
    if "key" in result and not isinstance(result["key"], str):
        return "its key is not text"
    t_end = result.get("t_end")
    if isinstance(t_end, bool) or not isinstance(t_end, int | float) or not math.isfinite(t_end):
        return "it has no finite t_end"
    if not isinstance(result.get("cases", []), list):
        return "its cases are not a list"
    return None


def read_result(path: Path) -> dict[str, Any] | None:
    """The result in ``path``, or None (with a :class:`CeltstoneWarning`) if the file is
    not one a target wrote; its cases' outcomes under their names now
    (``outcome.RENAMED_OUTCOMES``)."""
    try:
        result = json.loads(path.read_text(encoding="utf-8"))
        why = _why_not_a_result(result)
    except (OSError, UnicodeDecodeError, ValueError, RecursionError) as error:
        why = f"it cannot be read as JSON ({type(error).__name__})"
    if why is not None:
        warnings.warn(f"{path} is left out of the report: {why}", CeltstoneWarning, stacklevel=2)
        return None
    if "cases" in result:  # a result written before the outcomes' renames: the names now
        result["cases"] = [
            c if not isinstance(c, dict) else current_outcomes(c) for c in result["cases"]
        ]
    return result
