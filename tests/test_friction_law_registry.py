"""One registry entry per friction law (``contact.LAWS``) and one compiled dispatch
(``kernels.friction.law_functions``) drive every place a law is chosen.

Oracles: each law's closed forms against its own functions (the Padé disk law and stick
limit are paper eq. 10 written out; the limit set is the bisection of the functions),
the disk law of radius A as the elliptic contact with A = B, and a throw-away law of this
file whose limit set is known in closed form (F̂ = u/(1 + u), M̂ = M0/(1 + u) give
μ = 1 − φ). The throw-away law shows what an entry alone gives (names, help, models),
what fails until its kernel branch exists (``unknown_code`` on the disk, the ellipse and
in stick), and, with the kernels run as Python, that the branch in ``law_functions`` is
all the compiled side needs: the recipe of ``docs/architecture.md``, whose file count
is checked here.
"""

from __future__ import annotations

import inspect
import json
import math
import os
import re
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import celtstone as cs
from celtstone import ParameterError
from celtstone.cli.main import build_parser, main
from celtstone.contact import FRICTION_LAWS, LAW_WORDS, LAWS, FrictionLawEntry, choice_words
from celtstone.contact.laws import friction_functions
from celtstone.kernels import friction, friction_ellipse, layout, stick, stick_ellipse, system
from celtstone.kernels.layout import ContactPressure, FrictionLaw, ModelCode
from celtstone.plotting.friction import friction_law_figure
from celtstone.simulation.models import kernel_parameters

TABLE = friction_ellipse.TABLE_ADDRESS  # the elliptic law's table in this process

ROOT = Path(__file__).resolve().parents[1]
PRESSURES = [pressure.value for pressure in ContactPressure]
SPEEDS = [(0.0, 1.0), (1e-3, 1.0), (0.5, 1.0), (1.0, 1.0), (1.0, 0.5), (1.0, 1e-3), (1.0, 0.0)]
SLIPS = [((1e-3, -2e-3, 0.0), 2.0), ((0.3, 0.1, 0.0), -0.5), ((0.0, 0.0, 0.0), 1.0)]
THROWAWAY_CODE = len(FrictionLaw)  # the next code, which no compiled branch has
KL = cs.load_body("kane_levinson_1982")
START = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
ELLIPSE = {"contact_shape": "ellipse", "elastic_modulus": 3e9, "poisson_ratio": 0.35}


def linear_functions(slip_speed: float, pivot_speed: float, pressure: int) -> tuple[float, float]:
    """The throw-away law: F/(fN) = u/(1 + u), M/(fNε) = M0/(1 + u), u = slip/pivot."""
    if slip_speed == 0.0 and pivot_speed == 0.0:
        return 0.0, 0.0
    total = slip_speed + pivot_speed
    return slip_speed / total, friction.zero_slip_moment(pressure) * pivot_speed / total


THROWAWAY = FrictionLawEntry(
    "throwaway",
    THROWAWAY_CODE,
    "a law of tests/test_friction_law_registry.py",
    "throw-away",
    linear_functions,
)


@pytest.fixture
def throwaway(monkeypatch: pytest.MonkeyPatch) -> Iterator[FrictionLawEntry]:
    """The throw-away law registered in ``contact.LAWS`` for one test."""
    monkeypatch.setitem(LAWS, THROWAWAY.name, THROWAWAY)
    yield THROWAWAY


# --- the registry is the kernels' laws --------------------------------------------------


def test_the_registry_has_every_kernel_code_once() -> None:
    codes = [entry.code for entry in LAWS.values()]
    assert sorted(codes) == sorted(law.value for law in FrictionLaw)
    assert all(name == entry.name for name, entry in LAWS.items())
    assert dict(FRICTION_LAWS) == {name: entry.code for name, entry in LAWS.items()}
    assert dict(LAW_WORDS) == {name: entry.words for name, entry in LAWS.items()}


@pytest.mark.parametrize("name", list(LAWS))
def test_the_dispatch_calls_the_entrys_functions(name: str) -> None:
    """``law_functions`` returns, bit for bit, the kernel the entry names."""
    entry = LAWS[name]
    assert friction.has_friction_law(entry.code)
    for pressure in PRESSURES:
        for slip_speed, pivot_speed in SPEEDS:
            dispatched = friction.law_functions(entry.code, slip_speed, pivot_speed, pressure)
            assert dispatched == entry.functions(slip_speed, pivot_speed, pressure)


def _disk_law(
    entry: FrictionLawEntry,
    slip: tuple[float, float, float],
    spin: float,
    radius: float,
    delta: float,
    pressure: int,
) -> tuple[np.ndarray, float]:
    """The oracle: F/(fN) = −F̂(u) V1/|V1| and M/(fN) = −ε M̂(u) sign Ω_n (paper section 2)
    from the entry's functions, |V1| regularised as sqrt(|V1|² + δ²), in NumPy."""
    velocity = np.asarray(slip)
    speed = math.hypot(*slip, delta)
    force_ratio, moment_ratio = entry.functions(speed, radius * abs(spin), pressure)
    force = -force_ratio * velocity / speed if speed > 0.0 else np.zeros(3)
    return force, -math.copysign(moment_ratio * radius, spin) if spin != 0.0 else 0.0


@pytest.mark.parametrize("name", list(LAWS))
def test_the_disk_law_is_the_entrys_and_its_functions(name: str) -> None:
    """``contact_friction`` takes the entry's closed form where it names one (bit for
    bit), and agrees to rounding with the force and moment of its functions."""
    entry = LAWS[name]
    for pressure in PRESSURES:
        for slip, spin in SLIPS:
            args = (slip, spin, 1e-3, 1e-9)
            dispatched = friction.contact_friction(*args, entry.code, pressure)
            if entry.disk is not None:
                assert dispatched == entry.disk(*args, pressure)
            force, moment = _disk_law(entry, *args, pressure)
            np.testing.assert_allclose(dispatched[0], force, rtol=1e-13, atol=1e-300)
            assert dispatched[1] == pytest.approx(moment, rel=1e-13)


@pytest.mark.parametrize("name", list(LAWS))
def test_the_stick_limit_is_the_entrys_and_its_functions(name: str) -> None:
    """``limit_moment`` takes the entry's closed form where it names one, else the
    bisection of its functions; the two agree (the bisection's own error is 1e-17 in t)."""
    entry = LAWS[name]
    for pressure in PRESSURES:
        for force_ratio in (0.0, 1e-3, 0.3, 0.7, 0.999, 1.0):
            dispatched = stick.limit_moment(force_ratio, entry.code, pressure)
            bisected = stick.bisected_limit_moment(force_ratio, entry.code, pressure)
            named = entry.stick_limit(force_ratio, pressure) if entry.stick_limit else bisected
            assert dispatched == named
            assert dispatched == pytest.approx(bisected, rel=1e-12, abs=1e-14)


@pytest.mark.parametrize("name", list(LAWS))
def test_the_elliptic_contact_corrects_the_entrys_disk_law(name: str) -> None:
    """A = B is the disk law of the Hertz pressure itself; A > B is that law corrected."""
    code = LAWS[name].code
    normal, axis = (0.0, 0.0, 1.0), (1.0, 0.0, 0.0)
    hertz = ContactPressure.HERTZ.value
    for slip, spin in SLIPS:
        disk = friction.contact_friction(slip, spin, 2e-3, 1e-9, code, hertz)
        circle = friction_ellipse.elliptic_contact_friction(
            slip, spin, normal, axis, 2e-3, 2e-3, 1e-9, code, TABLE
        )
        assert circle == disk
        ellipse = friction_ellipse.elliptic_contact_friction(
            slip, spin, normal, axis, 2e-3, 5e-4, 1e-9, code, TABLE
        )
        corrected = friction_ellipse.elliptic_correction(
            *disk, slip, spin, normal, axis, 2e-3, 5e-4, TABLE
        )
        assert ellipse == corrected


def test_the_help_texts_plot_and_cli_list_every_law() -> None:
    words = choice_words(LAW_WORDS)
    friction_command = _subcommand("friction")
    law_help = next(a.help for a in friction_command._actions if a.dest == "law")
    assert law_help == words
    ellipse_help = next(a.help for a in friction_command._actions if a.dest == "ellipse")
    figure = friction_law_figure("hertz")
    legend = [text.get_text() for text in figure.axes[0].get_legend().get_texts()]
    for name, entry in LAWS.items():
        assert f"{name} ({entry.words})" in words
        assert name in str(ellipse_help)
    assert legend == [entry.label for entry in LAWS.values()]


def _subcommand(name: str):  # type: ignore[no-untyped-def]
    parser = build_parser()
    commands = next(a for a in parser._actions if a.dest == "command")
    return commands.choices[name]  # type: ignore[index]


# --- a throw-away law: what the entry gives, and what fails without its kernel branch --


def test_an_entry_alone_names_the_law_everywhere(throwaway: FrictionLawEntry) -> None:
    assert FRICTION_LAWS["throwaway"] == THROWAWAY_CODE
    assert "throwaway (a law of tests/" in choice_words(LAW_WORDS)
    friction_command = _subcommand("friction")
    assert "throwaway" in next(a.help for a in friction_command._actions if a.dest == "law")
    record = kernel_parameters(cs.SlidingModel(friction_law="throwaway"), KL)
    assert record.friction_law == THROWAWAY_CODE


def test_without_its_kernel_branch_the_kernels_give_nan(throwaway: FrictionLawEntry) -> None:
    code = throwaway.code
    hertz = ContactPressure.HERTZ.value
    assert not friction.has_friction_law(code)
    assert all(math.isnan(x) for x in friction.law_functions(code, 1.0, 1.0, hertz))
    force, moment = friction.contact_friction((1e-3, 0.0, 0.0), 2.0, 1e-3, 0.0, code, hertz)
    assert all(math.isnan(x) for x in (*force, moment))
    force, moment = friction_ellipse.elliptic_contact_friction(
        (1e-3, 0.0, 0.0), 2.0, (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), 2e-3, 5e-4, 0.0, code, TABLE
    )
    assert all(math.isnan(x) for x in (*force, moment))
    assert math.isnan(stick.limit_moment(0.0, code, hertz))
    assert math.isnan(stick.stick_margin_of(0.0, 0.0, 9.81, 0.3, 1e-3, code, hertz))
    # the elliptic stick margin says "no stick" (-1) where its law has no value
    margin = stick_ellipse.elliptic_stick_margin(
        (0.0, 0.0, 0.0), 0.0, (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), 2e-3, 5e-4, 1.0, code, TABLE
    )
    assert margin == -1.0


@pytest.mark.parametrize(
    ("kind", "settings"),
    [
        (cs.SlidingModel, {}),
        (cs.SlidingModel, {"friction_load": "dynamic", **ELLIPSE}),
        (cs.HybridModel, {"friction_load": "dynamic", **ELLIPSE}),
    ],
    ids=["sliding-disk", "sliding-ellipse", "stick-slip-ellipse"],
)
def test_without_its_kernel_branch_a_run_stops_with_unknown_code(
    throwaway: FrictionLawEntry, kind: type[cs.SlidingModel], settings: dict[str, object]
) -> None:
    model = kind(friction_law="throwaway", **settings)  # type: ignore[arg-type]
    run = cs.simulate(model, KL, START, 1.0)
    assert run.status == "unknown_code"
    assert run.dataset.attrs["friction_law"] == "throwaway"


def test_an_enum_member_without_its_branch_is_an_unknown_code(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Were the code a member of ``FrictionLaw`` (the range check passes), the missing
    branch in ``law_functions`` still makes it ``RHS_UNKNOWN_CODE`` for the models that
    read a law (``system.code_status``, run here as Python with the longer enum)."""
    monkeypatch.setattr(system, "N_FRICTION_LAWS", THROWAWAY_CODE + 1)
    params = kernel_parameters(cs.SlidingModel(), KL).copy()
    params["friction_law"] = THROWAWAY_CODE
    code_status = system.code_status.py_func
    for model in (ModelCode.SLIDING, ModelCode.STICK):
        assert code_status(model.value, params) == layout.RHS_UNKNOWN_CODE
    assert code_status(ModelCode.ROLLING.value, params) == layout.RHS_OK
    params["friction_law"] = FrictionLaw.EXACT.value
    assert code_status(ModelCode.SLIDING.value, params) == layout.RHS_OK


@pytest.mark.parametrize(
    "arguments",
    [
        ["friction", "--law", "throwaway"],
        ["friction", "--law", "throwaway", "--ellipse", "2e-3,5e-4"],
        ["friction", "--law", "throwaway", "--ellipse", "2e-3,2e-3", "--json"],
    ],
    ids=["disk", "ellipse", "circle-as-ellipse"],
)
def test_without_its_kernel_branch_the_friction_command_refuses_it(
    throwaway: FrictionLawEntry, arguments: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    """One line naming the law and the missing branch, exit status 2; never another
    law's numbers under its name."""
    assert main(arguments) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    (line,) = captured.err.strip().splitlines()
    assert "friction_law" in line and "'throwaway'" in line and "unknown_code" in line
    with pytest.raises(ParameterError, match="law_functions"):
        friction_functions([1.0], "throwaway")
    with pytest.raises(ParameterError, match="law_functions"):
        friction_law_figure("hertz")


# --- what it takes: the recipe of docs/architecture.md ----------------------------------


def _recipe() -> tuple[int, list[str]]:
    """The file count in the heading of the friction-law recipe and its numbered files."""
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    section = re.search(
        r"^## Adding a friction law \((\d+) files\)\n(.*?)(?=^## )", text, re.M | re.S
    )
    assert section is not None, "docs/architecture.md has the friction-law recipe"
    files = re.findall(r"^\d+\. `([^`]+)`", section.group(2), re.M)
    return int(section.group(1)), files


def test_the_recipe_counts_its_files() -> None:
    count, files = _recipe()
    assert count == len(files) == len(set(files))
    assert files == ["kernels/layout.py", "kernels/friction.py", "contact/laws.py"]
    for path in files:
        assert (ROOT / "src" / "celtstone" / path).is_file(), path


def test_the_dispatch_has_one_branch_per_code() -> None:
    """``law_functions`` is the one dispatch on a law code: a branch per member."""
    source = inspect.getsource(friction.law_functions.py_func)
    branches = re.findall(r"if law == FrictionLaw\.(\w+):", source)
    assert sorted(branches) == sorted(law.name for law in FrictionLaw)


# run with the kernels as Python: the throw-away law's branch in law_functions (and its
# code in the enum's count), nothing else, and every place a law is chosen computes it
_WITH_ITS_BRANCH = """
import json, math, sys
sys.path.insert(0, {tests!r})
from test_friction_law_registry import THROWAWAY, linear_functions
from celtstone.cli.main import main
from celtstone.contact import LAWS
from celtstone.kernels import friction, stick, system
from celtstone.kernels.layout import ContactPressure

LAWS[THROWAWAY.name] = THROWAWAY
dispatch = friction.law_functions


def law_functions(law, slip_speed, pivot_speed, pressure):
    if law == THROWAWAY.code:
        return linear_functions(slip_speed, pivot_speed, pressure)
    return dispatch(law, slip_speed, pivot_speed, pressure)


friction.law_functions = stick.law_functions = law_functions
system.N_FRICTION_LAWS += 1
hertz = ContactPressure.HERTZ.value
out = {{
    "limit": [stick.limit_moment(phi, THROWAWAY.code, hertz) for phi in (0.0, 0.25, 0.5, 0.9)],
    "has_law": friction.has_friction_law(THROWAWAY.code),
}}
print(json.dumps(out))
sys.exit(main(["friction", "--law", "throwaway", "--u", "1", "--ellipse", "2e-3,2e-3", "--json"]))
"""


def test_with_its_branch_in_law_functions_every_place_computes_the_law(tmp_path: Path) -> None:
    """The recipe's compiled step, run as Python (``NUMBA_DISABLE_JIT``): the stick limit
    follows (μ = 1 − φ for this law) and ``celtstone friction --ellipse`` prints the law
    (A = B: the disk's F̂(1) = 1/2, M̂(1) = M0/2 = 3π/32)."""
    code = _WITH_ITS_BRANCH.format(tests=str(ROOT / "tests"))
    environment = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=str(ROOT / "src"))
    # imported here: the step's code imports this module in a process without ``tests``
    from tests.processes import python_in_new_process

    lines = python_in_new_process(["-c", code], environment, tmp_path)
    first, second = (json.loads(line) for line in lines[-2:])
    assert first["has_law"] is True
    assert first["limit"] == pytest.approx([1.0, 0.75, 0.5, 0.1], rel=1e-12)
    assert second["force"] == pytest.approx([0.5], rel=1e-14)
    assert second["moment"] == pytest.approx([3.0 * math.pi / 32.0], rel=1e-14)
