"""Write the intersphinx inventories the documentation links to, without the network.

The build machine cannot fetch ``objects.inv`` from NumPy, SciPy, xarray, matplotlib or
Python (decisions §33), so ``docs/conf.py`` reads these small copies: each holds only the
external names that celtstone's docstrings and pages refer to, declared below with the
page that documents them. Run ``python docs/_inventories/make.py`` after adding a name
(a type in a docstring, a role in a page) and commit the ``.inv`` files it writes.

The format is Sphinx's inventory version 2: four header lines, then zlib-compressed
lines ``name domain:role priority uri display-name``; a ``$`` ending a uri stands for the
name and ``-`` as display name for the name itself (Sphinx's ``sphinx.util.inventory``).
"""

from __future__ import annotations

import zlib
from pathlib import Path
from typing import NamedTuple

HERE = Path(__file__).resolve().parent


class Project(NamedTuple):
    title: str
    base_url: str  # what conf.py's intersphinx_mapping gives as the target
    # (name, domain:role, uri relative to base_url)
    objects: tuple[tuple[str, str, str], ...]


def _generated(prefix: str, *names_roles: tuple[str, str]) -> tuple[tuple[str, str, str], ...]:
    """Objects documented one per page, ``<prefix><name>.html#<name>`` (autosummary's
    ``generated`` pages, as NumPy, SciPy, xarray and matplotlib build theirs)."""
    return tuple((name, role, f"{prefix}{name}.html#$") for name, role in names_roles)


_PYTHON = (
    ("None", "py:data", "library/constants.html#$"),
    ("True", "py:data", "library/constants.html#$"),
    ("False", "py:data", "library/constants.html#$"),
    ("bltin-boolean-values", "std:label", "library/stdtypes.html#$"),
    ("bool", "py:class", "library/functions.html#$"),
    ("int", "py:class", "library/functions.html#$"),
    ("float", "py:class", "library/functions.html#$"),
    ("str", "py:class", "library/stdtypes.html#$"),
    ("list", "py:class", "library/stdtypes.html#$"),
    ("tuple", "py:class", "library/stdtypes.html#$"),
    ("dict", "py:class", "library/stdtypes.html#$"),
    ("callable", "py:function", "library/functions.html#$"),
    ("pathlib.Path", "py:class", "library/pathlib.html#$"),
    ("iterable", "std:term", "glossary.html#term-iterable"),
    ("sequence", "std:term", "glossary.html#term-sequence"),
    ("mapping", "std:term", "glossary.html#term-mapping"),
)
_NUMPY = (
    *_generated(
        "reference/generated/",
        ("numpy.ndarray", "py:class"),
        ("numpy.record", "py:class"),
        ("numpy.dtype", "py:class"),
        ("numpy.linspace", "py:function"),
    ),
    ("numpy.inf", "py:data", "reference/constants.html#$"),
    ("numpy.nan", "py:data", "reference/constants.html#$"),
    ("array_like", "std:term", "glossary.html#term-array_like"),
)
_SCIPY = _generated(
    "generated/",
    ("scipy.optimize.least_squares", "py:function"),
    ("scipy.integrate.solve_ivp", "py:function"),
    ("scipy.integrate.DOP853", "py:class"),
    ("scipy.integrate.Radau", "py:class"),
    ("scipy.integrate.quad", "py:function"),
)
_XARRAY = _generated(
    "generated/",
    ("xarray.Dataset", "py:class"),
    ("xarray.DataArray", "py:class"),
    ("xarray.open_dataset", "py:function"),
    ("xarray.open_zarr", "py:function"),
    ("xarray.Dataset.to_netcdf", "py:method"),
)
_MATPLOTLIB = _generated(
    "api/_as_gen/",
    ("matplotlib.figure.Figure", "py:class"),
    ("matplotlib.figure.Figure.savefig", "py:method"),
    ("matplotlib.axes.Axes", "py:class"),
)
PROJECTS: dict[str, Project] = {
    "python": Project("Python", "https://docs.python.org/3/", _PYTHON),
    "numpy": Project("NumPy", "https://numpy.org/doc/stable/", _NUMPY),
    "scipy": Project("SciPy", "https://docs.scipy.org/doc/scipy/reference/", _SCIPY),
    "xarray": Project("xarray", "https://docs.xarray.dev/en/stable/", _XARRAY),
    "matplotlib": Project("Matplotlib", "https://matplotlib.org/stable/", _MATPLOTLIB),
}


def inventory(project: Project) -> bytes:
    """The ``objects.inv`` of ``project``: header, then the zlib-compressed lines."""
    header = (
        "# Sphinx inventory version 2\n"
        f"# Project: {project.title}\n"
        "# Version: stable\n"
        "# The remainder of this file is compressed using zlib.\n"
    )
    lines = "".join(f"{name} {role} 1 {uri} -\n" for name, role, uri in project.objects)
    return header.encode() + zlib.compress(lines.encode(), 9)


def main() -> None:
    for key, project in PROJECTS.items():
        path = HERE / f"{key}.inv"
        data = inventory(project)
        if not path.exists() or path.read_bytes() != data:
            path.write_bytes(data)
        print(f"{path.name}: {len(project.objects)} names -> {project.base_url}")


if __name__ == "__main__":
    main()
