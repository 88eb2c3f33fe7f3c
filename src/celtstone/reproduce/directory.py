"""The reproduction's directory: which files in it are celtstone's, and which may be replaced.

A reproduction adds its targets' files to ``out``, a directory that may hold the user's
own files too. Its manifest (``celtstone.files.ownership.MANIFEST``) lists every file a
reproduction moved in, with its size, SHA-256 and its *result* (``TARGET_KEY``, the stem
of the target's numbers ``data/TARGET_KEY.json``), and each result's source (the body
file, or the shipped body, it was computed for). The rules:

* a file that is not listed with its current bytes (a user's ``report.md``, a user's
  file that has an output's name, a listed file edited since) is never replaced, with or
  without ``overwrite``: a one-line refusal names it;
* a result already there is replaced only with ``overwrite``, and never by a result of
  another source with the same name (a custom ``kane_levinson_1982.toml`` beside the
  shipped body): the refusal names both;
* ``report.md``, the index of every result in ``out``, is rebuilt after each call when it
  is celtstone's and unchanged;
* a store (``atlas.zarr``) is replaced only when every file in it is listed, unchanged.

Every check is made before the first run (:meth:`ReproductionDirectory.check_planned`)
and again, authoritatively, before a target's files are moved in.
"""

from __future__ import annotations

import glob
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from celtstone.errors import ParameterError
from celtstone.files.export import OVERWRITE_HINT
from celtstone.files.ownership import (
    LockedOutput,
    WriterLock,
    file_entry,
    foreign_file,
    new_manifest,
    read_manifest,
    write_manifest,
)

__all__ = ["COMMAND", "REPORT", "ReproductionDirectory"]

COMMAND = "reproduce"
REPORT = "report.md"
_LOCK = ".celtstone-output.lock"
_ZARR_METADATA = "zarr.json"
_SEPARATORS = "._"  # after a result's stem in its files' names (not "+": another contact)


def _name_is_taken(out: Path, manifest: Mapping[str, Any]) -> None:
    """Refuse ``out`` if it holds the output of another command."""
    command = manifest.get("command")
    if command != COMMAND:
        raise ParameterError(
            "out",
            str(out),
            "a directory for `celtstone reproduce`",
            f"it holds the output of `celtstone {command}`; choose another directory",
        )


class ReproductionDirectory(LockedOutput):
    """The directory ``out`` of a reproduction, locked while it is written.

    Parameters
    ----------
    out : pathlib.Path
        The directory (made if missing).
    overwrite : bool
        Whether results already there may be replaced.
    lock : bool, optional
        Whether to hold ``out`` against a second reproduction until :meth:`close`.

    Raises
    ------
    ParameterError
        Naming ``out``: empty, not a directory, another command's output, or another
        process is writing it.
    """

    def __init__(self, out: Path, *, overwrite: bool, lock: bool = True) -> None:
        if str(out) == "":
            raise ParameterError("out", str(out), "a directory", "the path is empty")
        if os.path.lexists(out) and not out.is_dir():
            raise ParameterError("out", str(out), "a directory")
        if (out / _ZARR_METADATA).exists():  # Zarr warns of, and lists, any file in a store
            raise ParameterError("out", str(out), "a directory", "it is a Zarr store")
        try:
            out.mkdir(parents=True, exist_ok=True)
        except (NotADirectoryError, FileExistsError):
            raise ParameterError(
                "out", str(out), "a directory", "a part of the path is a file"
            ) from None
        self.out = out
        self.overwrite = overwrite
        self._lock = WriterLock(out / _LOCK, out) if lock else None
        try:
            manifest = read_manifest(out)
            if manifest is not None:
                _name_is_taken(out, manifest)
            self.manifest: dict[str, Any] = manifest or new_manifest(COMMAND)
            self.manifest.setdefault("results", {})
        except BaseException:
            self.close()
            raise

    # -- what is celtstone's -----------------------------------------------------------

    def owner(self, relative: str) -> str | None:
        """The result that wrote ``out/relative``, if it is listed with its current bytes."""
        entry = self.manifest["files"].get(relative)
        path = self.out / relative
        if not isinstance(entry, dict) or path.is_symlink() or not path.is_file():
            return None
        try:
            current = file_entry(path)
        except OSError:
            return None
        if current != {"size": entry.get("size"), "sha256": entry.get("sha256")}:
            return None
        return str(entry.get("result", ""))

    def _store_owner(self, relative: str) -> str | None:
        """The result that wrote the store ``out/relative`` if every file in it is listed,
        unchanged (and nothing else is in it)."""
        prefix = relative + "/"
        listed = {
            k[len(prefix) :]: v for k, v in self.manifest["files"].items() if k.startswith(prefix)
        }
        store = self.out / relative
        if not listed or store.is_symlink() or not store.is_dir():
            return None
        if foreign_file(store, {"files": listed}) is not None:
            return None
        results = {str(v.get("result", "")) for v in listed.values()}
        return results.pop() if len(results) == 1 else None

    def _refuse(self, path: Path, why: str) -> ParameterError:
        return ParameterError(
            "out", str(self.out), "a directory whose files celtstone may replace", f"{path} {why}"
        )

    def check_replaceable(self, relative: str, result: str | None) -> None:
        """Raise unless ``out/relative`` is free, or ``result``'s own (with ``overwrite``);
        ``result`` None: the report, rebuilt whenever it is celtstone's."""
        path = self.out / relative
        if not os.path.lexists(path):
            return
        is_store = path.is_dir() and not path.is_symlink()
        owner = self._store_owner(relative) if is_store else self.owner(relative)
        if owner is None:
            raise self._refuse(
                path, "is not celtstone's or changed since it was written; move it out first"
            )
        if result is None:
            return
        if owner != result:
            raise self._refuse(path, f"belongs to the result {owner}, not {result}")
        if not self.overwrite:
            raise self._refuse(path, f"is from an earlier run; {OVERWRITE_HINT}")

    # -- before the first run ----------------------------------------------------------

    def check_planned(self, results: Mapping[str, str], stores: Mapping[str, str]) -> None:
        """Refuse, before any run, what a reproduction of ``results`` would have to replace.

        Parameters
        ----------
        results : Mapping
            Each result's stem (``TARGET_KEY``) -> its source (body file or shipped body).
        stores : Mapping
            Each store the reproduction writes (``atlas.zarr``) -> its result.
        """
        self.check_replaceable(REPORT, None)
        recorded = self.manifest["results"]
        for stem, source in results.items():
            earlier = recorded.get(stem, {}).get("source")
            if earlier is not None and earlier != source:
                raise ParameterError(
                    "body",
                    source,
                    f"a body whose results are not named {stem} in {self.out} already",
                    f"{stem} there was computed for {earlier}; rename the body file or "
                    "choose another --out",
                )
            self.check_replaceable(f"data/{stem}.json", stem)
            for folder in (self.out, self.out / "data"):
                found = folder.glob(f"{glob.escape(stem)}*") if folder.is_dir() else ()
                for entry in sorted(found):
                    rest = entry.name[len(stem) :]
                    if rest[:1] in _SEPARATORS:
                        relative = entry.relative_to(self.out).as_posix()
                        self.check_replaceable(relative, stem)
        for relative, result in stores.items():
            self.check_replaceable(relative, result)

    # -- moving a target in ------------------------------------------------------------

    def check_moves(self, moves: Iterable[str], result: str) -> None:
        """Raise unless every ``out/relative`` of ``moves`` may take ``result``'s file."""
        for relative in moves:
            self.check_replaceable(relative, result)

    def record(
        self, entries: Mapping[str, dict[str, Any]], result: str, source: str, run: str
    ) -> None:
        """List the files moved in for ``result`` and save the manifest."""
        for relative, entry in entries.items():
            self.manifest["files"][relative] = {**entry, "result": result}
        self.manifest["results"][result] = {"source": source, "run": run}
        self.save()

    def record_report(self) -> None:
        """List the report just written and save the manifest."""
        self.manifest["files"][REPORT] = file_entry(self.out / REPORT)
        self.save()

    def save(self) -> None:
        """Write the manifest whole."""
        write_manifest(self.out, self.manifest)
