"""Run the reproduction's targets, each staged and moved into place whole (see the
package docstring)."""

from __future__ import annotations

import contextlib
import functools
import os
import secrets
import signal
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Protocol

from celtstone._about import version
from celtstone.errors import OutputError, ParameterError
from celtstone.files.export import (
    output_error,
    remove_stale_temporaries,
    replace_directory,
    temporary_directory,
    write_json,
)
from celtstone.files.ownership import file_entry
from celtstone.reproduce.cases import (
    case_key,
    compile_run_loop,
    compute_case,
    quiet_friction_bound,
)
from celtstone.reproduce.directory import ReproductionDirectory
from celtstone.reproduce.figure2 import figure2, figure2_models
from celtstone.reproduce.figure3 import figure3, figure3_models
from celtstone.reproduce.ingredients import ingredient_models
from celtstone.reproduce.parallel import SharedRuns, sharing_runs
from celtstone.reproduce.progress import Progress, duration_words, progress_bar
from celtstone.reproduce.report import write_report
from celtstone.reproduce.study import REALISTIC_STUDIES, STUDIES, TARGETS, Study
from celtstone.reproduce.threshold import threshold
from celtstone.simulation.models import Model

_RUNNERS = {"fig2": figure2, "fig3": figure3, "threshold": threshold}
_STAGING = "reproduce"  # staging directories out/.reproduce.<pid>.<random>.part
ATLAS_TARGET = "atlas"
"""The target of the whole family (issue 15): run once, not per study, by the runner
``celtstone.atlas.target.AtlasTarget`` that the caller passes (the atlas builds on this
package, so this package cannot import it)."""
_STORES = ("atlas.zarr",)  # directories a target writes, moved into ``out`` whole
ATLAS_SOURCE = "the atlas family"  # what the atlas's result was computed for


class FamilyTarget(Protocol):
    """A target run once for a reproduction (the atlas): writes its files into the
    staging directory it is given and returns its numbers (with ``target`` and ``key``)."""

    def runs(self) -> int: ...

    def __call__(self, out: Path, progress: Progress) -> dict[str, Any]: ...


def _targets(names: Sequence[str], atlas: FamilyTarget | None) -> list[str]:
    """The targets asked for; ``all`` is every study's target and the atlas if given."""
    known = (*TARGETS, ATLAS_TARGET)
    chosen: list[str] = []
    for name in names:
        if name == "all":
            chosen.extend(TARGETS if atlas is None else known)
        elif name in known:
            chosen.append(name)
        else:
            raise ParameterError("target", name, "one of: " + ", ".join((*known, "all")))
    if ATLAS_TARGET in chosen and atlas is None:
        raise ParameterError(
            "atlas", None, "an atlas target, celtstone.atlas.target.AtlasTarget(grid)"
        )
    return list(dict.fromkeys(chosen))


def _planned_runs(study: Study, target: str) -> list[tuple[Study, Model, float]]:
    """The runs a study's target asks for, each with the study it runs in and its length
    [s]: all of them but the threshold's bisections, which follow from its grid."""
    if target == "fig2":
        t_end = study.fig2_t_end
        ingredients = [(i.study(study), model, t_end) for i, model in ingredient_models(study)]
        return [(study, model, t_end) for model in figure2_models(study)] + ingredients
    if target == "fig3":
        return [(study, model, study.fig3_t_end) for model in figure3_models(study)]
    return [(study, study.sliding(f), study.threshold_t_end) for f in study.friction_grid()]


def _in_run_order(chosen: Sequence[str]) -> list[str]:
    """The targets in the order they run: the atlas first. Its sweeps go in rounds (each
    waits for its slowest run) and end with a few long runs: run last, they would leave a
    core idle at the end; run first, they share the cores with the runs computed ahead
    for the other targets, whose figures and videos (one thread's work) follow."""
    return sorted(chosen, key=lambda target: target != ATLAS_TARGET)


def _plan(runs: SharedRuns, chosen: Sequence[str], studies: Sequence[Study]) -> None:
    """Every planned run of the studies' targets, in the order the targets ask for them."""
    bodies = {study.body: study.load_body() for study in studies}
    for target in chosen:
        for study in studies:
            if target in study.targets and target in _RUNNERS:
                for run_study, model, t_end in _planned_runs(study, target):
                    compute = functools.partial(
                        compute_case, run_study, bodies[study.body], model, t_end
                    )
                    runs.plan(case_key(run_study, model, t_end), compute)


def _utc_now() -> str:
    return datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def run_identity(targets: Sequence[str], studies: Sequence[Study]) -> dict[str, Any]:
    """Identify one ``reproduce`` call in each target's numbers.

    Parameters
    ----------
    targets : sequence of str
        The targets asked for.
    studies : sequence of Study
        The studies asked for.

    Returns
    -------
    dict
        A unique ``id``, the UTC start time, the celtstone version, the targets, bodies
        and studies (keys).
    """
    started = _utc_now()
    return {
        "id": f"{started.replace('-', '').replace(':', '')}-{secrets.token_hex(3)}",
        "started_utc": started,
        "celtstone_version": version(),
        "targets": list(targets),
        "bodies": [study.body for study in studies],
        "studies": [study.key for study in studies],
        "quick": any(study.reduced for study in studies),
    }


@contextlib.contextmanager
def _signals_deferred() -> Iterator[None]:
    """SIGINT and SIGTERM wait until the block is done (a few renames), then act as they
    would have. Only the main thread can hold them; elsewhere nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending: list[signal.Signals] = []

    def note(signum: int, frame: object) -> None:
        pending.append(signal.Signals(signum))

    # read before any swap, so that a signal between the swaps (raising in the handler
    # not yet swapped) cannot leave the other one swapped: both are put back in any case
    previous = {number: signal.getsignal(number) for number in (signal.SIGINT, signal.SIGTERM)}
    try:
        signal.signal(signal.SIGINT, note)
        signal.signal(signal.SIGTERM, note)
        yield
    finally:
        try:  # nested: a SIGINT once its handler is back must not leave SIGTERM's swapped
            _restore_handler(previous, signal.SIGINT)
        finally:
            _restore_handler(previous, signal.SIGTERM)
    if pending:
        handler = previous[pending[0]]
        if callable(handler):
            handler(pending[0], None)
        elif handler == signal.SIG_DFL:
            signal.raise_signal(pending[0])


def _restore_handler(previous: dict[signal.Signals, Any], number: signal.Signals) -> None:
    handler = previous[number]
    signal.signal(number, signal.SIG_DFL if handler is None else handler)


def _move_files(
    staging: Path, directory: ReproductionDirectory, last: Path, source: str, run: str
) -> None:
    """Every file of ``staging`` to the same place in ``out``, ``last`` last; a store
    (``_STORES``, a directory) moves whole. Nothing moves unless every destination may be
    replaced (``ReproductionDirectory.check_moves``); the manifest lists them after."""
    out = directory.out
    result = last.stem
    stores = [staging / name for name in _STORES if (staging / name).is_dir()]
    files = [
        *sorted(
            p
            for p in staging.rglob("*")
            if p.is_file() and p != last and not any(p.is_relative_to(s) for s in stores)
        ),
        last,
    ]
    moves = {p.relative_to(staging).as_posix(): p for p in (*stores, *files)}
    directory.check_moves(moves, result)
    entries = {
        p.relative_to(staging).as_posix(): file_entry(p)
        for p in (*files, *(f for s in stores for f in s.rglob("*") if f.is_file()))
    }
    with _signals_deferred():
        for store in stores:
            replace_directory(store, out / store.relative_to(staging))
        for path in files:
            destination = out / path.relative_to(staging)
            try:
                destination.parent.mkdir(parents=True, exist_ok=True)
                os.replace(path, destination)
            except OSError as error:
                raise output_error(destination, error) from error
        try:
            directory.record(entries, result, source, run)
        except OSError as error:
            raise output_error(out, error) from error


def _run_target(
    run: Callable[[Path, Progress], dict[str, Any]],
    directory: ReproductionDirectory,
    progress: Progress,
    identity: dict[str, Any],
    source: str,
) -> None:
    """One target, staged: its files reach ``out`` only once it is done."""
    out = directory.out
    with temporary_directory(out / _STAGING) as staging:
        try:
            result = run(staging, progress)
            numbers = staging / "data" / f"{result['target']}_{result['key']}.json"
            stamped = {**result, "run": {**identity, "finished_utc": _utc_now()}}
            numbers.parent.mkdir(exist_ok=True)
            write_json(stamped, numbers, overwrite=True)  # the target's own, in staging
            _move_files(staging, directory, numbers, source, identity["id"])
        except OutputError as error:  # name the file where it went, not the staging area
            path = Path(error.path)
            if path.is_relative_to(staging):
                raise OutputError(
                    str(out / path.relative_to(staging)), error.cause, error.errno
                ) from error
            raise


def _body_source(study: Study) -> str:
    """What a study's results were computed for: the body file (resolved) or the shipped
    body; two sources must not share a result's name."""
    text = study.body
    if text.endswith(".toml") or Path(text).is_file():
        return f"body file {os.path.realpath(text)}"
    return f"shipped body {text}"


def _planned(
    chosen: Sequence[str], studies: Sequence[Study], atlas: FamilyTarget | None
) -> tuple[dict[str, str], dict[str, str]]:
    """The results (stem -> source) and stores (name -> result) a reproduction writes;
    two bodies of the same name from different sources are refused, naming both."""
    results: dict[str, str] = {}
    bodies: dict[str, Study] = {}
    for target in chosen:
        if target == ATLAS_TARGET and atlas is not None:
            results[f"{ATLAS_TARGET}_{ATLAS_TARGET}"] = ATLAS_SOURCE
            continue
        for study in studies:
            if target not in study.targets:
                continue
            source = _body_source(study)
            other = bodies.setdefault(study.key, study)
            if _body_source(other) != source:
                raise ParameterError(
                    "body",
                    study.body,
                    f"bodies whose results have different names (this one's are {study.key})",
                    f"{other.body} has the same name; rename one of the files",
                )
            results[f"{target}_{study.key}"] = source
    stores = {name: f"{ATLAS_TARGET}_{ATLAS_TARGET}" for name in _STORES}
    return results, stores if ATLAS_TARGET in chosen and atlas is not None else {}


def reproduce(
    targets: Sequence[str],
    out: str | Path = "results",
    studies: Sequence[Study] = STUDIES + REALISTIC_STUDIES,
    progress: bool = True,
    atlas: FamilyTarget | None = None,
    *,
    overwrite: bool = False,
) -> Path:
    """Run ``targets`` for each study and rebuild the report.

    Writes figures, tables and NetCDF runs into ``out`` and rebuilds
    ``out/report.md`` from every target's numbers found there. Each target reaches
    ``out`` whole or not at all (see the module docstring): an interrupted run leaves
    the finished targets and nothing of the others. A result already in ``out`` is
    replaced only with ``overwrite``, and a file celtstone did not write there never
    is (``reproduce.directory``): both are refused before the first run.

    Parameters
    ----------
    targets : sequence of str
        ``fig2``, ``fig3``, ``threshold``, ``atlas`` or ``all``.
    out : str or pathlib.Path, optional
        The directory written.
    studies : sequence of Study, optional
        The studies (default the paper's and the realistic ones).
    progress : bool, optional
        Whether to show a progress bar.
    atlas : FamilyTarget, optional
        The atlas (``celtstone.atlas.target.AtlasTarget``), run once, before the studies;
        ``all`` includes it when it is given.
    overwrite : bool, optional
        Whether results of an earlier reproduction in ``out`` may be replaced.

    Returns
    -------
    pathlib.Path
        The report ``out/report.md``.

    Raises
    ------
    ParameterError
        Naming ``out`` (empty, not a directory, a file there that may not be replaced,
        another process writing it) or ``body`` (two bodies of the same name).
    """
    if str(out) == "":
        raise ParameterError("out", str(out), "a directory", "the path is empty")
    chosen = _targets(targets, atlas)
    results, stores = _planned(chosen, studies, atlas)
    with ReproductionDirectory(Path(out), overwrite=overwrite) as directory:
        directory.check_planned(results, stores)
        return _reproduce(chosen, directory, studies, progress, atlas)


def _reproduce(
    chosen: Sequence[str],
    directory: ReproductionDirectory,
    studies: Sequence[Study],
    progress: bool,
    atlas: FamilyTarget | None,
) -> Path:
    identity = run_identity(chosen, studies)
    total = sum(
        len(_planned_runs(study, target))
        for study in studies
        for target in chosen
        if target in study.targets
    )
    if atlas is not None and ATLAS_TARGET in chosen:
        total += atlas.runs()
    # what a killed reproduction left goes now, as each target's staging would remove it,
    # since a signal may come in a run computed ahead before the first target has begun
    remove_stale_temporaries(directory.out / _STAGING)
    bar = progress_bar(total, "reproduce", progress)
    started = time.monotonic()

    def done(words: str, since: float) -> None:
        now = time.monotonic()
        bar.note(f"{words}: {duration_words(now - since)} ({duration_words(now - started)} in all)")

    # the runs of every study's targets computed ahead on the cores (``parallel``), quiet
    # as each target's own are (``cases.quiet_friction_bound``: the filters are the process's),
    # once the loop that every run can take is compiled (``cases.compile_run_loop``)
    try:
        if studies:
            bar.set_description("compiling the run loop (once)")
            compile_run_loop(studies[0])
        with quiet_friction_bound(), sharing_runs() as runs:
            _plan(runs, chosen, studies)
            for target in _in_run_order(chosen):
                if target == ATLAS_TARGET and atlas is not None:
                    since = time.monotonic()
                    _run_target(atlas, directory, bar, identity, ATLAS_SOURCE)
                    done("atlas", since)
                    continue
                for study in studies:
                    if target in study.targets:  # a study may run some targets only
                        since = time.monotonic()
                        run = functools.partial(_RUNNERS[target], study)
                        _run_target(run, directory, bar, identity, _body_source(study))
                        done(f"{target} {study.key}", since)
        since = time.monotonic()
        report = write_report(directory.out, directory)
        done("report", since)
    finally:
        bar.close()
    return report
