"""Shared fixtures: the shipped bodies and the literature's initial states."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import matplotlib
import pytest
from hypothesis import settings

import celtstone as cs

matplotlib.use("Agg")

settings.register_profile("ci", max_examples=30, deadline=None, derandomize=True)
settings.register_profile("dev", max_examples=10, deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")

BODY_NAMES = sorted(cs.list_bodies())


#: The longest single tests of ``make test`` (CPU on a fresh clone, where the first ones
#: compile what ``celtstone compile`` does not), longest first, by node ID up to the
#: parameters. ``--dist loadgroup`` hands each worker the groups first (the largest
#: first), then the other tests one by one in collection order: these go to the front
#: of those, so that no long test starts last and keeps one worker busy while the other
#: has nothing left. ``tests/test_xdist_groups.py`` checks that each names a test.
STARTED_FIRST = (
    "tests/test_sweep_cuda.py::test_benchmark_stages_run_and_agree_in_the_simulator",
    "tests/test_sweep_cuda.py::test_gpu_thread_gives_the_cpu_sweeps_fields_in_the_simulator",
    "tests/test_atlas_fields.py::test_the_atlas_equals_a_reproduction_of_the_same_body",
    "tests/test_fit.py::test_synthetic_recovery_within_the_standard_errors",
    "tests/test_sweep_dask.py::test_local_cluster_equals_local_threads",
    "tests/test_solvers.py::test_agrees_with_scipy_on_the_same_right_hand_side",
    "tests/e2e/test_explore_browser.py::test_the_explorer_in_chromium",
    "tests/test_numba_cache.py::test_a_run_from_the_cache_loads_no_compiler_and_a_later",
    "tests/oracle/test_oracle_selfcheck.py::test_rolling_conserves_energy",
    "tests/test_compile_scope.py::test_the_diagnostics_of_a_rolling_run_compile_no_other",
)


def _started_first_rank(nodeid: str) -> int:
    """The place of ``nodeid`` in :data:`STARTED_FIRST`, ``len(STARTED_FIRST)`` if none."""
    return next(
        (rank for rank, prefix in enumerate(STARTED_FIRST) if nodeid.startswith(prefix)),
        len(STARTED_FIRST),
    )


@pytest.hookimpl(trylast=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Keep ``make test``'s ``xdist_group`` marks working: with ``--dist loadgroup`` each
    worker appends ``@GROUP`` to a grouped test's node ID and the scheduler keeps a group
    on one worker. pytest-xdist 3.8 writes the suffix into ``Item._nodeid``, which pytest
    9.2 no longer reads (node IDs are structured), so every group was split across the
    workers and its module and session fixtures computed in both (pytest-xdist issue
    1386). Here the suffix goes into the structured ID, after xdist's own hook and only
    where that left none. Then the tests of :data:`STARTED_FIRST` go first (every
    worker sorts alike, so the workers' collections stay the same)."""
    if not getattr(config.option, "loadgroup", False):  # a worker of --dist loadgroup
        return
    from _pytest.nodeid import coerce_node_id

    for item in items:
        marks = item.iter_markers("xdist_group")
        names = sorted(
            {str(m.args[0] if m.args else m.kwargs.get("name", "default")) for m in marks}
        )
        suffix = "@" + "_".join(names)
        if names and not item.nodeid.endswith(suffix):
            item._id = coerce_node_id(item.nodeid + suffix)  # type: ignore[attr-defined]
    items.sort(key=lambda item: _started_first_rank(item.nodeid))  # stable: ties keep order


@pytest.fixture(scope="session")
def kane_levinson() -> cs.Body:
    """Kane & Levinson (1982) ellipsoid, ../shared/references.md."""
    return cs.load_body("kane_levinson_1982")


@pytest.fixture(params=BODY_NAMES, scope="session")
def any_body(request: pytest.FixtureRequest) -> cs.Body:
    """Each shipped body in turn."""
    return cs.load_body(request.param)


# Kane & Levinson's initial state: alpha = beta = 0.5 deg, omega = (0, 0, w3) body axes
LITERATURE_EULER_ANGLES = (0.5, 0.5)


# --------------------------------------------------------------------------------------
# One quick reproduction, read by the tests of Figure 2, of the report and of the atlas
# --------------------------------------------------------------------------------------

QUICK_REPRODUCTION = "quick-reproduction"
"""The ``xdist_group`` of every test that reads :func:`quick_reproduction`. pytest-xdist
computes a session fixture once in each worker that asks for it; the group keeps its
readers in one worker, so the reproduction is computed once per ``make test``."""


@dataclass(frozen=True)
class QuickReproduction:
    """``celtstone reproduce all --quick`` of the K&L body with the paper's contact.

    Attributes
    ----------
    out : pathlib.Path
        The directory it wrote (``--out``).
    argv : list of str
        Its command line, without the program name.
    status : int
        Its exit status.
    shared : list
        The :class:`celtstone.reproduce.parallel.SharedRuns` of each ``sharing_runs`` block
        it entered, after the block ended.
    """

    out: Path
    argv: list[str]
    status: int
    shared: list


@pytest.fixture(scope="session")
def quick_reproduction(tmp_path_factory: pytest.TempPathFactory) -> QuickReproduction:
    """Every target of the K&L body in ``--quick`` form (Figure 2's runs of 5 s, the
    threshold, Figure 3, the coarse atlas), run once through the CLI; mark its readers
    ``pytest.mark.xdist_group(QUICK_REPRODUCTION)``."""
    from celtstone.cli.main import main
    from celtstone.reproduce import targets as reproduce_targets

    out = tmp_path_factory.mktemp("quick-reproduction")
    argv = [
        *("reproduce", "all", "--quick", "--no-progress", "--out", str(out)),
        *("--body", "kane_levinson_1982", "--contact", "paper"),
    ]
    shared: list = []
    sharing = reproduce_targets.sharing_runs

    @contextlib.contextmanager
    def watched(*args: object, **kwargs: object) -> Iterator[object]:
        with sharing(*args, **kwargs) as runs:  # type: ignore[arg-type]
            shared.append(runs)
            yield runs

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(reproduce_targets, "sharing_runs", watched)
        status = main(argv)
    return QuickReproduction(out, argv, status, shared)
