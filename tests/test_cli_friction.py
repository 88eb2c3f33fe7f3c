"""``celtstone friction`` and the contact options of ``celtstone run``, in-process.

Expected values: the Hertz closed form for u <= 1 worked by hand
(F = (3π/32) u (4 − u²), M = (3π/128)(8 − 8u² + 3u⁴), checked against quadrature in
tests/physics/test_friction_exact.py) and the Padé law of paper eq. (10), (12).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
import xarray as xr

from tests.test_cli import Result


def test_friction_json_keys_and_values() -> None:
    result = Result(["friction", "--law", "exact", "--u", "0.1,0.5,1,2", "--json"])
    assert result.status == 0, result.err
    value = result.json()
    assert set(value) == {"law", "pressure", "u", "force", "moment"}
    assert value["u"] == [0.1, 0.5, 1.0, 2.0]
    assert (value["law"], value["pressure"]) == ("exact", "hertz")
    for u, force, moment in zip(value["u"][:3], value["force"], value["moment"], strict=False):
        assert force == pytest.approx(3 * math.pi / 32 * u * (4 - u * u), rel=1e-14)
        assert moment == pytest.approx(3 * math.pi / 128 * (8 - 8 * u * u + 3 * u**4), rel=1e-14)


def test_friction_pade_uniform() -> None:
    """Uniform-pressure Padé law: F = u/(u + 1), M = (2/3)/(1 + 8u/3) (references.md)."""
    result = Result(["friction", "--law", "pade", "--pressure", "uniform", "--u", "0,2", "--json"])
    value = result.json()
    assert value["force"] == [0.0, pytest.approx(2 / 3, rel=1e-15)]
    assert value["moment"] == [pytest.approx(2 / 3), pytest.approx((2 / 3) / (1 + 16 / 3))]


def test_friction_text_output() -> None:
    result = Result(["friction", "--law", "pade", "--u", "0"])
    assert result.status == 0
    assert "pade law, hertz pressure" in result.out
    assert f"{3 * math.pi / 16:.10f}" in result.out


@pytest.mark.parametrize("suffix", [".png", ".svg"])
def test_friction_plot(tmp_path: Path, suffix: str) -> None:
    target = tmp_path / f"laws{suffix}"
    result = Result(["friction", "--plot", str(target)])
    assert result.status == 0, result.err
    data = target.read_bytes()
    assert data.startswith(b"\x89PNG") if suffix == ".png" else b"<svg" in data[:1000]
    if suffix == ".svg":  # axis labels in the drawing
        assert b"slip ratio" in data and b"pivoting moment" in data
    assert list(tmp_path.iterdir()) == [target]  # no temporary left behind


@pytest.mark.parametrize(
    "argv, words",
    [
        (["friction", "--law", "exakt"], ["friction_law", "exact"]),
        (["friction", "--pressure", "flat"], ["contact_pressure", "hertz"]),
        (["friction", "--u", "0.1,-1"], ["u", ">= 0"]),
        (["friction", "--u", "a"], ["u"]),
        (["friction", "--plot", "laws.gif"], ["plot", ".png"]),
        (["run", "--model", "sliding", "--friction-law", "zhuravlev"], ["friction_law"]),
        (["run", "--model", "sliding", "--contact-pressure", "x"], ["contact_pressure"]),
        (["run", "--model", "sliding", "--elastic-modulus", "0", "--poisson-ratio", "0.3"],
         ["elastic_modulus", "> 0"]),
        (["run", "--model", "sliding", "--elastic-modulus", "1e9", "--poisson-ratio", "0.6"],
         ["poisson_ratio", "(-1, 0.5)"]),
        (["run", "--model", "sliding", "--elastic-modulus", "1e9"], ["poisson_ratio"]),
    ],
)  # fmt: skip
def test_bad_input_is_one_line(argv: list[str], words: list[str]) -> None:
    result = Result(argv)
    assert result.status == 2
    assert result.out == ""
    assert result.err.count("\n") == 1 and result.err.startswith("celtstone: error:")
    for word in words:
        assert word in result.err


def test_non_convex_body_file_is_one_line(tmp_path: Path) -> None:
    """A paraboloid cap with a negative radius of curvature (a saddle) is refused."""
    body = tmp_path / "saddle.toml"
    body.write_text(
        'title = "saddle"\n[body]\nmass = 1.0\n'
        "inertia = [[2.0e-4, 0.0, 0.0], [0.0, 1.6e-3, 0.0], [0.0, 0.0, 1.7e-3]]\n"
        '[shape]\nkind = "paraboloid"\nradii_of_curvature = [2.0, -0.045]\ncom_height = 0.01\n'
    )
    result = Result(
        ["run", "--body", str(body), "--model", "sliding", "--elastic-modulus", "1e9",
         "--poisson-ratio", "0.3"]
    )  # fmt: skip
    assert result.status == 2
    assert result.err.count("\n") == 1 and "radii_of_curvature" in result.err


def test_run_contact_options_reach_json_and_netcdf(tmp_path: Path) -> None:
    target = tmp_path / "run.nc"
    argv = [
        "run", "--model", "sliding", "--friction-law", "exact", "--contact-pressure", "uniform",
        "--elastic-modulus", "3e9", "--poisson-ratio", "0.35", "--friction-load", "dynamic",
        "--t-end", "0.5", "--rtol", "1e-8", "--json", "--out", str(target),
    ]  # fmt: skip
    result = Result(argv)
    assert result.status == 0, result.err
    summary = result.json()
    expected = {
        "friction_law": "exact",
        "contact_pressure": "uniform",
        "contact_radius_model": "hertz",
        "elastic_modulus": 3e9,
        "poisson_ratio": 0.35,
        "friction_load": "dynamic",
    }
    assert {k: summary[k] for k in expected} == expected
    # E* = E / (2 (1 − ν²)) for body and plane of one material
    assert summary["effective_modulus"] == pytest.approx(3e9 / (2 * (1 - 0.35**2)), rel=1e-15)
    with xr.open_dataset(target) as dataset:
        attrs = dict(dataset.attrs)
    assert {k: attrs[k] for k in expected} == expected


def test_run_defaults_record_the_pade_law_and_no_elastic_constants() -> None:
    result = Result(["run", "--model", "sliding", "--t-end", "0.2", "--json"])
    summary = result.json()
    assert summary["friction_law"] == "pade"
    assert summary["contact_pressure"] == "hertz"
    assert summary["contact_radius_model"] == "fixed"
    assert summary["elastic_modulus"] is None and summary["poisson_ratio"] is None
    assert json.loads(result.out) == summary
