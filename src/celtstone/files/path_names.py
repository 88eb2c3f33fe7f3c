"""Output names the file system and the writers can take, checked before any work.

A name that is not UTF-8 text (bytes of another encoding, read by Python as surrogates)
cannot be passed to NetCDF or Zarr, and a name over the file system's limit fails only
when the file is created, after the computation: both are bad input, refused at once
with the option that gave them (exit 2), not an error while writing (exit 1).
"""

from __future__ import annotations

import os
from pathlib import Path

from celtstone.errors import ParameterError

__all__ = ["TEMPORARY_NAME_EXTRA", "check_path_name"]

# what a temporary adds to a name: "." NAME "." <pid, up to 10 digits> "." <8> ".part"
# (export's temporaries); the temporary must fit the file system's limit too
TEMPORARY_NAME_EXTRA = 1 + 1 + 10 + 1 + 8 + len(".part")
_DEFAULT_NAME_MAX = 255  # bytes; POSIX file systems' usual limit
_DEFAULT_PATH_MAX = 4096  # bytes; Linux's


def _limit(directory: Path, name: str, default: int) -> int:
    try:
        return int(os.pathconf(directory, name))
    except (OSError, ValueError, AttributeError):  # no such directory, or no pathconf
        return default


def check_path_name(path: str | Path, parameter: str) -> None:
    """Refuse ``path`` (ParameterError naming ``parameter``) if it is not UTF-8 text or
    its name, with a temporary's affixes, or the whole path is over the file system's
    limit."""
    text = str(path)
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        raise ParameterError(
            parameter,
            text,
            "a path in UTF-8 text",
            "its name holds bytes of another encoding, which NetCDF and Zarr cannot "
            "store: rename it",
        ) from None
    target = Path(text)
    directory = target.parent
    name_max = _limit(directory, "PC_NAME_MAX", _DEFAULT_NAME_MAX)
    size = len(os.fsencode(target.name))
    if size + TEMPORARY_NAME_EXTRA > name_max:
        raise ParameterError(
            parameter,
            text,
            f"a file name of at most {name_max - TEMPORARY_NAME_EXTRA} bytes",
            f"this one has {size}; the file system takes {name_max}, and the temporary "
            f"written first adds {TEMPORARY_NAME_EXTRA}",
        )
    path_max = _limit(directory, "PC_PATH_MAX", _DEFAULT_PATH_MAX)
    whole = len(os.fsencode(os.path.abspath(text))) + TEMPORARY_NAME_EXTRA
    if whole >= path_max:
        raise ParameterError(
            parameter, text, f"a path of fewer than {path_max} bytes", f"this one has {whole}"
        )
