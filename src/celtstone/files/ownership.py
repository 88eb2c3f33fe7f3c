"""What celtstone may replace: only what it wrote itself, proven by a marker it owns.

The one rule of every command that writes a directory (a fit, a sweep store, a
reproduction, an atlas store in it):

* the directory carries a manifest, :data:`MANIFEST` (``.celtstone-output.json``): the
  command that wrote it, a random id, and every file it wrote with its size and SHA-256.
  A Zarr store, whose chunk files change as it is filled and where Zarr warns of any
  file it does not know, carries its mark in its own group metadata instead (the
  caller checks it) and is described by its arrays: a file is the store's if Zarr names
  it so (:func:`foreign_file` with ``zarr``);
* it is replaced only with ``overwrite``, only if its manifest names the same command,
  and only if it holds nothing but the files listed, unchanged since they were written:
  anything else (a user's notes, their input data, a listed file they edited) is a
  one-line :class:`~celtstone.errors.ParameterError` naming that file;
* an input of the command is never inside what its output replaces
  (:func:`check_inputs_outside`, by resolved path and ``os.path.samefile``);
* a directory being written is locked against a second writer (:class:`WriterLock`, an
  exclusive ``flock`` held for the writer's lifetime; the kernel drops the lock of a
  killed process, so a stale lock file never blocks).

A file name alone never proves ownership: a user can have a ``summary.json`` or a
``report.md`` too; the manifest's hash of the file's bytes can.

A single file is replaced (``--overwrite``) only if it carries celtstone's mark where
its format has a place for one (:func:`is_marked_file`): the global attribute
``software = "celtstone"`` of a NetCDF run, the ``Software`` text of a PNG and the
``Creator`` of an SVG or PDF figure (:func:`figure_metadata`), a ``# software: celtstone
...`` line among a CSV file's leading comments (:data:`CSV_MARK`), the ``generator``
meta tag of an HTML page, the comment of a GIF or MP4 video (:func:`video_mark`; an
MP4's is read from its last 64 kB, where ffmpeg writes it). Other formats (JSON,
Markdown) are not checked: an existing regular file of those is replaced as asked.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
import secrets
import tempfile
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any, Self

from celtstone.errors import ParameterError

__all__ = [
    "CSV_MARK",
    "MANIFEST",
    "SOFTWARE",
    "WriterLock",
    "check_inputs_outside",
    "check_replaceable",
    "figure_metadata",
    "file_entry",
    "foreign_file",
    "is_marked_file",
    "new_manifest",
    "read_manifest",
    "video_mark",
    "write_manifest",
]

SOFTWARE = "celtstone"
"""The mark of a file celtstone wrote: its software attribute, or the start of it."""
CSV_MARK = "# software: " + SOFTWARE
"""The start of the comment line that marks a CSV file as celtstone's (its version follows)."""
MANIFEST = ".celtstone-output.json"
"""The marker file of every output directory celtstone writes."""
FORMAT = "celtstone-output-1"
_MANIFEST_SIZE_LIMIT = 64 << 20  # bytes; far above any manifest celtstone writes
_HASH_BLOCK = 1 << 20  # bytes read at a time
_UMASK = os.umask(0o022)  # read the process's umask once (os.umask can only set it) ...
os.umask(_UMASK)  # ... and put it back
# a Zarr v3 chunk key ("c/0/12") and Zarr's local-store temporary ("12.<uuid hex>.partial")
_CHUNK_PART = re.compile(r"\d{1,20}")
_ZARR_TEMPORARY = re.compile(r"(\d{1,20}|zarr)\.[0-9a-f]{32}\.partial")


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        while block := stream.read(_HASH_BLOCK):
            digest.update(block)
    return digest.hexdigest()


def file_entry(path: str | Path) -> dict[str, Any]:
    """The manifest's record of one file: its size [bytes] and SHA-256.

    Parameters
    ----------
    path : str or pathlib.Path
        A file celtstone has just written.

    Returns
    -------
    dict
        ``{"size": ..., "sha256": ...}``.
    """
    source = Path(path)
    return {"size": source.stat().st_size, "sha256": _sha256(source)}


def new_manifest(command: str, *, zarr: bool = False) -> dict[str, Any]:
    """An empty manifest of ``command`` with a new random id.

    Parameters
    ----------
    command : str
        The command that writes the directory (``fit``, ``sweep``, ``reproduce``).
    zarr : bool, optional
        Whether the directory is a Zarr store (its chunks are the store's by their names).

    Returns
    -------
    dict
        The manifest, its ``files`` empty.
    """
    return {
        "format": FORMAT,
        "command": command,
        "id": secrets.token_hex(8),
        "zarr": zarr,
        "files": {},
    }


def record_files(manifest: dict[str, Any], directory: Path, files: Iterable[Path]) -> None:
    """Add ``files`` (inside ``directory``) to ``manifest`` with their sizes and hashes."""
    for path in files:
        manifest["files"][path.relative_to(directory).as_posix()] = file_entry(path)


def read_manifest(directory: str | Path) -> dict[str, Any] | None:
    """The manifest of ``directory``, or None if it has none that celtstone wrote.

    Parameters
    ----------
    directory : str or pathlib.Path
        An output directory.

    Returns
    -------
    dict or None
        The manifest.
    """
    path = Path(directory) / MANIFEST
    try:
        if path.is_symlink() or not path.is_file():
            return None
        if path.stat().st_size > _MANIFEST_SIZE_LIMIT:
            return None
        document = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        return None
    if not isinstance(document.get("command"), str) or not isinstance(document.get("files"), dict):
        return None
    return document


def write_manifest(directory: str | Path, manifest: Mapping[str, Any]) -> Path:
    """Write ``manifest`` into ``directory`` whole (a temporary renamed into place).

    Parameters
    ----------
    directory : str or pathlib.Path
        The output directory.
    manifest : Mapping
        From :func:`new_manifest`, its files recorded.

    Returns
    -------
    pathlib.Path
        The manifest file.
    """
    target = Path(directory) / MANIFEST
    text = json.dumps(manifest, indent=1, sort_keys=True) + "\n"
    # ".NAME.<pid>.<8 random>.part": export.remove_stale_temporaries's naming
    with tempfile.NamedTemporaryFile(
        "w",
        encoding="utf-8",
        dir=target.parent,
        prefix=f".{MANIFEST}.{os.getpid()}.",
        suffix=".part",
        delete=False,
    ) as stream:
        temporary = Path(stream.name)
        try:
            stream.write(text)
        except BaseException:
            stream.close()
            temporary.unlink(missing_ok=True)
            raise
    try:
        os.chmod(temporary, 0o666 & ~_UMASK)  # the mode a plain open() would give it
        os.replace(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return target


def _is_zarr_part(relative: tuple[str, ...], arrays: Mapping[tuple[str, ...], int]) -> bool:
    """Whether the file ``relative`` (path parts) is Zarr's: a node's ``zarr.json``, a
    chunk ``ARRAY/c/i/j`` of an array of that many dimensions, or Zarr's temporary."""
    name = relative[-1]
    if name == "zarr.json" or _ZARR_TEMPORARY.fullmatch(name):
        return True
    for array, ndim in arrays.items():
        depth = len(array)
        if relative[:depth] != array or len(relative) != depth + 1 + ndim:
            continue
        key = relative[depth:]
        return key[0] == "c" and all(_CHUNK_PART.fullmatch(part) for part in key[1:])
    return False


def _zarr_arrays(directory: Path) -> dict[tuple[str, ...], int]:
    """Every array of the Zarr store ``directory``: its path parts -> its dimensions."""
    arrays: dict[tuple[str, ...], int] = {}
    for metadata in directory.rglob("zarr.json"):
        try:
            document = json.loads(metadata.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if isinstance(document, dict) and document.get("node_type") == "array":
            shape = document.get("shape")
            if isinstance(shape, list):
                arrays[metadata.parent.relative_to(directory).parts] = len(shape)
    return arrays


def _walk(directory: Path) -> Iterator[Path]:
    """Every entry under ``directory`` that is not a directory, links to directories
    included (never followed), sorted; an empty directory holds nothing to lose."""
    for root, folders, files in os.walk(directory, followlinks=False):
        folders.sort()
        base = Path(root)
        for name in sorted(files):
            yield base / name
        for name in folders:
            path = base / name
            if path.is_symlink():
                yield path


def foreign_file(directory: str | Path, manifest: Mapping[str, Any]) -> Path | None:
    """The first entry of ``directory`` that ``manifest`` does not prove celtstone's.

    An entry is celtstone's if it is the manifest itself, a file listed with the same
    size and SHA-256, or, in a Zarr store (``manifest["zarr"]``), a file Zarr names:
    a node's ``zarr.json``, a chunk ``ARRAY/c/i/...`` of one of the store's arrays, or
    Zarr's own temporary. A link is never celtstone's.

    Parameters
    ----------
    directory : str or pathlib.Path
        The output directory.
    manifest : Mapping
        Its manifest (:func:`read_manifest`).

    Returns
    -------
    pathlib.Path or None
        The first foreign entry, None if there is none.
    """
    root = Path(directory)
    listed = manifest.get("files", {})
    arrays = _zarr_arrays(root) if manifest.get("zarr") else {}
    for path in _walk(root):
        relative = path.relative_to(root)
        if path.is_symlink():
            return path
        if relative.as_posix() == MANIFEST:
            continue
        entry = listed.get(relative.as_posix())
        if isinstance(entry, dict):
            try:
                if file_entry(path) == {"size": entry.get("size"), "sha256": entry.get("sha256")}:
                    continue
            except OSError:
                pass
            return path
        if manifest.get("zarr") and _is_zarr_part(relative.parts, arrays):
            continue
        return path
    return None


def check_replaceable(
    directory: str | Path,
    command: str,
    *,
    parameter: str = "out",
    inputs: Iterable[str | Path] = (),
    zarr: bool = False,
) -> None:
    """Raise unless ``directory`` holds only what ``celtstone command`` wrote, unchanged.

    Call it before any computation whose output replaces ``directory``, and again just
    before the replacement.

    Parameters
    ----------
    directory : str or pathlib.Path
        The existing output directory.
    command : str
        The command that is to replace it.
    parameter : str, optional
        The option named in errors.
    inputs : iterable of path, optional
        The command's input files: none may be inside ``directory``.
    zarr : bool, optional
        ``directory`` is a Zarr store whose group metadata the caller has found to be
        ``command``'s: every file in it must be Zarr's (it has no manifest).

    Raises
    ------
    ParameterError
        Naming ``parameter`` and the first file that is not celtstone's.
    """
    target = Path(directory)
    allowed = f"a directory written by `celtstone {command}`"
    if target.is_symlink() or not target.is_dir():
        what = "a link" if target.is_symlink() else "a file"
        raise ParameterError(parameter, str(directory), allowed, f"it is {what}")
    manifest = {"command": command, "zarr": True, "files": {}} if zarr else read_manifest(target)
    if manifest is None or manifest.get("command") != command:
        raise ParameterError(
            parameter,
            str(directory),
            allowed,
            f"it has no {MANIFEST} of `celtstone {command}`; --overwrite replaces only "
            "what celtstone wrote itself",
        )
    check_inputs_outside(target, inputs, parameter)
    first = foreign_file(target, manifest)
    if first is not None:
        raise ParameterError(
            parameter,
            str(directory),
            f"a directory holding only what `celtstone {command}` wrote",
            f"{first} is not celtstone's or changed since it was written; move it out first",
        )


def figure_metadata(suffix: str) -> dict[str, str]:
    """The metadata that marks a figure as celtstone's (matplotlib's ``savefig``).

    Parameters
    ----------
    suffix : str
        The figure's format (``png``, ``svg``, ``pdf``; a leading dot is ignored).

    Returns
    -------
    dict
        ``{"Software": ...}`` for PNG, ``{"Creator": ...}`` for SVG and PDF.
    """
    from celtstone._about import version

    key = "Software" if suffix.lower().lstrip(".") == "png" else "Creator"
    return {key: f"{SOFTWARE} {version()}"}


_HEAD = 1 << 16  # bytes read from the start of a file for its mark
_TAIL = 1 << 14  # bytes read from the end of a PDF (its Info dictionary)
_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_SVG_CREATOR = re.compile(
    r"<dc:creator>\s*<cc:Agent>\s*<dc:title>" + SOFTWARE + r"[ <]", re.IGNORECASE
)


def _netcdf_is_marked(path: Path) -> bool:
    with open(path, "rb") as stream:
        signature = stream.read(len(_HDF5_SIGNATURE))
    if signature != _HDF5_SIGNATURE and not signature.startswith(b"CDF"):
        return False  # not opened: the library would print its diagnostics
    import netCDF4

    with netCDF4.Dataset(path, "r") as dataset:
        return bool(dataset.__dict__.get("software") == SOFTWARE)


def _png_is_marked(path: Path) -> bool:
    with open(path, "rb") as stream:
        head = stream.read(_HEAD)
    if not head.startswith(_PNG_SIGNATURE):
        return False
    position = len(_PNG_SIGNATURE)
    while position + 8 <= len(head):  # chunks: length, type, data, CRC
        length = int.from_bytes(head[position : position + 4], "big")
        kind = head[position + 4 : position + 8]
        data = head[position + 8 : position + 8 + length]
        if kind == b"IDAT":
            return False  # the text chunks matplotlib writes come before the image
        if kind == b"tEXt" and data.startswith(b"Software\x00" + SOFTWARE.encode() + b" "):
            return True
        position += 12 + length
    return False


def _svg_is_marked(path: Path) -> bool:
    with open(path, "rb") as stream:
        head = stream.read(_HEAD).decode("utf-8", "replace")
    return _SVG_CREATOR.search(head) is not None


def _pdf_is_marked(path: Path) -> bool:
    with open(path, "rb") as stream:
        if not stream.read(5) == b"%PDF-":
            return False
        stream.seek(0, os.SEEK_END)
        stream.seek(max(0, stream.tell() - _TAIL))
        tail = stream.read()
    return b"/Creator (" + SOFTWARE.encode() + b" " in tail


def _csv_is_marked(path: Path) -> bool:
    with open(path, "rb") as stream:
        head = stream.read(_HEAD).decode("utf-8", "replace")
    for line in head.splitlines():
        if not line.startswith("#"):
            return False  # the mark is among the leading comments
        if line == CSV_MARK or line.startswith(CSV_MARK + " "):
            return True
    return False


_HTML_GENERATOR = re.compile(r'<meta name="generator" content="' + SOFTWARE + r'[ "]')


def _html_is_marked(path: Path) -> bool:
    with open(path, "rb") as stream:
        head = stream.read(_HEAD).decode("utf-8", "replace")
    return _HTML_GENERATOR.search(head.split("</head>", 1)[0]) is not None


def video_mark() -> bytes:
    """The comment that marks a video as celtstone's (a GIF comment, MP4 ``comment``)."""
    from celtstone._about import version

    return f"{SOFTWARE} {version()}".encode()


_GIF_COMMENT = re.compile(rb"!\xfe.(" + SOFTWARE.encode() + rb" )", re.DOTALL)
_MP4_COMMENT = re.compile(rb"\xa9cmt.{4}data.{8}(" + SOFTWARE.encode() + rb" )", re.DOTALL)


def _gif_is_marked(path: Path) -> bool:
    with open(path, "rb") as stream:
        head = stream.read(_HEAD)
    return head[:6] in (b"GIF87a", b"GIF89a") and _GIF_COMMENT.search(head) is not None


def _mp4_is_marked(path: Path) -> bool:
    with open(path, "rb") as stream:
        if stream.read(8)[4:] != b"ftyp":
            return False
        stream.seek(0, os.SEEK_END)  # ffmpeg writes the metadata last, in the moov box
        stream.seek(max(0, stream.tell() - _HEAD))
        tail = stream.read()
    return _MP4_COMMENT.search(tail) is not None


_MARK_READERS = {
    ".gif": _gif_is_marked,
    ".mp4": _mp4_is_marked,
    ".nc": _netcdf_is_marked,
    ".png": _png_is_marked,
    ".svg": _svg_is_marked,
    ".pdf": _pdf_is_marked,
    ".csv": _csv_is_marked,
    ".html": _html_is_marked,
}


def is_marked_file(path: str | Path) -> bool | None:
    """Whether the existing file ``path`` carries celtstone's mark.

    Parameters
    ----------
    path : str or pathlib.Path
        A regular file.

    Returns
    -------
    bool or None
        True or False for a format that has a mark (NetCDF, PNG, SVG, PDF, CSV, HTML,
        GIF, MP4, by suffix); None for one that is not checked.
    """
    reader = _MARK_READERS.get(Path(path).suffix.lower())
    if reader is None:
        return None
    try:
        return reader(Path(path))
    except (OSError, ValueError, RuntimeError):
        return False


def _resolved(path: str | Path) -> Path:
    return Path(os.path.realpath(os.path.abspath(path)))


def check_inputs_outside(
    output: str | Path, inputs: Iterable[str | Path], parameter: str = "out"
) -> None:
    """Raise if an input is ``output`` or inside it (by resolved path or the same file).

    Parameters
    ----------
    output : str or pathlib.Path
        A file or directory that a command is to write or replace.
    inputs : iterable of path
        The files the command reads.
    parameter : str, optional
        The option named in errors.

    Raises
    ------
    ParameterError
        Naming ``parameter``, ``output`` and the input.
    """
    target = _resolved(output)
    for source in inputs:
        if str(source) == "":
            continue
        path = _resolved(source)
        same = False
        with contextlib.suppress(OSError):
            same = os.path.exists(output) and os.path.samefile(source, output)
        if same or path == target or path.is_relative_to(target):
            raise ParameterError(
                parameter,
                str(output),
                "an output that is not an input",
                f"{source} is read by this command and would be replaced; choose another output",
            )


class WriterLock:
    """An exclusive lock on an output while one process writes it.

    ``flock`` on ``path`` (created if needed), which holds this process's id. A second
    writer is refused in one line naming the output and the holder's id; the kernel
    releases the lock of a process that ends however it ends (SIGKILL too), so the
    file a killed process leaves never blocks. :meth:`release` removes the file.

    Parameters
    ----------
    path : pathlib.Path
        The lock file.
    output : str or pathlib.Path
        The output it protects (named in the error).
    parameter : str, optional
        The option named in errors.

    Raises
    ------
    ParameterError
        If another process holds the lock.
    """

    def __init__(self, path: Path, output: str | Path, parameter: str = "out") -> None:
        self.path = path
        self._fd: int | None = None
        import fcntl

        for _ in range(100):  # the holder may remove the file between our open and lock
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = os.read(fd, 32).decode("ascii", "replace").strip() or "unknown"
                os.close(fd)
                raise ParameterError(
                    parameter,
                    str(output),
                    "an output no other process is writing",
                    f"process {holder} is writing it; wait for it to finish or stop it",
                ) from None
            except BaseException:
                os.close(fd)
                raise
            try:
                same = os.fstat(fd).st_ino == os.stat(path).st_ino
            except FileNotFoundError:
                same = False
            if same:
                self._fd = fd
                with contextlib.suppress(OSError):  # the id is for the message only (full disk)
                    os.ftruncate(fd, 0)
                    os.write(fd, f"{os.getpid()}\n".encode("ascii"))
                return
            os.close(fd)  # a file removed by its holder meanwhile: lock the new one
        raise ParameterError(parameter, str(output), "an output no other process is writing")

    def release(self) -> None:
        """Remove the lock file and release the lock (again: nothing)."""
        if self._fd is None:
            return
        fd, self._fd = self._fd, None
        with contextlib.suppress(OSError):
            self.path.unlink()
        os.close(fd)

    def __enter__(self) -> WriterLock:
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()

    def __del__(self) -> None:
        self.release()


class LockedOutput:
    """An output this process writes while it holds the output's :class:`WriterLock`
    (``_lock``, or None for an output opened unlocked): :meth:`close`, or the end of a
    ``with`` block, lets another process write it."""

    _lock: WriterLock | None = None

    def close(self) -> None:
        """Release the lock (again, or unlocked: nothing)."""
        if self._lock is not None:
            self._lock.release()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
