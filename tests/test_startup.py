"""A command imports only what it does: ``celtstone --help``, every ``COMMAND --help`` and
``import celtstone`` import none of the heavy libraries, and a run asked for JSON imports
no plotting, storage or table library (issue 17, item 1). Each of those cases runs in a
fresh interpreter, the only place where "was it imported" has an answer. A first run that
compiles the kernels says so at a terminal."""

from __future__ import annotations

import io
import json
import subprocess
import sys

import numba
import pytest

from celtstone.cli.main import SUBCOMMANDS
from celtstone.kernels import _jit

# never needed to print help or a JSON summary; each costs 0.1 to 0.6 s to import
PLOTTING_AND_STORAGE = ("matplotlib", "dask", "distributed", "zarr", "imageio", "xarray", "pandas")
# the engine and SciPy's slow modules: not needed to print help either
ENGINE = ("numba", "scipy.integrate", "scipy.optimize")


def _imported_after(code: str) -> list[str]:
    """The modules of PLOTTING_AND_STORAGE and ENGINE imported by ``code`` in a new process."""
    watched = PLOTTING_AND_STORAGE + ENGINE
    script = (
        "import contextlib, io, json, sys\n"
        f"with contextlib.redirect_stdout(io.StringIO()):\n{code}\n"
        f"print(json.dumps([m for m in {watched!r} if m in sys.modules]))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=300, check=True
    )
    return list(json.loads(done.stdout.splitlines()[-1]))


def _main(*arguments: str) -> str:
    return (
        "    from celtstone.cli.main import main\n"
        "    try:\n"
        f"        main({list(arguments)!r})\n"
        "    except SystemExit:\n"
        "        pass"
    )


def test_import_celtstone_is_light() -> None:
    assert _imported_after("    import celtstone") == []


def test_top_level_help_imports_nothing_heavy() -> None:
    assert _imported_after(_main("--help")) == []


@pytest.mark.parametrize("command", list(SUBCOMMANDS))
def test_command_help_imports_no_plotting_or_storage(command: str) -> None:
    imported = _imported_after(_main(command, "--help"))
    assert not set(imported) & set(PLOTTING_AND_STORAGE), imported
    assert "scipy.integrate" not in imported and "scipy.optimize" not in imported, imported


def test_json_run_imports_no_plotting_or_storage() -> None:
    imported = _imported_after(_main("run", "--t-end", "0.01", "--json"))
    assert "numba" in imported  # it did run
    assert not set(imported) & set(PLOTTING_AND_STORAGE), imported
    assert "scipy.integrate" not in imported and "scipy.optimize" not in imported, imported


def test_dataset_is_built_on_first_use_and_kept() -> None:
    import celtstone as cs

    run = cs.simulate(
        cs.RollingModel(),
        cs.load_body("kane_levinson_1982"),
        cs.InitialState((0.0, 0.0, -5.0), (0.5, 0.5)),
        0.05,
    )
    summary = run.summary()
    dataset = run.dataset
    assert run.dataset is dataset
    assert summary["spin_final"] == float(dataset["spin"].values[-1])
    assert dataset["spin"].attrs["units"] == "rad/s"
    assert list(dataset["quaternion"].dims) == ["time", "component"]


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _compile_probe(module: str) -> None:
    """Compile a new one-line function as if defined in ``module`` (a cache miss)."""

    def probe(x: float) -> float:
        return 2.0 * x

    probe.__module__ = module
    numba.njit(probe)(1.0)


@pytest.mark.parametrize("terminal", [True, False], ids=["terminal", "captured"])
def test_the_first_compilation_says_so_once_on_a_terminal(
    monkeypatch: pytest.MonkeyPatch, terminal: bool
) -> None:
    """A first run that compiles for minutes says why in one line, on a terminal only,
    once per process, and only for celtstone's own kernels (not a user's shape)."""
    stream = _Terminal() if terminal else io.StringIO()
    monkeypatch.setattr(sys, "stderr", stream)
    monkeypatch.setattr(_jit.COMPILING, "shown", False)
    _compile_probe("my_shapes")
    assert stream.getvalue() == ""
    _compile_probe("celtstone.kernels.probe")
    _compile_probe("celtstone.solvers.probe")
    assert stream.getvalue() == (_jit.COMPILING_NOTICE + "\n" if terminal else "")
    assert _jit.COMPILING.shown
