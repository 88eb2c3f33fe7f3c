"""The method registry (``solvers.METHOD_ENTRIES``) is the one place a method is named:
the codes, the validation, the CLI's help, the driver's first-run compile and the GPU
sweep read it, and the compiled dispatch (``solvers/_dispatch.py``) is generated from
it. A method registered without its branch in the dispatch ends its run with
``unknown_code``; a throw-away method (a copy of Verner's pair under a new name and code,
in a package of the test's own) shows that its module, its entry and the generated
dispatch are all a method takes: the recipe of ``docs/architecture.md``, whose file count
is checked here."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import numpy as np
import pytest

import celtstone as cs
from celtstone import solvers
from celtstone.cli.main import build_parser
from celtstone.simulation.models import initial_vector, kernel_parameters
from celtstone.solvers import _generate, _vern9, batch_cuda, codes, driver
from tests.processes import python_in_new_process

ROOT = Path(__file__).resolve().parents[1]
THROWAWAY = codes.Method(code=99, words="a method with no module", module="nowhere")


def _help(command: str) -> str:
    parser = build_parser()
    (subparsers,) = (a for a in parser._actions if a.dest == "command")
    return " ".join(subparsers.choices[command].format_help().split())


def test_the_codes_are_the_registry_s() -> None:
    assert solvers.METHODS == {name: entry.code for name, entry in codes.METHOD_ENTRIES.items()}
    assert len(set(solvers.METHODS.values())) == len(solvers.METHODS)


@pytest.mark.parametrize("command", ["run", "sweep"])
def test_the_help_names_every_registered_method_with_its_words(
    monkeypatch: pytest.MonkeyPatch, command: str
) -> None:
    monkeypatch.setitem(codes.METHOD_ENTRIES, "throwaway", THROWAWAY)
    text = _help(command)
    for name, entry in codes.METHOD_ENTRIES.items():
        assert f"{name}: {entry.words}" in text, name


def test_a_registered_method_without_a_branch_ends_its_run_with_unknown_code(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setitem(codes.METHOD_ENTRIES, "throwaway", THROWAWAY)
    monkeypatch.setitem(codes.METHODS, "throwaway", THROWAWAY.code)
    model = cs.RollingModel()
    params = kernel_parameters(model, cs.load_body("kane_levinson_1982"))
    y0 = initial_vector(cs.InitialState(omega=(0.0, 0.0, -5.0)))
    raw = solvers.solve(
        model.code,
        "throwaway",
        params,
        y0,
        1.0,
        rtol=1e-8,
        atol=1e-10,
        sample_times=np.linspace(0.0, 1.0, 5),
    )
    assert solvers.Status(raw.status) == solvers.Status.UNKNOWN_CODE
    assert raw.t_stop == 0.0


def test_an_unregistered_method_is_refused_in_one_line() -> None:
    body = cs.load_body("kane_levinson_1982")
    with pytest.raises(cs.ParameterError, match="method") as refused:
        cs.simulate(cs.RollingModel(), body, cs.InitialState(omega=(0, 0, -5)), 1.0, method="rk4")
    assert "\n" not in str(refused.value)


def test_the_checked_in_dispatch_is_the_registry_s() -> None:
    """``solvers/_dispatch.py`` is what ``solvers._generate`` writes from the registry."""
    checked_in = _generate.TARGET.read_text(encoding="utf-8")
    assert checked_in == _generate.dispatch_source(codes.METHOD_ENTRIES), (
        f"solvers/_dispatch.py is not the method registry's: run `{_generate.COMMAND}`"
    )


def test_the_driver_and_the_gpu_read_the_registry_s_traits() -> None:
    entries = codes.METHOD_ENTRIES.items()
    assert driver.OWN_LOOP_METHODS == tuple(e.code for _, e in entries if e.own_loop)
    assert batch_cuda.CUDA_METHODS == {name: e.code for name, e in entries if e.gpu}


@pytest.mark.parametrize(
    ("change", "refusal"),
    [
        ({"toy": codes.Method(7, "", "toy_methods._toy")}, "codes must be 0 .. 4"),
        ({"toy-1": codes.Method(4, "", "toy_methods._toy")}, "not a Python identifier"),
        (
            {"toy": codes.Method(4, "", "toy_methods._toy", switches_among=("rk4",))},
            "'rk4' is not a registered stepping method",
        ),
        (
            {"toy": codes.Method(4, "", "toy_methods._toy", switches_among=("dop853",))},
            "one switching record",
        ),
    ],
)
def test_the_generator_refuses_a_registry_the_dispatch_cannot_serve(
    change: dict[str, codes.Method], refusal: str
) -> None:
    with pytest.raises(ValueError, match=re.escape(refusal)):
        _generate.dispatch_source({**codes.METHOD_ENTRIES, **change})


# --- the throw-away method -------------------------------------------------------------

TOY = "vern9_copy"
TOY_ENTRY = codes.Method(
    code=len(codes.METHOD_ENTRIES), words="Verner's pair again", module="toy_methods._toy"
)
T_END = 0.05  # [s]: a few steps, as Python (``NUMBA_DISABLE_JIT``)

# run in a new process as Python: ``solvers._dispatch`` is read from argv[1] (the file the
# command writes; none: the checked-in one), the toy's package from argv[2]; the entry is
# registered as a line of ``codes.py`` would register it
_RUN = f"""
import importlib.abc, importlib.util, json, sys

generated, package_root = sys.argv[1], sys.argv[2]


class Generated(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name == "celtstone.solvers._dispatch" and generated:
            return importlib.util.spec_from_file_location(name, generated)
        return None


sys.meta_path.insert(0, Generated())
sys.path.insert(0, package_root)
import numpy as np
import celtstone as cs
from celtstone import solvers
from celtstone.simulation.models import initial_vector, kernel_parameters
from celtstone.solvers import codes

codes.METHOD_ENTRIES[{TOY!r}] = codes.{TOY_ENTRY!r}
codes.METHODS[{TOY!r}] = {TOY_ENTRY.code}
model = cs.RollingModel()
params = kernel_parameters(model, cs.load_body("kane_levinson_1982"))
y0 = initial_vector(cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5)))
out = {{}}
for name in ("vern9", {TOY!r}):
    raw = solvers.solve(
        model.code, name, params, y0, {T_END}, rtol=1e-8, atol=1e-10,
        sample_times=np.linspace(0.0, {T_END}, 6),
    )
    out[name] = {{
        "status": raw.status, "t_stop": raw.t_stop, "samples": raw.samples.tolist(),
        "nfev": raw.nfev, "n_accepted": raw.n_accepted,
    }}
print(json.dumps(out))
"""


def _run_toy(tmp_path: Path, regenerated: bool) -> dict[str, dict[str, object]]:
    """The rolling runs of vern9 and the toy, as Python, in a new process; with
    ``regenerated``, on the dispatch generated from the registry with the toy's entry."""
    package = tmp_path / "toy_methods"
    package.mkdir(exist_ok=True)
    (package / "__init__.py").write_text("", encoding="utf-8")
    (package / "_toy.py").write_text(Path(_vern9.__file__).read_text(encoding="utf-8"))
    generated = ""
    if regenerated:
        source = _generate.dispatch_source({**codes.METHOD_ENTRIES, TOY: TOY_ENTRY})
        (tmp_path / "_dispatch.py").write_text(source, encoding="utf-8")
        generated = str(tmp_path / "_dispatch.py")
    environment = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=str(ROOT / "src"))
    lines = python_in_new_process(["-c", _RUN, generated, str(tmp_path)], environment, tmp_path)
    result: dict[str, dict[str, object]] = json.loads(lines[-1])
    return result


def test_a_method_is_its_module_its_entry_and_the_generated_dispatch(tmp_path: Path) -> None:
    """The toy, a copy of Verner's module registered under a new name and code, takes the
    same steps to the same numbers as Verner's pair once the dispatch is regenerated."""
    runs = _run_toy(tmp_path, regenerated=True)
    verner, toy = runs["vern9"], runs[TOY]
    assert verner["status"] == solvers.STATUS_SUCCESS
    assert verner["t_stop"] == T_END
    assert int(verner["n_accepted"]) > 1  # type: ignore[call-overload]
    assert toy == verner


def test_a_method_left_out_of_the_dispatch_ends_its_run_with_unknown_code(
    tmp_path: Path,
) -> None:
    """Registered but the dispatch not regenerated: the toy's run stops where it starts,
    with ``unknown_code``, never with another method's numbers."""
    runs = _run_toy(tmp_path, regenerated=False)
    assert runs["vern9"]["status"] == solvers.STATUS_SUCCESS
    assert runs[TOY]["status"] == solvers.STATUS_UNKNOWN_CODE
    assert runs[TOY]["t_stop"] == 0.0


# --- what it takes: the recipe of docs/architecture.md --------------------------------


def test_the_recipe_names_the_module_the_registry_and_the_generated_dispatch() -> None:
    """The recipe's steps are the method's module, ``codes.py`` (its code and entry) and
    the dispatch the command regenerates, which it names."""
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    section = re.search(
        r"^## Adding an integration method \((\d+) files\b[^)]*\)\n(.*?)^## ", text, re.M | re.S
    )
    assert section is not None, "docs/architecture.md has the integration-method recipe"
    steps = re.findall(r"^\d+\. `([^`]+)`", section.group(2), re.M)
    assert int(section.group(1)) == len(steps) == 3
    assert steps == ["solvers/_<name>.py", "solvers/codes.py", "solvers/_dispatch.py"]
    assert _generate.COMMAND in section.group(2)
