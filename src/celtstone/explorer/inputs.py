"""What the explorer's page asks for, validated by the same checks as ``celtstone run``.

The page holds an :class:`Inputs` (plain numbers and names, as typed); :func:`prepare`
turns it into the objects :func:`celtstone.simulate` takes, through ``model_from_name``,
``InitialState``, ``load_body`` and ``Design``: an out-of-range or contradictory input
raises the :class:`~celtstone.errors.ParameterError` the command line prints, and no run
starts. :func:`command_line` and :func:`python_snippet` spell the same run for the shell
and for Python.
"""

from __future__ import annotations

import shlex
import tempfile
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

from celtstone.bodies import Body, Design, load_body, load_design
from celtstone.errors import BodyFileError, ParameterError, require_choice
from celtstone.simulation import schema
from celtstone.simulation.models import (
    SETTINGS,
    InitialState,
    Model,
    model_from_name,
    setting_defaults,
)

__all__ = [
    "BODY_SOURCES",
    "DESIGN_BODY",
    "DESIGN_FIELDS",
    "KINDS",
    "Inputs",
    "Prepared",
    "body_from_file",
    "command_line",
    "design_defaults",
    "prepare",
    "python_snippet",
]

# the page's model choice -> (``model_from_name`` name, contact): stick-slip is the
# sliding model with the hybrid contact, as ``celtstone run --model sliding --contact hybrid``
KINDS: dict[str, tuple[str, str | None]] = {
    "rolling": ("rolling", None),
    "sliding": ("sliding", None),
    "hybrid": ("sliding", "hybrid"),
}
BODY_SOURCES = ("shipped", "file", "design")

# the design form starts at a shipped stone's measured design (its body file's [design])
DESIGN_BODY = "printed_stone_12cm"
DESIGN_FIELDS = ("length", "width", "height", "misalignment", "mass")


def design_defaults() -> dict[str, float]:
    """The design form's first values: :data:`DESIGN_BODY`'s ``[design]`` table."""
    design = load_design(DESIGN_BODY)
    assert design is not None  # the shipped file has one (tests/test_explore.py)
    return {name: float(getattr(design, name)) for name in DESIGN_FIELDS}


MAX_BODY_FILE_BYTES = 1 << 20  # a body file is a few hundred bytes; refuse a large upload


@dataclass(frozen=True)
class Inputs:
    """One state of the explorer's controls, unvalidated.

    Parameters
    ----------
    body_source : {"shipped", "file", "design"}
        Where the stone comes from.
    body : str
        Shipped body name (``celtstone bodies``), for ``body_source="shipped"``.
    body_file : bytes or None
        An uploaded body file's content, for ``body_source="file"``.
    body_file_name : str
        The uploaded file's name, shown in messages.
    design : dict of str to float
        ``Design`` keywords (length, width, height [m], misalignment [deg], mass [kg]).
    kind : {"rolling", "sliding", "hybrid"}
        The model; "hybrid" is the sliding model's stick-slip contact.
    omega : tuple of 3 float
        Initial angular velocity ω0 in body axes [rad/s].
    euler_angles : tuple of 2 float
        Initial Euler angles (α, β) [deg].
    t_end : float
        Duration [s].
    settings : dict of str to object
        Model settings by ``models.SETTINGS`` name; None (or a missing name) leaves the
        model's default.
    """

    body_source: str = "shipped"
    body: str = "kane_levinson_1982"
    body_file: bytes | None = field(default=None, repr=False)
    body_file_name: str = "body.toml"
    design: dict[str, float] = field(default_factory=design_defaults)
    kind: str = "rolling"
    omega: tuple[float, float, float] = (0.0, 0.0, -5.0)
    euler_angles: tuple[float, float] = (0.5, 0.5)
    t_end: float = 10.0
    settings: dict[str, Any] = field(default_factory=dict)

    def own_settings(self) -> dict[str, Any]:
        """The settings this kind of model has that differ from its defaults: what
        ``model_from_name`` and the command line are given."""
        kind = self.kind if self.kind in KINDS else "rolling"
        given = {}
        for name, value in self.settings.items():
            defaults = setting_defaults(name)
            if value is None or kind not in defaults:
                continue
            if value != defaults[kind]:
                given[name] = value
        return given


@dataclass(frozen=True)
class Prepared:
    """A validated run: what :func:`celtstone.simulate` takes."""

    model: Model
    body: Body
    initial_state: InitialState
    t_end: float


def body_from_file(content: bytes, file_name: str = "body.toml") -> Body:
    """Load an uploaded body file through ``load_body``'s checks.

    The bytes are written to a private temporary directory (the loader reads paths),
    read, and removed; nothing else is written.

    Parameters
    ----------
    content : bytes
        The file's content (TOML).
    file_name : str
        Its name on the user's machine; only its stem is kept (the body's name).

    Returns
    -------
    Body
    """
    if len(content) > MAX_BODY_FILE_BYTES:
        raise ParameterError(
            "body", file_name, f"a body file of at most {MAX_BODY_FILE_BYTES} bytes"
        )
    return _body_from_file(bytes(content), Path(file_name).name)


@lru_cache(maxsize=8)
def _body_from_file(content: bytes, file_name: str) -> Body:
    stem = Path(file_name).stem or "body"
    safe = "".join(c if c.isalnum() or c in "-_" else "_" for c in stem)[:64] or "body"
    with tempfile.TemporaryDirectory(prefix="celtstone-explore-") as folder:
        path = Path(folder) / f"{safe}.toml"
        path.write_bytes(content)
        try:
            return load_body(path)
        except ParameterError as error:
            # the command line's message for this file, naming the user's file instead
            # of the temporary copy
            error.args = (str(error).replace(str(path), file_name),)
            if isinstance(error, BodyFileError):
                error.file = file_name
            raise error from None


def _body(inputs: Inputs) -> Body:
    require_choice("body_source", inputs.body_source, BODY_SOURCES)
    if inputs.body_source == "shipped":
        return load_body(inputs.body)
    if inputs.body_source == "file":
        if inputs.body_file is None:
            raise ParameterError("body", None, "a body file (.toml) to upload")
        return body_from_file(inputs.body_file, inputs.body_file_name)
    return Design(**inputs.design).body("design")  # type: ignore[arg-type]


def prepare(inputs: Inputs) -> Prepared:
    """Validate ``inputs`` as ``celtstone run`` validates its options.

    Raises
    ------
    ParameterError
        The command line's one-line message, for the first input out of range.
    """
    require_choice("model", inputs.kind, KINDS)
    name, contact = KINDS[inputs.kind]
    for key in inputs.settings:
        require_choice("setting", key, SETTINGS)
    model = model_from_name(name, contact=contact, **inputs.own_settings())
    state = InitialState(omega=inputs.omega, euler_angles=inputs.euler_angles)
    t_end = schema.check("t_end", inputs.t_end)
    return Prepared(model=model, body=_body(inputs), initial_state=state, t_end=t_end)


def _number(value: float) -> str:
    return f"{value:g}"


def command_line(inputs: Inputs) -> str | None:
    """The ``celtstone run`` command of the same run; None for a design (the command line
    takes a body name or file, not the form's numbers: see :func:`python_snippet`)."""
    if inputs.body_source == "design":
        return None
    body = inputs.body if inputs.body_source == "shipped" else inputs.body_file_name
    name, contact = KINDS[inputs.kind]
    words = ["celtstone", "run", "--body", body, "--model", name]
    if contact is not None:
        words += ["--contact", contact]
    words += ["--omega", ",".join(_number(w) for w in inputs.omega)]
    words += ["--euler-angles", ",".join(_number(a) for a in inputs.euler_angles)]
    words += ["--t-end", _number(inputs.t_end)]
    for key, value in inputs.own_settings().items():
        words += [
            "--" + key.replace("_", "-"),
            _number(value) if isinstance(value, float) else str(value),
        ]
    return shlex.join(words)


def python_snippet(inputs: Inputs) -> str:
    """Python that reproduces the same run with the public API."""
    name, contact = KINDS[inputs.kind]
    settings = dict(inputs.own_settings())
    if contact is not None:
        settings = {"contact": contact, **settings}
    arguments = "".join(f", {key}={value!r}" for key, value in settings.items())
    if inputs.body_source == "shipped":
        body = f"cs.load_body({inputs.body!r})"
    elif inputs.body_source == "file":
        body = f"cs.load_body({inputs.body_file_name!r})"
    else:
        fields_ = ", ".join(f"{key}={value!r}" for key, value in inputs.design.items())
        body = f"cs.Design({fields_}).body()"
    return "\n".join(
        [
            "import celtstone as cs",
            "",
            f"body = {body}",
            f"model = cs.model_from_name({name!r}{arguments})",
            f"state = cs.InitialState(omega={tuple(inputs.omega)!r}, "
            f"euler_angles={tuple(inputs.euler_angles)!r})",
            f"run = cs.simulate(model, body, state, t_end={inputs.t_end!r})",
            "print(run.summary()['reversal_times'])",
        ]
    )
